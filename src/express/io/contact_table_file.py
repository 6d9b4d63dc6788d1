"""Contact geometry tables from a file (as other programs export them): what a
``conicity = { from = "table", file = "contact.csv" }`` node reads
(``docs/model-format.md``, "Contact tables from a file").

The format is a CSV table, one row per lateral displacement of the wheelset, a header
row and a units row; ``#`` lines are comments::

    # S1002 on 60E1 at 1:40, gauge 1435 mm, flange back 1360 mm
    y,  r_L,     r_R,     delta_L, delta_R, y_cL,    y_cR,    roll
    mm, mm,      mm,      rad,     rad,     mm,      mm,      rad
    -10, 459.55, 461.00,  0.0171,  0.0600,  762.1,   741.0,   -0.00035
    ...

* ``y``: the wheelset's lateral displacement, positive to the left, strictly increasing,
  the range containing 0;
* ``r_L``, ``r_R``: rolling radii (the contact's depth below the axle);
* ``delta_L``, ``delta_R``: contact angles in the track plane, positive when the wheel
  surface rises toward the field side (both positive at a centred coned wheelset);
* ``y_cL``, ``y_cR``: the contacts' outward distances from the track centre (both
  positive, about 750 mm on standard gauge);
* ``roll``: the wheelset's roll angle, positive lifting the left wheel;
* optional ``kappa_L``, ``kappa_R``: the lateral relative curvature of each contact
  (wheel plus rail profile curvature, ``1/m``), for the Hertz ellipse.  Without them the
  contact is taken as circular (lateral relative curvature equal to the rolling one,
  ``cos(delta) / r``).

Lengths in a length unit (``mm``, ``m``), angles in an angle unit (``rad``, ``mrad``,
``deg``), curvatures in ``1/m`` (or ``1/mm``).  Every problem is reported with the file and
its line, all at once; nothing is evaluated (cells are plain numbers).
"""

from __future__ import annotations

import csv
import io
import math
from dataclasses import dataclass
from itertools import pairwise
from pathlib import Path

import numpy as np

from express.base.diagnostics import ModelError, Problem
from express.base.limits import read_input_text
from express.base.units import UnitError, describe_dimension, dimension, unit_dimension, unit_factor

__all__ = ["COLUMNS", "OPTIONAL", "ContactTableData", "read_contact_table", "write_contact_table"]

#: Required columns and their dimension.
COLUMNS = (("y", "length"), ("r_L", "length"), ("r_R", "length"), ("delta_L", "angle"), ("delta_R", "angle"),
           ("y_cL", "length"), ("y_cR", "length"), ("roll", "angle"))
#: Optional columns and their dimension.
OPTIONAL = (("kappa_L", "curvature"), ("kappa_R", "curvature"))
_DIMENSIONS = {"length": dimension("length"), "angle": dimension("dimensionless"),
               "curvature": unit_dimension("1/m")}
_ITEM = "contact table"


@dataclass(frozen=True, eq=False)
class ContactTableData:
    """A contact table read from a file, SI.

    Attributes
    ----------
    source : str
        The file.
    columns : dict of str to numpy.ndarray, shape (n,)
        Every column given, by name, SI (m, rad, 1/m).
    """

    source: str
    columns: dict


def _rows(text: str) -> list[tuple[int, list[str]]]:
    rows = []
    for number, line in enumerate(text.splitlines(), start=1):
        if not line.strip() or line.lstrip().startswith("#"):
            continue
        rows.append((number, [cell.strip() for cell in next(csv.reader(io.StringIO(line)))]))
    return rows


def _factors(source: str, line: int, header: list[str], units: list[str], problems: list[Problem]) -> dict[str, float]:
    known = dict(COLUMNS + OPTIONAL)
    factors = {}
    for name in dict.fromkeys(header):
        if name not in known:
            problems.append(Problem(source, line - 1, _ITEM, f"unknown column {name!r} (known: {', '.join(known)})"))
            continue
        if header.count(name) > 1:
            problems.append(Problem(source, line - 1, _ITEM, f"column {name!r} given twice"))
        unit = units[header.index(name)] if header.index(name) < len(units) else ""
        wanted = known[name]
        try:
            if not unit:
                raise UnitError("no unit")
            if unit_dimension(unit) != _DIMENSIONS[wanted]:
                raise UnitError(f"{unit!r} is not a {describe_dimension(_DIMENSIONS[wanted])}")
            factors[name] = unit_factor(unit)
        except UnitError as error:
            problems.append(Problem(source, line, _ITEM, f"column {name}: unit {unit!r}: {error}"))
            factors[name] = math.nan  # its cells are still checked
    for name, _ in COLUMNS:
        if name not in header:
            problems.append(Problem(source, line - 1, _ITEM, f'missing column "{name}"'))
    if ("kappa_L" in header) != ("kappa_R" in header):
        problems.append(Problem(source, line - 1, _ITEM, "kappa_L and kappa_R go together"))
    return factors


def read_contact_table(path: str | Path) -> ContactTableData:
    """Read a contact table file (the format of this module's docstring).

    Raises
    ------
    ModelError
        Listing every problem with the file and line: a missing or unknown column, a unit
        of the wrong dimension, a cell that is not a finite number, ``y`` not strictly
        increasing or not spanning 0, a radius that is not positive.
    """
    source = str(path)
    text = read_input_text(path, _ITEM, "the contact table")
    rows = _rows(text)
    problems: list[Problem] = []
    if len(rows) < 4:
        raise ModelError([Problem(source, None, _ITEM, "needs a header row, a units row and at least two data rows")])
    (_, header), (unit_line, units) = rows[0], rows[1]
    factors = _factors(source, unit_line, header, units, problems)
    values: dict[str, list[float]] = {name: [] for name in factors}
    lines = []
    for number, cells in rows[2:]:
        if len(cells) != len(header):
            problems.append(Problem(source, number, _ITEM, f"{len(cells)} cells, the header has {len(header)}"))
            continue
        lines.append(number)
        for name, factor in factors.items():
            cell = cells[header.index(name)]
            try:
                value = float(cell)
                if not math.isfinite(value):
                    raise ValueError
            except ValueError:
                problems.append(Problem(source, number, _ITEM, f"{name}: {cell!r} is not a finite number"))
                value = math.nan
            values[name].append(value * factor)
    if "y" in values and all(math.isfinite(value) for value in values["y"]) and len(values["y"]) >= 2:
        _check_grid(source, lines, values, problems)
    if problems:
        raise ModelError(sorted(problems, key=lambda problem: problem.line or 0))
    return ContactTableData(source, {name: np.array(column) for name, column in values.items()})


def _check_grid(source: str, lines: list[int], values: dict[str, list[float]], problems: list[Problem]) -> None:
    y = values["y"]
    for k in range(1, len(y)):
        if not y[k] > y[k - 1]:
            problems.append(Problem(source, lines[k], _ITEM, f"y must increase strictly: {y[k] * 1e3:g} mm after "
                                                              f"{y[k - 1] * 1e3:g} mm"))
    if all(b > a for a, b in pairwise(y)) and not y[0] <= 0.0 <= y[-1]:
        problems.append(Problem(source, lines[0], _ITEM, f"y must span 0 (found {y[0] * 1e3:g} .. {y[-1] * 1e3:g} mm)"))
    for name in ("r_L", "r_R", "y_cL", "y_cR"):
        for k, value in enumerate(values.get(name, [])):
            if math.isfinite(value) and not value > 0:
                problems.append(Problem(source, lines[k], _ITEM, f"{name} must be positive, got {value:g} m"))
                break


def write_contact_table(path: str | Path, columns: dict, comment: str = "") -> None:
    """Write ``columns`` (SI arrays by name, the required ones and optionally the
    curvatures) in this module's format: lengths in mm, angles in rad, curvatures in 1/m."""
    names = [name for name, _ in COLUMNS + OPTIONAL if name in columns]
    units = {"length": "mm", "angle": "rad", "curvature": "1/m"}
    kinds = dict(COLUMNS + OPTIONAL)
    scale = {"length": 1e3, "angle": 1.0, "curvature": 1.0}
    lines = [f"# {line}" for line in comment.splitlines()]
    lines += [", ".join(names), ", ".join(units[kinds[name]] for name in names)]
    count = len(columns["y"])
    for k in range(count):
        lines.append(", ".join(f"{columns[name][k] * scale[kinds[name]] + 0.0:.12g}" for name in names))
    Path(path).write_text("\n".join(lines) + "\n", encoding="utf-8")
