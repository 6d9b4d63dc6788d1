"""Modal data of a flexible body from a file (e.g. exported from a finite-element model).

The format (``docs/model-format.md``, "Modal data files") is a CSV table, one row per
mode, a header row and a units row; ``#`` lines are comments::

    # coach car body, free-free modes from the FE model
    mode, kind,     frequency, damping, modal_mass, P1,     P2,     floor_centre
    unit, ,         Hz,        -,       kg,         -,      -,      -
    vb1,  vertical, 8.9,       0.02,    21050,      1.000,  -0.612, -0.971
    to1,  torsion,  11.3,      0.02,    3200,       0.25,   -0.25,  0.0

* ``kind``: ``vertical`` (z), ``lateral`` (y) or ``torsion`` (about x);
* ``frequency`` in a frequency unit (``Hz``, ``rad/s``), positive;
* ``damping``: modal damping ratio [-] (an empty cell: the body's ``damping``);
* the shape columns, one per point (a CP id or an output name): either **mass-normalised**
  (unit ``1/sqrt(kg)``, no ``modal_mass`` column, or a modal mass of 1 kg), or **scaled
  any way** (unit ``-``: metres per metre of modal amplitude for bending, radians per
  metre for torsion) with the mode's ``modal_mass`` (the generalised mass
  ``phi^T M phi`` in a mass unit, ``kg`` or ``t``), by which the reader divides:
  ``phi / sqrt(modal_mass)``.  An empty cell is a shape not given (an error where the
  model uses the point).

Every problem is reported with the file and its line; nothing is evaluated.
"""

from __future__ import annotations

import csv
import io
import math
from dataclasses import dataclass
from fractions import Fraction
from pathlib import Path

from express.base.diagnostics import ModelError, Problem
from express.base.limits import read_input_text
from express.base.units import Dimension, UnitError, is_angular_frequency, unit_dimension, unit_factor
from express.model.modal_body import ModeKind

__all__ = ["ModeData", "read_modal_data"]

_FIXED = ("mode", "kind", "frequency", "damping", "modal_mass")
_MASS = Dimension(Fraction(1), Fraction(0), Fraction(0))
_FREQUENCY = Dimension(Fraction(0), Fraction(0), Fraction(-1))
_NORMALISED = ("1/sqrt(kg)", "kg^-0.5", "1/kg^0.5")


@dataclass(frozen=True)
class ModeData:
    """One mode read from a file: name, kind, ``omega`` [rad/s], ``zeta`` (None: the body's),
    mass-normalised ``shapes`` by point, ``order`` among its kind, ``line`` in the file."""

    name: str
    kind: ModeKind
    omega: float
    zeta: float | None
    shapes: dict[str, float]
    order: int
    line: int


def _rows(text: str) -> list[tuple[int, list[str]]]:
    """The non-comment, non-blank rows with their line numbers, cells stripped."""
    rows = []
    for number, line in enumerate(text.splitlines(), start=1):
        if not line.strip() or line.lstrip().startswith("#"):
            continue
        cells = next(csv.reader(io.StringIO(line)))
        rows.append((number, [cell.strip() for cell in cells]))
    return rows


def _number(text: str) -> float | None:
    try:
        value = float(text)
    except ValueError:
        return None
    return value if math.isfinite(value) else None


def read_modal_data(path: str | Path, problems: list[Problem]) -> list[ModeData]:
    """The modes of a modal data file (see the module); problems are appended to
    ``problems`` with this file's name and lines.

    Parameters
    ----------
    path : str or pathlib.Path
        The CSV file.
    problems : list of Problem
        Where to report.

    Returns
    -------
    list of ModeData
        The modes read without a problem.
    """
    source = str(path)
    try:
        text = read_input_text(path, "modal data")
    except ModelError as error:
        problems.extend(error.problems)
        return []
    rows = _rows(text)
    if len(rows) < 2:
        problems.append(Problem(source, None, "modal data", "needs a header row and a units row"))
        return []
    (header_line, header), (unit_line, units) = rows[0], rows[1]
    found: list[Problem] = []
    if header[:3] != ["mode", "kind", "frequency"] or (units[:1] != ["unit"]):
        found.append(Problem(source, header_line, "modal data",
                             'the header starts "mode, kind, frequency" and the next row "unit, ..."'))
        problems.extend(found)
        return []
    units = units + [""] * (len(header) - len(units))
    column = {name: i for i, name in enumerate(header)}
    points = [name for name in header if name not in _FIXED]
    try:
        frequency_factor = unit_factor(units[column["frequency"]] or "Hz")
        if is_angular_frequency(units[column["frequency"]] or "Hz"):
            frequency_factor /= 2 * math.pi  # rad/s, rpm: to Hz
        if unit_dimension(units[column["frequency"]] or "Hz") != _FREQUENCY:
            raise UnitError(f"unit {units[column['frequency']]} is not a frequency")
    except UnitError as error:
        found.append(Problem(source, unit_line, "modal data frequency", str(error)))
        frequency_factor = math.nan
    mass_factor = 1.0
    if "modal_mass" in column:
        unit = units[column["modal_mass"]]
        try:
            if unit_dimension(unit) != _MASS:
                raise UnitError(f"unit {unit or '(none)'} is not a mass (kg, t)")
            mass_factor = unit_factor(unit)
        except UnitError as error:
            found.append(Problem(source, unit_line, "modal data modal_mass", str(error)))
    shape_units = {units[column[p]] for p in points}
    normalised = shape_units <= set(_NORMALISED)
    if not normalised and shape_units - {"-", "1", ""}:
        found.append(Problem(source, unit_line, "modal data shapes",
                             f"shape units must all be 1/sqrt(kg) (mass-normalised) or - (with modal_mass), "
                             f"got {', '.join(sorted(shape_units))}"))
    elif not normalised and "modal_mass" not in column:
        found.append(Problem(source, unit_line, "modal data shapes",
                             "shapes of unit - need a modal_mass column (or give them in 1/sqrt(kg))"))
    if found:
        problems.extend(found)
        return []
    return _modes(source, rows[2:], header, column, points, frequency_factor, mass_factor, normalised, problems)


def _modes(source: str, rows: list[tuple[int, list[str]]], header: list[str], column: dict[str, int],
           points: list[str], frequency_factor: float, mass_factor: float, normalised: bool,
           problems: list[Problem]) -> list[ModeData]:
    """The mode rows of a modal data file whose header and units are valid."""
    modes: list[ModeData] = []
    counts: dict[ModeKind, int] = {}
    for line, cells in rows:
        cells = cells + [""] * (len(header) - len(cells))
        name = cells[0]
        item = f"modal data mode {name}"
        if len(cells) > len(header):
            problems.append(Problem(source, line, item, f"{len(cells)} cells, the header has {len(header)}"))
            continue
        try:
            kind = ModeKind(cells[1])
        except ValueError:
            problems.append(Problem(source, line, item, f"kind must be vertical, lateral or torsion, got {cells[1]!r}"))
            continue
        frequency = _number(cells[2])
        if frequency is None or not frequency > 0:
            problems.append(Problem(source, line, item, f"frequency must be a positive number, got {cells[2]!r}"))
            continue
        zeta = None
        if "damping" in column and cells[column["damping"]]:
            zeta = _number(cells[column["damping"]])
            if zeta is None or not zeta >= 0:
                problems.append(Problem(source, line, item, f"damping must be >= 0, got {cells[column['damping']]!r}"))
                continue
        scale = 1.0
        if "modal_mass" in column:
            mass = _number(cells[column["modal_mass"]])
            if mass is None or not mass > 0:
                problems.append(Problem(source, line, item,
                                        f"modal_mass must be a positive number, got {cells[column['modal_mass']]!r}"))
                continue
            if normalised and abs(mass * mass_factor - 1.0) > 1e-9:
                problems.append(Problem(source, line, item, "mass-normalised shapes need a modal mass of 1 kg"))
                continue
            scale = 1.0 / math.sqrt(mass * mass_factor)
        shapes: dict[str, float] = {}
        bad = False
        for point in points:
            cell = cells[column[point]]
            if not cell:
                continue
            value = _number(cell)
            if value is None:
                problems.append(Problem(source, line, item, f"shape at {point} is not a number: {cell!r}"))
                bad = True
                continue
            shapes[point] = value * scale
        if bad:
            continue
        counts[kind] = counts.get(kind, 0) + 1
        modes.append(ModeData(name, kind, 2 * math.pi * frequency * frequency_factor, zeta, shapes, counts[kind], line))
    return modes
