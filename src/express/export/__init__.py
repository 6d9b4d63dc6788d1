"""Exporters: turn an :class:`~express.assembly.equations.EquationsOfMotion` into text.

Every exporter is a pure function ``EquationsOfMotion -> str``; writing the file is the
caller's job. The same record always gives the same string.

======== ====================================== ==========
format   function                               suffix
======== ====================================== ==========
json     :func:`~.json_export.to_json`          ``.json``
matlab   :func:`~.matlab.to_matlab`             ``.m``
python   :func:`~.python_module.to_python`      ``.py``
latex    :func:`~.latex.to_latex`               ``.tex``
text     :func:`~.text.to_text`                 ``.txt``
======== ====================================== ==========

Modules: :mod:`.json_export` owns the JSON contract and the matrix order/shape checks
shared by all exporters; :mod:`.matlab` the MATLAB/Octave function file and the
safe-local-name rules; :mod:`.python_module` the numpy module; :mod:`.assignments` the
non-zero assignments and entry printing those two share; :mod:`.latex` the LaTeX
fragment and name typesetting; :mod:`.text` the terminal view.

A MATLAB function file must be saved as ``<function name>.m``; :func:`to_matlab` takes
the function name as an optional second argument (``eom.name`` by default).
"""

from __future__ import annotations

from collections.abc import Callable

from express.assembly.equations import EquationsOfMotion
from express.export.json_export import to_json
from express.export.latex import to_latex
from express.export.matlab import to_matlab
from express.export.python_module import to_python
from express.export.text import to_text

__all__ = ["FORMATS", "SUFFIXES", "default_suffix", "to_json", "to_latex", "to_matlab",
           "to_python", "to_text"]

#: Exporter by format name.
FORMATS: dict[str, Callable[[EquationsOfMotion], str]] = {
    "json": to_json,
    "matlab": to_matlab,
    "python": to_python,
    "latex": to_latex,
    "text": to_text,
}

#: File suffix by format name.
SUFFIXES: dict[str, str] = {
    "json": ".json",
    "matlab": ".m",
    "python": ".py",
    "latex": ".tex",
    "text": ".txt",
}


def default_suffix(fmt: str) -> str:
    """Return the usual file suffix of an export format.

    Parameters
    ----------
    fmt : str
        A key of :data:`FORMATS`.

    Returns
    -------
    str
        The suffix with its dot, e.g. ``".m"``.

    Raises
    ------
    ValueError
        If ``fmt`` is not a known format.
    """
    try:
        return SUFFIXES[fmt]
    except KeyError:
        raise ValueError(
            f"unknown export format {fmt!r}; choose one of {', '.join(FORMATS)}"
        ) from None
