"""Modal data of a flexible body from a universal file (UFF/UNV), as FE programs export it.

The universal file format (I-DEAS, now Simcenter; written by NX, Simcenter 3D, FEMAP,
ANSYS and Abaqus export tools, and by test-modal software) carries a model's nodes and
its normal modes as text datasets.  They are read with pyuff (the well-kept reader of the
format, imported here only); this module takes from them:

* dataset **164**, the file's units: its length and force factors (file unit per SI unit),
  from which the mass unit follows (force / (length / s^2));
* dataset **2414** (analysis data at nodes) or **55** (data at nodes), each with the
  analysis type 2 (normal mode): the mode's frequency [Hz], its modal mass, its viscous
  damping ratio and its shape at the nodes, three translations (data characteristic 2)
  or three translations and three rotations (3); complex data are read by their real
  part (a normal mode's imaginary part is zero).

The model names the FE node at every point it uses and the FE axes along the body's x, y,
z (``docs/model-format.md``, "Flexible bodies").  Each FE mode becomes one EXPRESS mode
of one kind: ``vertical`` (the body-z translation at the points), ``lateral`` (body y)
or ``torsion`` (the rotation about body x, which needs rotations in the file).  The kind
is given per mode, or found from the translations at the named nodes (z or y, whichever
carries at least :data:`PURITY` of their squares: a mode that is not mostly one of them
is refused, since a modal body moves each mode in one direction).  Shapes are divided by
the square root of the modal mass and converted to SI: [1/sqrt(kg)] for bending,
[rad/(sqrt(kg) m)] for torsion.  Mass normalisation ``phi^T M phi = 1`` involves lengths
only through the rotational inertias, so a translation's value changes with the mass unit
alone (``phi_SI = phi_file sqrt(file mass per kg)``) and a rotation's with both
(``psi_SI = psi_file sqrt(file mass per kg) x file length per metre``): a point mass of
2 kg has ``phi = 1/sqrt(2)`` in kg-mm as in kg-m.

Every problem is reported with the file (and the dataset's mode number); nothing is
evaluated.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from express.base.diagnostics import Problem
from express.io.modal_data import ModeData
from express.model.modal_body import ModeKind

__all__ = ["PURITY", "FEModeChoice", "read_uff_modes"]

#: The share of the squared translations at the named nodes the dominant direction of an
#: automatically classified mode must carry.
PURITY = 0.9

_PREFIX = {ModeKind.VERTICAL: "vb", ModeKind.LATERAL: "lb", ModeKind.TORSION: "to"}


@dataclass(frozen=True)
class FEModeChoice:
    """One FE mode the model keeps: its ``number`` in the file, the EXPRESS ``name`` and
    ``kind`` (None: found from the shape)."""

    name: str
    number: int
    kind: ModeKind | None = None


@dataclass(frozen=True)
class _FileMode:
    line: int | None  # where its dataset starts
    number: int
    frequency: float  # [Hz]
    modal_mass: float  # file units
    damping: float | None
    shapes: dict[int, np.ndarray]  # node -> (6,) in file units, rotations nan if absent


def _axis(code: str) -> tuple[int, float]:
    """``"x"``, ``"-z"``, ...: the FE component index and sign."""
    sign = -1.0 if code.startswith("-") else 1.0
    return "xyz".index(code.lstrip("+-")), sign


def _units(sets: list[dict[str, Any]]) -> tuple[float, float] | None:
    """(length factor, mass factor): file length per metre, file mass per kg."""
    for data in sets:
        if data.get("type") == 164:
            length, force = float(data["length"]), float(data["force"])
            return length, force / length  # mass = force / (length / s^2)
    return None


def _real(values: Any, complex_data: bool) -> np.ndarray:
    """The real parts of a node's values (complex data interleave real and imaginary)."""
    row = np.asarray(values)
    if np.iscomplexobj(row):
        return np.real(row).astype(float)
    return row[::2].astype(float) if complex_data else row.astype(float)


def _dataset_lines(text: str) -> list[int]:
    """The first line of each dataset 2414 or 55 (a ``-1`` line, the type on the next)."""
    lines, starts, inside = text.splitlines(), [], False
    for number, line in enumerate(lines, start=1):
        if line.strip() == "-1":
            if not inside and number < len(lines) and lines[number].split()[:1] in (["2414"], ["55"]):
                starts.append(number)
            inside = not inside
    return starts


def _file_modes(sets: list[dict[str, Any]], starts: list[int]) -> list[_FileMode]:
    """The normal modes of datasets 2414 and 55, in file order."""
    modes = []
    lines = iter(starts)
    for data in sets:
        kind = data.get("type")
        if kind == 2414 and data.get("analysis_type") == 2:
            complex_data = data.get("data_type") in (5, 6)
            number = int(data.get("record10_field6") or data.get("analysis_dataset_label") or 0)
            values = {int(node): _real(row, complex_data) for node, row in zip(data["node_nums"], data["data_at_node"], strict=True)}
            frequency, mass, zeta = (float(data[f"record12_field{k}"]) for k in (2, 4, 5))
        elif kind == 55 and data.get("analysis_type") == 2:
            number = int(data["mode_n"])
            columns = [np.real(np.asarray(data[f"r{k}"])) for k in range(1, 7) if f"r{k}" in data]
            values = {int(node): np.array([c[i] for c in columns], dtype=float) for i, node in enumerate(data["node_nums"])}
            frequency, mass, zeta = float(data["freq"]), float(data["modal_m"]), float(data["modal_damp_vis"])
        else:
            if data.get("type") in (2414, 55):
                next(lines, None)
            continue
        line = next(lines, None)
        shapes = {node: np.concatenate([row[:6], np.full(6 - min(row.size, 6), math.nan)]) for node, row in values.items()}
        modes.append(_FileMode(line, number, frequency, mass, zeta, shapes))
    return modes


def _read_sets(path: Path, source: str, problems: list[Problem]) -> list[dict[str, Any]] | None:
    try:
        import pyuff
    except ImportError:  # a dependency from Python 3.11 (pyproject.toml)
        problems.append(Problem(source, None, "FE modes", "reading a universal file needs pyuff (Python >= 3.11)"))
        return None
    try:
        sets = pyuff.UFF(str(path)).read_sets()
    except Exception as error:  # pyuff raises what its parser meets; all of it is bad input here
        problems.append(Problem(source, None, "FE modes", f"not a readable universal file: {error}"))
        return None
    return [sets] if isinstance(sets, dict) else list(sets)


def read_uff_modes(path: str | Path, nodes: Mapping[str, int], axes: tuple[str, str, str],
                   choices: list[FEModeChoice] | None, rigid_below: float,
                   problems: list[Problem]) -> list[ModeData]:
    """The modes a model keeps from a universal file.

    Parameters
    ----------
    path : str or pathlib.Path
        The ``.unv``/``.uff`` file.
    nodes : mapping of str to int
        The FE node at each point of the body the model uses (CP or output point).
    axes : tuple of 3 str
        The FE axis along body x, y and z, each ``"x"``, ``"y"``, ``"z"`` with an optional
        ``-`` (e.g. ``("z", "-x", "y")``).
    choices : list of FEModeChoice or None
        The modes kept; None: every mode above ``rigid_below``, named ``vb1``, ``lb1``...
        in order of frequency.
    rigid_below : float
        [Hz] modes below are the free body's rigid motions (left out when ``choices`` is
        None).
    problems : list of Problem
        Where to report, with this file's name.

    Returns
    -------
    list of ModeData
        The modes read without a problem, shapes mass-normalised in SI.
    """
    source = str(path)
    if not Path(path).is_file():
        problems.append(Problem(source, None, "FE modes", "no such file"))
        return []
    sets = _read_sets(Path(path), source, problems)
    if sets is None:
        return []
    units = _units(sets)
    text = Path(path).read_text(encoding="latin-1")
    by_number = {mode.number: mode for mode in _file_modes(sets, _dataset_lines(text))}
    found = []
    if units is None:
        found.append(Problem(source, None, "FE modes", "no units dataset (164): the file's length and force units are unknown"))
    if not by_number:
        found.append(Problem(source, None, "FE modes", "no normal modes (dataset 2414 or 55 with analysis type 2)"))
    if found or units is None:
        problems.extend(found)
        return []
    if choices is None:
        choices = [FEModeChoice("", number) for number, mode in sorted(by_number.items(), key=lambda item: item[1].frequency)
                   if mode.frequency >= rigid_below]
    counts: dict[ModeKind, int] = {}
    modes = []
    for choice in choices:
        mode = by_number.get(choice.number)
        if mode is None:
            problems.append(Problem(source, None, f"FE mode {choice.number}",
                                    f"not in the file (its modes: {', '.join(map(str, sorted(by_number)))})"))
            continue
        data = _mode(mode, choice, nodes, axes, units, source, problems)
        if data is None:
            continue
        kind, zeta, shapes = data
        counts[kind] = counts.get(kind, 0) + 1
        name = choice.name or f"{_PREFIX[kind]}{counts[kind]}"
        modes.append(ModeData(name, kind, 2 * math.pi * mode.frequency, zeta, shapes, counts[kind], mode.line or 0))
    return modes


def _mode(mode: _FileMode, choice: FEModeChoice, nodes: Mapping[str, int], axes: tuple[str, str, str],
          units: tuple[float, float], source: str,
          problems: list[Problem]) -> tuple[ModeKind, float | None, dict[str, float]] | None:
    """One FE mode's kind, damping and SI shapes at the points; None after a problem."""
    item = f"FE mode {mode.number} ({mode.frequency:.6g} Hz)"
    line = mode.line
    missing = sorted(point for point, node in nodes.items() if node not in mode.shapes)
    if missing:
        problems.append(Problem(source, line, item, "no shape at the node of "
                                + ", ".join(f"{point} (node {nodes[point]})" for point in missing)))
        return None
    if not (mode.frequency > 0 and mode.modal_mass > 0 and math.isfinite(mode.frequency)):
        problems.append(Problem(source, line, item, f"frequency {mode.frequency} Hz and modal mass {mode.modal_mass} "
                                "must be positive"))
        return None
    length, mass = units
    body = {"x": _axis(axes[0]), "y": _axis(axes[1]), "z": _axis(axes[2])}
    translation = {axis: np.array([sign * mode.shapes[nodes[p]][index] for p in nodes]) for axis, (index, sign) in body.items()}
    kind = choice.kind
    if kind is None:
        squares = {axis: float(np.sum(values**2)) for axis, values in translation.items()}
        total = sum(squares.values())
        dominant = max(squares, key=lambda axis: squares[axis])
        if total == 0 or dominant == "x" or squares[dominant] < PURITY * total:
            shares = ", ".join(f"{axis} {squares[axis] / total:.0%}" for axis in "xyz") if total else "zero"
            problems.append(Problem(source, line, item, f"not a vertical or lateral mode at the points (body {shares}): "
                                    "a modal body moves each mode in one direction; choose the modes in `modes`"))
            return None
        kind = ModeKind.VERTICAL if dominant == "z" else ModeKind.LATERAL
    scale = 1.0 / math.sqrt(mode.modal_mass / mass)  # per sqrt(kg)
    if kind is ModeKind.TORSION:
        index, sign = body["x"]
        rotation = [sign * mode.shapes[nodes[p]][3 + index] for p in nodes]
        if any(math.isnan(value) for value in rotation):
            problems.append(Problem(source, line, item, "torsion needs rotations at the nodes (data characteristic 3)"))
            return None
        shapes = {p: value * scale * length for p, value in zip(nodes, rotation, strict=True)}
    else:
        values = translation["z" if kind is ModeKind.VERTICAL else "y"]
        shapes = {p: float(value) * scale for p, value in zip(nodes, values, strict=True)}
    zeta = mode.damping if mode.damping else None
    return kind, zeta, {p: float(v) for p, v in shapes.items()}
