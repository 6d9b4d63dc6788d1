"""Wheel and rail profiles: reading and validating profile files, smoothing, and the
standard S1002 wheel (EN 13715) and 60E1/UIC60 rail (EN 13674-1) shapes.

A profile is a curve ``(y, z)`` in its own *side frame*, in metres (``docs/contact.md``):

* ``y`` lateral, positive toward the **field side** (away from the track centre), so the
  wheel flange and the rail's gauge face are at negative ``y``;
* ``z`` vertical, positive **up**;
* wheel: origin at the taping line (nominal rolling circle), ``z`` measured from its lowest
  point, so the rolling radius at ``y`` is ``r0 - z(y)`` and the flange tip has ``z < 0``;
  the flange back (inner face) is ``tapeline_offset`` (70 mm for S1002) inward;
* rail: origin at the crown of the upright (not inclined) rail, on its axis; ``z <= 0``.

The same file serves a left and a right wheel (rail): the right one is its mirror image.
Files are read by :func:`express.rail.profile_formats.read_profile` (two columns, or
SIMPACK ``.prr``/``.prw`` and MiniProf ``.ban``/``.whl`` files of contact software).  Two-column files are plain text: ``#``
comments, an optional header ``y_mm,z_mm`` (or ``y_m,z_m``) naming the unit, then two
numbers a line separated by a comma, semicolon or blanks.  Every problem found is reported at once, with file and line, as a
:class:`~express.base.diagnostics.ModelError`.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from importlib import resources
from pathlib import Path

import numpy as np

from express.base.diagnostics import ArgumentError, ModelError, Problem, RowProblems, excerpt
from express.rail.options import PROFILE_KINDS, ProfileKind

__all__ = [
    "STANDARD_PROFILES",
    "Profile",
    "check_profile_points",
    "parse_inclination",
    "parse_profile",
    "role_problems",
    "row_numbers",
    "s1002_height",
    "smooth_profile",
    "standard_profile",
    "standard_profile_text",
    "uic60_height",
]

_UNITS = {"m": 1.0, "mm": 1e-3}
_HEADER = re.compile(r"(y|z)_(m|mm)\Z", re.IGNORECASE)
_SPLIT = re.compile(r"[,;\s]+")
#: Problems of one kind listed before the rest are summed up in one line.
_MAX_LISTED = 20


@dataclass(frozen=True, eq=False)
class Profile:
    """A wheel or rail profile in its side frame (see the module docstring).

    Attributes
    ----------
    name : str
        Label for displays (file stem or standard name).
    kind : str
        ``"wheel"`` or ``"rail"``.
    y, z : numpy.ndarray, shape (n,)
        Lateral (strictly increasing) and vertical coordinates [m].
    source : str
        Where the points came from (a path, or the standard's name).
    """

    name: str
    kind: ProfileKind
    y: np.ndarray
    z: np.ndarray
    source: str = ""

    def __post_init__(self) -> None:
        if self.kind not in PROFILE_KINDS:
            raise ArgumentError(f"profile kind must be 'wheel' or 'rail', not {self.kind!r}")
        if self.y.shape != self.z.shape or self.y.ndim != 1:
            raise ArgumentError("profile y and z must be 1-D arrays of one length")
        if len(self.y) < 4 or not np.all(np.diff(self.y) > 0):
            raise ArgumentError("profile y must be strictly increasing with at least 4 points")

    def mirrored(self) -> Profile:
        """The same profile with ``y`` reversed (a profile measured the other way round)."""
        return Profile(self.name, self.kind, -self.y[::-1].copy(), self.z[::-1].copy(), self.source)


def parse_inclination(text: str | float) -> float:
    """Rail inclination as its tangent: ``"1:40"`` -> 0.025, ``"1:inf"`` or ``0`` -> 0.0.

    A number is taken as the tangent itself (``0.025``); ``"1:n"`` needs n >= 5.
    """
    if isinstance(text, (int, float)):
        value = float(text)
    else:
        head, sep, tail = str(text).strip().partition(":")
        try:
            if not sep:
                value = float(head)
            elif float(head) != 1.0:
                raise ValueError
            elif tail.strip().lower() in ("inf", "∞", "infinity"):
                value = 0.0
            else:
                value = 1.0 / float(tail)
        except (ValueError, ZeroDivisionError):
            raise ArgumentError(f'rail inclination "{text}": expected 1:n (e.g. 1:40, 1:20, 1:inf) or a tangent') from None
    if not math.isfinite(value) or not 0.0 <= value <= 0.2:
        raise ArgumentError(f'rail inclination "{text}": the tangent must lie in 0..0.2 (1:inf .. 1:5)')
    return value


# ---------------------------------------------------------------------------- reading


def parse_profile(
    text: str,
    kind: ProfileKind,
    *,
    file: str = "<profile>",
    units: str | None = None,
    name: str | None = None,
    spike_tolerance: float = 0.5e-3,
    min_points: int = 10,
) -> Profile:
    """:func:`express.rail.profile_formats.read_profile` on a two-column text already read (``file`` names it in the messages)."""
    if kind not in PROFILE_KINDS:
        raise ArgumentError(f"profile kind must be 'wheel' or 'rail', not {kind!r}")
    if units is not None and units not in _UNITS:
        raise ArgumentError(f"profile units must be 'mm' or 'm', not {units!r}")
    problems: list[Problem] = []
    header_unit, rows = _parse_rows(text, file, problems)
    if not rows:
        problems.append(Problem(file, None, "", "no profile points"))
        raise ModelError(problems)
    unit = _resolve_unit(header_unit, units, file, problems)
    lines = np.array([row[0] for row in rows])
    y = np.array([row[1] for row in rows])
    z = np.array([row[2] for row in rows])
    if len(rows) > 1 and np.all(np.diff(y) < 0):  # a file written from the other end
        lines, y, z = lines[::-1], y[::-1], z[::-1]
    problems += check_profile_points(y, z, lines, file, kind, unit, spike_tolerance, min_points)
    if problems:
        raise ModelError(problems)
    factor = _UNITS[unit or "m"]
    return Profile(name or Path(file).stem, kind, y * factor, z * factor, file)


def _parse_rows(text: str, file: str, problems: list[Problem]) -> tuple[str | None, list[tuple[int, float, float]]]:
    """Header unit and the numeric rows ``(line, y, z)``; bad lines become problems."""
    header_unit: str | None = None
    rows: list[tuple[int, float, float]] = []
    seen_data = False
    bad = RowProblems(file)  # the file may not be the user's own: one short excerpt, 20 rows
    for number, raw in enumerate(text.splitlines(), start=1):
        line = raw.split("#", 1)[0].strip()
        if not line:
            continue
        fields = [field for field in _SPLIT.split(line) if field]
        if not seen_data and any(ch.isalpha() for ch in line) and not _all_numbers(fields):
            header_unit = _parse_header(fields, file, number, problems)
            bad.quoted = bool(problems)  # the header's problem quoted the file already
            seen_data = True
            continue
        seen_data = True
        if len(fields) != 2:
            bad.add(number, "", f"expected 2 columns (lateral, vertical), found {len(fields)}", line)
            continue
        values = row_numbers(fields, ("lateral coordinate", "vertical coordinate"), number, bad)
        if values is not None:
            rows.append((number, values[0], values[1]))
    problems += bad.problems()
    return header_unit, rows


def row_numbers(fields: list[str], columns: tuple[str, ...], number: int, bad: RowProblems) -> list[float] | None:
    """The ``fields`` of data row ``number`` as finite numbers, or ``None`` once every
    bad one is added to ``bad`` (its item the column's name in ``columns``)."""
    values = []
    for column, field in zip(columns, fields, strict=True):
        try:
            value = float(field)
        except ValueError:
            bad.add(number, column, "not a number", field, "{found} is {message}")
            continue
        if not math.isfinite(value):
            bad.add(number, column, "not a finite number", field, "{found} is {message}")
            continue
        values.append(value)
    return values if len(values) == len(columns) else None


def _all_numbers(fields: list[str]) -> bool:
    try:
        [float(field) for field in fields]
    except ValueError:
        return False
    return True


def _parse_header(fields: list[str], file: str, number: int, problems: list[Problem]) -> str | None:
    matches = [_HEADER.match(field) for field in fields]
    if len(fields) != 2 or not all(matches) or [m.group(1).lower() for m in matches if m] != ["y", "z"]:
        problems.append(Problem(file, number, "header", f"{excerpt(', '.join(fields))}: expected the columns y_mm,z_mm or y_m,z_m"))
        return None
    units = {m.group(2).lower() for m in matches if m}
    if len(units) != 1:
        problems.append(Problem(file, number, "header", "both columns must have the same unit (y_mm,z_mm or y_m,z_m)"))
        return None
    return units.pop()


def _resolve_unit(header_unit: str | None, option: str | None, file: str, problems: list[Problem]) -> str | None:
    if header_unit and option and header_unit != option:
        problems.append(Problem(file, None, "units", f"the header says {header_unit} but {option} was asked for"))
    unit = header_unit or option
    if unit is None and not any(p.item == "header" for p in problems):
        problems.append(Problem(file, None, "units", "unknown unit: add a header line y_mm,z_mm (or y_m,z_m) or give the unit"))
    return unit


def check_profile_points(y, z, lines, file, kind, unit, spike_tolerance, min_points) -> list[Problem]:
    """The problems of points ``y``, ``z`` (increasing y; in ``unit``, or None when it is
    unknown) read from ``lines`` of ``file``: too few, y not increasing, an implausible
    extent for the unit, the origin outside, spikes."""
    problems: list[Problem] = []
    if len(y) < min_points:
        problems.append(Problem(file, None, "", f"{len(y)} points: a {kind} profile needs at least {min_points}"))
    bad = np.flatnonzero(np.diff(y) <= 0) + 1
    for count, i in enumerate(bad):
        if count == _MAX_LISTED:
            problems.append(Problem(file, int(lines[i]), "", f"... and {len(bad) - count} more points where y does not increase"))
            break
        problems.append(Problem(
            file, int(lines[i]), "lateral coordinate",
            f"y = {y[i]:g} does not increase (line {lines[i - 1]} has y = {y[i - 1]:g}): a profile must be "
            "single-valued in y, sorted in one direction; trim overhanging parts such as the flange back",
        ))
    if unit is not None and len(y) > 1:
        problems += _check_extent(y, z, file, kind, unit)
    if unit is not None and len(y) >= 5 and not len(bad):
        problems += _check_spikes(y, z * _UNITS[unit], lines, file, spike_tolerance, unit)
    return problems


#: Shape of a wheel profile (side frame, mm): a flange at least this deep below the
#: taping line, at negative y ...
FLANGE_DEPTH_MM = 10.0
#: ... and a tread on the field side (y >= 0) that nowhere drops more than this below it.
TREAD_DROP_MM = 2.0
#: Shape of a rail profile: the crown (the highest point) within this of y = 0, ...
CROWN_OFFSET_MM = 15.0
#: ... the head falling at least this much to both ends, and rising nowhere again by
#: more than this (a convex head, no flange-like dip).
HEAD_FALL_MM = 1.0


def role_problems(y_mm: np.ndarray, z_mm: np.ndarray, file: str, kind: ProfileKind) -> list[Problem]:
    """Whether the shape fits the role (``docs/contact.md``, side frame, in mm): a wheel has
    a flange (at least :data:`FLANGE_DEPTH_MM` below the taping line, at negative y) and a
    tread (the field side nowhere :data:`TREAD_DROP_MM` below it); a rail a convex head
    (its crown within :data:`CROWN_OFFSET_MM` of y = 0, falling to both ends and rising
    nowhere again). A problem names the file, the role and what was seen.

    Examples
    --------
    >>> y = np.linspace(-36.0, 36.0, 73)
    >>> [p.message[:44] for p in role_problems(y, -y**2 / 50, "r.csv", "wheel")]
    ['given as the wheel, but it has a convex head']
    """
    seen = _shape(y_mm, z_mm)
    if kind == "wheel":
        if seen["flange"] and seen["flange_y"] < 0 and seen["tread"]:
            return []
        if seen["flange"] and seen["flange_y"] > 0:
            what = (f"its flange ({seen['depth']:.3g} mm deep at y = {seen['flange_y']:.4g} mm) lies at positive y: "
                    "a mirrored wheel (the flange belongs at negative y, toward the track centre; mirror y)")
        elif seen["head"]:
            what = f"it has a convex head ({seen['fall']}) instead of a flange and a tread: a rail profile?"
        elif not seen["flange"]:
            what = f"it has no flange (the lowest point is {seen['depth']:.3g} mm below y = 0, at least {FLANGE_DEPTH_MM:g} needed)"
        else:
            what = f"its field side (y > 0) drops {seen['drop']:.3g} mm below the taping line: no tread"
        return [Problem(file, None, "wheel profile", f"given as the wheel, but {what}")]
    if seen["head"]:
        return []
    if seen["flange"]:
        what = (f"it has a flange ({seen['depth']:.3g} mm deep at y = {seen['flange_y']:.4g} mm) and "
                "a tread: a wheel profile?")
    else:
        what = f"it has no convex head ({seen['why']})"
    return [Problem(file, None, "rail profile", f"given as the rail, but {what}")]


def _shape(y: np.ndarray, z: np.ndarray) -> dict:
    """What a profile looks like: flange, tread, convex head (see :func:`role_problems`)."""
    level = float(np.interp(0.0, y, z))
    lowest = int(np.argmin(z))
    depth = level - float(z[lowest])
    field = z[y >= 0.0]
    drop = level - float(field.min()) if field.size else 0.0
    top = int(np.argmax(z))
    outward = (z[: top + 1][::-1], z[top:])  # from the highest point to each end
    rise_left, rise_right = (float(np.max(side - np.minimum.accumulate(side))) for side in outward)
    falls = (float(z[top] - z[0]), float(z[top] - z[-1]))
    why = ""
    if abs(float(y[top])) > CROWN_OFFSET_MM:
        why = f"the highest point is at y = {float(y[top]):.4g} mm, not near the crown at y = 0"
    elif min(falls) < HEAD_FALL_MM:
        why = f"it does not fall to both sides of its highest point (by {falls[0]:.3g} and {falls[1]:.3g} mm)"
    elif max(rise_left, rise_right) > HEAD_FALL_MM:
        why = f"it rises again by {max(rise_left, rise_right):.3g} mm away from its highest point"
    return {
        "flange": depth >= FLANGE_DEPTH_MM, "flange_y": float(y[lowest]), "depth": depth,
        "tread": drop <= TREAD_DROP_MM, "drop": drop,
        "head": not why, "why": why, "fall": f"falling {falls[0]:.3g} and {falls[1]:.3g} mm to the two sides",
    }


def _check_extent(y, z, file, kind, unit) -> list[Problem]:
    factor = _UNITS[unit]
    width = (y[-1] - y[0]) * factor
    height = (z.max() - z.min()) * factor
    if width > 0.5 or height > 0.2:
        hint = " (the values look like mm)" if unit == "m" else ""
        return [Problem(file, None, "units", f"the profile spans {width:g} m x {height:g} m, too large for a {kind}{hint}")]
    if width < 5e-3:
        hint = " (the values look like m)" if unit == "mm" else ""
        return [Problem(file, None, "units", f"the profile spans only {width * 1e3:g} mm laterally, too small for a {kind}{hint}")]
    if not y[0] <= 0.0 <= y[-1]:
        origin = "taping line" if kind == "wheel" else "rail crown"
        return [Problem(file, None, "origin", f"y = 0 (the {origin}) lies outside the profile (y from {y[0]:g} to {y[-1]:g} {unit})")]
    return []


def _check_spikes(y, z_si, lines, file, tolerance, unit) -> list[Problem]:
    padded = np.concatenate([z_si[:1], z_si[:1], z_si, z_si[-1:], z_si[-1:]])
    windows = np.lib.stride_tricks.sliding_window_view(padded, 5)
    deviation = np.abs(z_si - np.median(windows, axis=1))
    problems = []
    for count, i in enumerate(np.flatnonzero(deviation > tolerance)):
        if count == _MAX_LISTED:
            problems.append(Problem(file, int(lines[i]), "", "... and more spikes"))
            break
        problems.append(Problem(
            file, int(lines[i]), "spike",
            f"z = {z_si[i] / _UNITS[unit]:g} {unit} at y = {y[i]:g} {unit} is {deviation[i] * 1e3:.3g} mm off its "
            f"neighbours (more than {tolerance * 1e3:g} mm)",
        ))
    return problems


# --------------------------------------------------------------------------- smoothing


def smooth_profile(profile: Profile, window: float = 2e-3, spacing: float = 0.1e-3) -> Profile:
    """A smoothed copy: resampled on a uniform grid and filtered by Savitzky-Golay.

    Parameters
    ----------
    window : float
        Length of the filter window [m] (a cubic is fitted over it); noise shorter than
        this is removed, cubic shapes over it are kept exactly.
    spacing : float
        Uniform lateral spacing of the result [m].
    """
    from scipy.signal import savgol_filter

    y = np.arange(profile.y[0], profile.y[-1] + 0.5 * spacing, spacing)
    y = y[y <= profile.y[-1]]
    z = np.interp(y, profile.y, profile.z)
    points = max(5, round(window / spacing) | 1)
    if points > len(y):
        raise ArgumentError(f"smoothing window {window * 1e3:g} mm is longer than the profile")
    return Profile(profile.name, profile.kind, y, savgol_filter(z, points, 3, mode="interp"), profile.source)


# -------------------------------------------------------------------- standard profiles

# S1002 (EN 13715 Annex C / UIC 510-2): height F(s) of the profile below the taping line
# [mm] as a function of s [mm], lateral from the taping line, positive toward the field side.
# Sections A..H from the field side to the flange back; polynomials are in powers of s.
_S1002_BREAKS = (60.0, 32.15796, -26.0, -35.0, -38.426669071, -39.764473993, -49.662510381, -62.764705882, -70.0)
_S1002_A = (1.364323640, -0.066666667)
_S1002_B = (0.0, -3.358537058e-02, 1.565681624e-03, -2.810427944e-05, 5.844240864e-08,
            -1.562379023e-08, 5.309217349e-15, -5.957839843e-12, 2.646656573e-13)
_S1002_C = (-4.320221063e+03, -1.038384026e+03, -1.065501873e+02, -6.051367875, -2.054332446e-01,
            -4.169739389e-03, -4.687195829e-05, -2.252755540e-07)
_S1002_D = (16.446, 13.0, 26.210665)            # F = A - sqrt(B^2 - (s + C)^2)
_S1002_E = (-93.576667419, -2.747477419)         # F = A + B s
_S1002_FGH = ((8.834924130, 20.0, 58.558326413),  # F = A + sqrt(B^2 - (s + C)^2)
              (16.0, 12.0, 55.0),
              (9.519259302, 20.5, 49.5))


def s1002_height(s: np.ndarray) -> np.ndarray:
    """S1002 profile height F(s) [mm] below the taping line, s in [-70, 60] mm.

    The definition of EN 13715 (and UIC 510-2): a straight line, two polynomials, four
    circular arcs and a straight flange face (coefficients in ``docs/contact.md``).
    """
    s = np.asarray(s, dtype=float)
    if np.any((s < -70.0) | (s > 60.0)):
        raise ArgumentError("S1002 is defined for s in [-70, 60] mm")
    b = _S1002_BREAKS
    conditions = [s >= b[1], s >= b[2], s >= b[3], s >= b[4], s >= b[5], s >= b[6], s >= b[7], s >= b[8]]

    def arc(params, sign):
        a, radius, centre = params
        return a + sign * np.sqrt(np.maximum(radius**2 - (s + centre) ** 2, 0.0))

    choices = [
        np.polynomial.polynomial.polyval(s, _S1002_A),
        np.polynomial.polynomial.polyval(s, _S1002_B),
        np.polynomial.polynomial.polyval(s, _S1002_C),
        arc(_S1002_D, -1.0),
        np.polynomial.polynomial.polyval(s, _S1002_E),
        arc(_S1002_FGH[0], 1.0),
        arc(_S1002_FGH[1], 1.0),
        arc(_S1002_FGH[2], 1.0),
    ]
    return np.select(conditions, choices)


# 60E1 (EN 13674-1; the former UIC60) head: arcs R300, R80, R13 from the crown outward,
# meeting at half-widths 20.456/2, 52.053/2 and 72/2 mm, then the 1:20 flank.
_UIC60_RADII = (300.0, 80.0, 13.0)
_UIC60_BREAKS = (20.456 / 2.0, 52.053 / 2.0, 72.0 / 2.0)
_UIC60_FLANK = 1.0 / 20.0


def _uic60_geometry() -> tuple[tuple[tuple[float, float, float], ...], tuple[float, float]]:
    """Centres ``(y, z, R)`` of the three arcs and the start ``(y, z)`` of the flank [mm]."""
    r1, r2, r3 = _UIC60_RADII
    c1 = (0.0, -r1)
    phi1 = math.asin(_UIC60_BREAKS[0] / r1)
    c2 = (c1[0] + (r1 - r2) * math.sin(phi1), c1[1] + (r1 - r2) * math.cos(phi1))
    phi2 = math.asin((_UIC60_BREAKS[1] - c2[0]) / r2)
    c3 = (c2[0] + (r2 - r3) * math.sin(phi2), c2[1] + (r2 - r3) * math.cos(phi2))
    phi3 = math.asin((_UIC60_BREAKS[2] - c3[0]) / r3)
    start = (c3[0] + r3 * math.sin(phi3), c3[1] + r3 * math.cos(phi3))
    return ((*c1, r1), (*c2, r2), (*c3, r3)), start


def uic60_height(y: np.ndarray) -> np.ndarray:
    """60E1 (UIC60) head height z(y) [mm] below the crown, symmetric, for |y| up to the
    point 30 mm below the crown on the 1:20 flank."""
    y = np.asarray(y, dtype=float)
    arcs, (y_flank, z_flank) = _uic60_geometry()
    depth_limit = -30.0
    y_max = y_flank + (z_flank - depth_limit) * _UIC60_FLANK
    a = np.abs(y)
    if np.any(a > y_max + 1e-9):
        raise ArgumentError(f"60E1 head is tabulated for |y| <= {y_max:.3f} mm")
    z = np.empty_like(a)
    bounds = (0.0, *_UIC60_BREAKS)
    for (cy, cz, radius), lo, hi in zip(arcs, bounds[:-1], bounds[1:], strict=True):
        mask = (a >= lo) & (a <= hi)
        z[mask] = cz + np.sqrt(np.maximum(radius**2 - (a[mask] - cy) ** 2, 0.0))
    flank = a > _UIC60_BREAKS[2]
    z[flank] = z_flank - (a[flank] - y_flank) / _UIC60_FLANK
    return z


def _arc_length_samples(func, lo: float, hi: float, step: float, breaks: tuple[float, ...]) -> np.ndarray:
    """Abscissae in [lo, hi] spaced ``step`` along the curve z = func(y), with the ends, the
    origin and the section breaks included exactly (samples closer than step/4 to one are dropped)."""
    dense = np.linspace(lo, hi, round((hi - lo) / 1e-3) + 1)
    height = func(dense)
    length = np.concatenate([[0.0], np.cumsum(np.hypot(np.diff(dense), np.diff(height)))])
    samples = np.round(np.interp(np.arange(0.0, length[-1], step), length, dense), 9)
    fixed = np.array(sorted({lo, hi, 0.0, *(b for b in breaks if lo < b < hi)}))
    nearest = np.min(np.abs(samples[:, None] - fixed[None, :]), axis=1)
    return np.union1d(samples[nearest > step / 4.0], np.round(fixed, 9))


#: The profiles shipped under ``express/data/profiles`` (name -> file, kind).
STANDARD_PROFILES: dict[str, tuple[str, ProfileKind]] = {"S1002": ("S1002.csv", "wheel"), "60E1": ("60E1.csv", "rail")}
_ALIASES = {"UIC60": "60E1", "60E1": "60E1", "S1002": "S1002"}


def standard_profile_text(name: str, step: float = 0.1) -> str:
    """The text of the shipped file ``name`` (``"S1002"`` or ``"60E1"``), generated from the
    standard's definition with points every ``step`` mm along the curve.

    The data files are exactly this text; ``tests/test_profiles.py`` checks that.
    """
    key = _standard_key(name)
    if key == "S1002":
        y = _arc_length_samples(lambda s: -s1002_height(s), -70.0, 60.0, step, _S1002_BREAKS)
        z = -s1002_height(y)
        head = [
            "# S1002 wheel profile (EN 13715 Annex C; UIC 510-2), new, no wear.",
            "# Generated by express.rail.profiles.standard_profile_text('S1002') from the standard's",
            "# definition: straight line, two polynomials, four circular arcs and a straight flange face;",
            "# coefficients as published in EN 13715 and in open contact codes (docs/contact.md).",
            "# Side frame: y lateral from the taping line, positive toward the field side (flange at",
            "# negative y, flange back at y = -70 mm); z up from the taping line (rolling radius r0 - z).",
            f"# Points every {step:g} mm along the profile, the taping line and section ends included.",
        ]
    else:
        _arcs, (y_flank, z_flank) = _uic60_geometry()
        y_max = round(y_flank + (z_flank + 30.0) * _UIC60_FLANK, 9)
        breaks = tuple(b * sign for b in _UIC60_BREAKS for sign in (-1.0, 1.0))
        y = _arc_length_samples(uic60_height, -y_max, y_max, step, breaks)
        z = uic60_height(y)
        head = [
            "# 60E1 rail head profile (EN 13674-1; the former UIC60), new, upright (not inclined).",
            "# Generated by express.rail.profiles.standard_profile_text('60E1') from the drawing's",
            "# definition: arcs R300, R80, R13 meeting at half-widths 10.228, 26.0265 and 36 mm,",
            "# then the 1:20 flank, drawn to 30 mm below the crown (docs/contact.md).",
            "# Side frame: y lateral from the rail axis, positive toward the field side (gauge face at",
            "# negative y); z up from the crown.",
            f"# Points every {step:g} mm along the profile, the crown and arc ends included.",
        ]
    # nine decimals (pm): curvatures come from second differences of these points
    body = [f"{a:.9f},{b:.9f}" for a, b in zip(y, z, strict=True)]
    return "\n".join([*head, "y_mm,z_mm", *body]) + "\n"


def standard_profile(name: str) -> Profile:
    """The shipped profile ``name``: ``"S1002"`` (wheel) or ``"60E1"`` (alias ``"UIC60"``).

    Parameters
    ----------
    name : str
        ``"S1002"``, ``"60E1"`` or ``"UIC60"`` (case and blanks ignored).

    Returns
    -------
    Profile
    """
    key = _standard_key(name)
    filename, kind = STANDARD_PROFILES[key]
    text = resources.files("express").joinpath("data").joinpath("profiles").joinpath(filename).read_text(encoding="utf-8")
    return parse_profile(text, kind, file=f"express/data/profiles/{filename}", name=key)


def _standard_key(name: str) -> str:
    key = _ALIASES.get(name.strip().upper().replace(" ", ""))
    if key is None:
        raise ArgumentError(f"unknown standard profile {name!r} (known: S1002, 60E1 alias UIC60)")
    return key
