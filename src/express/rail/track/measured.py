"""A measured track: one CSV file with the distance and the four EN 13848 components.

The file (``docs/track.md``, "Measured track files") has a header line naming its
columns with their units in brackets, in any order::

    distance [m], alignment [mm], vertical [mm], cross_level [mm], gauge [mm]

and one row per measured point. Every column must be there (a missing one is an error
naming it, not a zero), the units are lengths (:func:`express.base.units.parse_quantity`),
the distances increase strictly, and each component becomes a
:class:`~express.rail.track.irregularity.ProfileIrregularity` (linear between the points,
end values held; ``|value|`` at most 0.1 m). Bad rows are reported as the two-column
profiles' are (:mod:`express.rail.track.reader`): by line, the first quoted briefly.
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np

from express.base.diagnostics import ModelError, Problem
from express.base.units import UnitError, parse_quantity
from express.rail.track.irregularity import ProfileIrregularity
from express.rail.track.textfiles import MAX_PROFILE_BYTES, MAX_ROW_PROBLEMS, excerpt, read_text_file

__all__ = ["MEASURED_COLUMNS", "read_measured_csv"]

#: The columns of a measured track file, each with a unit in brackets.
MEASURED_COLUMNS = ("distance", "alignment", "vertical", "cross_level", "gauge")
_HEADER_CELL = re.compile(r"\s*(?P<name>[A-Za-z_ ]+?)\s*\[(?P<unit>[^\]]+)\]\s*\Z")
_SPLIT = re.compile(r"[,;\t]+")


def _header(line: str, source: str, lineno: int, item: str) -> tuple[list[int], list[float], list[Problem]]:
    """Column index and unit factor of each of :data:`MEASURED_COLUMNS`, or problems."""
    problems: list[Problem] = []
    found: dict[str, tuple[int, float]] = {}
    for index, cell in enumerate(_SPLIT.split(line.strip())):
        match = _HEADER_CELL.match(cell)
        if match is None:
            problems.append(Problem(source, lineno, item, f"header cell {cell.strip()[:40]!r} is not 'name [unit]' "
                                                          f"(columns: {', '.join(MEASURED_COLUMNS)})"))
            continue
        name = match["name"].strip().lower().replace(" ", "_")
        if name not in MEASURED_COLUMNS:
            problems.append(Problem(source, lineno, item, f"unknown column {name!r} (columns: "
                                                          f"{', '.join(MEASURED_COLUMNS)})"))
            continue
        try:
            factor = parse_quantity(f"1 {match['unit'].strip()}", dimension="length")[0]
        except UnitError as exc:
            problems.append(Problem(source, lineno, item, f"column {name!r}: {exc}"))
            continue
        if name in found:
            problems.append(Problem(source, lineno, item, f"column {name!r} given twice"))
            continue
        found[name] = (index, factor)
    missing = [name for name in MEASURED_COLUMNS if name not in found]
    if missing and not problems:
        problems.append(Problem(source, lineno, item, f"missing column{'s' if len(missing) > 1 else ''} "
                                                      f"{', '.join(missing)} (every one of "
                                                      f"{', '.join(MEASURED_COLUMNS)} is needed, with its unit)"))
    if problems:
        return [], [], problems
    return [found[name][0] for name in MEASURED_COLUMNS], [found[name][1] for name in MEASURED_COLUMNS], []


def read_measured_csv(path: str | Path, *, item: str = "measured") -> dict[str, ProfileIrregularity]:
    """The four components of a measured track file, by name (``alignment``, ``vertical``,
    ``cross_level``, ``gauge``), in metres.

    Raises
    ------
    ModelError
        Every problem, ``<file>:<line>: <item>: <what is wrong>`` (the header's, or the
        first :data:`~express.rail.track.reader.MAX_ROW_PROBLEMS` bad rows and a count).
    """
    path = Path(path)
    source = str(path)
    text = read_text_file(path, MAX_PROFILE_BYTES, item, "utf-8-sig")
    columns: list[int] | None = None
    factors: list[float] = []
    rows: list[list[float]] = []
    problems: list[Problem] = []
    bad = 0
    previous: tuple[int, float] | None = None
    for lineno, raw in enumerate(text.splitlines(), 1):
        line = raw.strip()
        if not line or line.startswith("#"):
            continue
        if columns is None:
            columns, factors, problems = _header(line, source, lineno, item)
            if problems:
                raise ModelError(problems)
            continue
        cells = [cell.strip() for cell in _SPLIT.split(line)]
        message = None
        values: list[float] = []
        if len(cells) != len(MEASURED_COLUMNS):
            message = f"expected {len(MEASURED_COLUMNS)} columns ({', '.join(MEASURED_COLUMNS)}), got {len(cells)}"
        else:
            try:
                values = [float(cells[i]) * f for i, f in zip(columns, factors, strict=True)]
            except ValueError:
                message = "not a number"
        if message is None:
            if not all(math.isfinite(x) for x in values):
                message = "values must be finite"
            elif previous is not None and values[0] <= previous[1]:
                message = f"distance {values[0]:g} m is not greater than {previous[1]:g} m on line {previous[0]}"
        if message is None:
            rows.append(values)
            previous = (lineno, values[0])
            continue
        bad += 1
        if bad == 1:
            message = f"{message}: {excerpt(line)}"
        if bad <= MAX_ROW_PROBLEMS:
            problems.append(Problem(source, lineno, item, message))
    if bad > MAX_ROW_PROBLEMS:
        problems.append(Problem(source, None, item, f"{bad} bad rows in all, the first {MAX_ROW_PROBLEMS} listed"))
    if columns is None:
        problems.append(Problem(source, None, item, f"no header line ({', '.join(f'{c} [unit]' for c in MEASURED_COLUMNS)})"))
    elif not problems and len(rows) < 2:
        problems.append(Problem(source, None, item, f"need at least two data rows, found {len(rows)}"))
    if problems:
        raise ModelError(problems)
    table = np.array(rows)
    distance = table[:, 0]
    out = {}
    for j, name in enumerate(MEASURED_COLUMNS[1:], 1):
        for _, message in ProfileIrregularity.field_problems(distance, table[:, j]):
            problems.append(Problem(source, None, item, f"{name}: {message.replace('yr', name)}"))
        out[name] = table[:, j]
    if problems:
        raise ModelError(problems)
    return {name: ProfileIrregularity(distance, values, source=f"{source} ({name})") for name, values in out.items()}
