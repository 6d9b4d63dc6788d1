"""Exports of a model's equations kept as text in the derivation cache.

``express generate`` writes the readable matrices in one of five formats.  For a long
train the readable generation is cached (:mod:`express.numeric.generation`), but reading
the model file into SymPy records and rebuilding the SymPy matrices from the entry's
programs still cost seconds (a 100-car train: 13.5 s and 4.7 s), more than the export
itself.  So a finished export is stored too, as its text, and a second ``generate`` of
unchanged files with the same options copies it without reading the model or importing
SymPy (``docs/cache.md``).

The entry is found by the model file's bytes and the options (format, the MATLAB
function's name, ``--keep-virtual``, ``--no-rail``) and used only while every file the
first run read still has its recorded SHA-256 (as the warm vehicle entry,
:mod:`express.numeric.warm`).  The text is data: it is written out, never run.  A run
with ``--set`` overrides does not use it (the values are part of the text).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from express.numeric.products import cached_product
from express.numeric.program import ProgramError, checked_strings

__all__ = ["RenderedExport", "rendered_export"]


@dataclass(frozen=True)
class RenderedExport:
    """An export's text and what the command reports with it.

    Attributes
    ----------
    text : str
        The file's contents.
    dofs : int
        Number of coordinates of the equations.
    notices : tuple of str
        The generator's notices (a DOF without mass, ...), as printed.
    name : str
        The model's name (``express cache info`` lists the entry under it).
    """

    text: str
    dofs: int
    notices: tuple[str, ...]
    name: str


def rendered_export(path: str | Path, options: dict[str, Any], render: Callable[[], RenderedExport]) -> RenderedExport:
    """The export of ``path`` under ``options``: from the cache, or ``render()`` stored.

    Parameters
    ----------
    path : str or Path
        The model file, as the command was given it (warnings name it so).
    options : dict
        Everything besides the files that shapes the text (JSON-able): the format, the
        function name, ``keep_virtual``, ``with_rail``.
    render : callable
        Builds the export (reads the model, :func:`express.numeric.generation.load_generation`);
        the warnings it gives are recorded and given again by every later use.

    Returns
    -------
    RenderedExport
        The same text, whether rendered now or read back.
    """
    def encode(export: RenderedExport) -> tuple[str, Any]:
        data = {"text": export.text, "dofs": export.dofs, "notices": list(export.notices), "name": export.name}
        return f"{export.name} ({options.get('format', 'export')})", data

    return cached_product(path, "export text", options, render, encode, _decode)


def _decode(data: Any) -> RenderedExport:
    if not isinstance(data, dict):
        raise ProgramError("bad export")
    text, dofs, name = data.get("text"), data.get("dofs"), data.get("name")
    if not (isinstance(text, str) and type(dofs) is int and dofs >= 0 and isinstance(name, str)):
        raise ProgramError("bad export")
    return RenderedExport(text, dofs, tuple(checked_strings(data.get("notices"))), name)
