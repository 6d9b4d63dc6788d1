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

import os
import warnings
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from express.io.cache import cache_enabled, entry_damaged, entry_key, read_entry, write_entry
from express.numeric.program import ProgramError, checked_list, checked_strings
from express.numeric.warm import file_digest, read_warning_items, repeat_warnings, unchanged, warning_items

__all__ = ["RenderedExport", "rendered_export"]

_KIND = "export text"


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
    key = _key(path, options) if cache_enabled() else None
    if key is None:
        return render()
    found = _read(key, str(path))
    if found is not None:
        return found
    from express.base.reads import recorded_reads

    with recorded_reads() as reads, warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = render()
    for warning in caught:
        warnings.warn_explicit(warning.message, warning.category, warning.filename, warning.lineno, source=warning.source)
    items = warning_items(caught)
    if items is not None and reads:
        write_entry(key, {
            "name": f"{result.name} ({options.get('format', 'export')})", "kind": _KIND, "reads": [list(read) for read in reads],
            "source": str(path), "warnings": items, "text": result.text, "dofs": result.dofs,
            "notices": list(result.notices),
        })
    return result


def _key(path: str | Path, options: dict[str, Any]) -> str | None:
    digest = file_digest(os.fspath(path))
    if digest is None:  # a pipe or an unreadable file: read once, by the model reader
        return None
    return entry_key(_KIND, [(os.path.abspath(path), digest)], options)


def _read(key: str, source: str) -> RenderedExport | None:
    """The entry's export with its warnings given again; None when there is none, a file
    it lists changed (rebuilt), or it is damaged (one warning, rebuilt)."""
    payload = read_entry(key)
    if payload is None:
        return None
    try:
        if not isinstance(payload, dict) or payload.get("kind") != _KIND:
            raise ProgramError("not an export entry")
        reads = [(r[0], r[1]) for r in checked_list(payload.get("reads")) if len(checked_strings(r)) == 2]
        if not reads or len(reads) != len(payload["reads"]):
            raise ProgramError("bad reads")
        messages = read_warning_items(payload.get("warnings"))
        text, dofs, recorded = payload.get("text"), payload.get("dofs"), payload.get("source")
        name = payload.get("name")
        if not (isinstance(text, str) and type(dofs) is int and dofs >= 0 and isinstance(recorded, str)
                and isinstance(name, str)):
            raise ProgramError("bad export")
        notices = checked_strings(payload.get("notices"))
    except ProgramError:
        entry_damaged(key)
        return None
    if not unchanged(reads):
        return None
    repeat_warnings(messages, recorded, source)
    return RenderedExport(text, dofs, tuple(notices), name)
