"""Wheel and rail profiles in the file formats of open contact software: SIMPACK-style
``.prr`` (rail) and ``.prw`` (wheel) files and MiniProf ``.ban`` (rail) and ``.whl``
(wheel) exports, read as CONTACT reads them and mapped to this package's side frame.

Sources: the layouts are those read by CONTACT (E.A.H. Vollebregt, Vtech CMCC; open
source, Apache 2.0, ``github.com/eve70a/CONTACT``): its user guide (``doc/user-guide.tex``,
section "Inputs regarding wheel and rail profiles") and its readers
(``src/m_profile.f90``: ``read_simpack_profile``, ``read_miniprof_profile``,
``check_z_pos_down``; ``matlab/read_simpack.m``, ``matlab/read_miniprof.m``), with the
example files ``examples/MBench_S1002_v3.prw``, ``MBench_UIC60_v3.prr`` and
``MBench_UIC60_v3.ban`` of the Manchester contact benchmark.  ``docs/contact.md``
("Profile files of contact software") summarises them.

**SIMPACK ``.prr``/``.prw``**: ``!`` and ``%`` start a comment; sections
``header.begin`` ... ``header.end`` (``version``, ``type`` = 0 rail, 1 wheel) and
``spline.begin`` ... ``spline.end`` holding ``key = value`` settings and the points
between ``point.begin`` and ``point.end``, one ``y z [weight]`` a line.  The settings are
applied in CONTACT's order: ``point.dist.min`` (drop a point closer than this to the
last one kept; CONTACT's default 1e-4), ``shift.y``/``shift.z``, ``rotate`` (CONTACT
refuses a rotation, so do we), ``bound.y.min/max`` (drop points outside, when min <
max), ``bound.z.min/max`` (clip, when min < max), ``mirror.y``/``mirror.z`` (negate
when 1), then ``units.len.f`` = length unit per metre (1000: mm; default 1: m).
``inversion`` only reorders the points, which this reader sorts anyway.
``approx.smooth`` is ignored (CONTACT does the same; see :func:`smooth_profile`), as
are ``file``, ``file.mtime``, ``comment``, ``type``, ``units.len``, ``units.ang``.

**MiniProf ``.ban``/``.whl``**: ``!``, ``"``, ``%`` and ``#`` start a comment; header
lines ``Keyword=value`` up to the first blank line, then the points in mm, the columns
named by ``ColumnDef`` (letters ``X`` lateral, ``Y`` vertical, ``A``, ``C``, ``N``,
``K``; default ``X,Y`` and any further columns ignored), separated by blanks or commas;
``XOffset``/``YOffset`` are added to X and Y.  An old-style file (``MINIPROF`` in its
first lines) has its free-text header up to the first blank line ignored.  The
direction of Y is not fixed by the format: as CONTACT does (``check_z_pos_down``), a
wheel whose lowest Y lies in the interior and a rail whose Y rises from the ends toward
the middle are taken as measured with Y down, and flipped.

**Axes.**  After these steps both formats give CONTACT's canonical form: y lateral,
positive toward the field side, z positive *down*, with the profile's own origin (the
taping line for a wheel; the rail's reference point).  This package's side frame
(:mod:`express.rail.profiles`) has the same y and z positive *up*, so ``z = -z_file``.
A wheel's flange must then lie at negative y: a ``.prw`` whose flange is at positive y
describes a left-side profile without ``mirror.y = 1`` and is refused; a MiniProf wheel
(whose format has no mirror setting) with its flange at positive X is mirrored, as a
CONTACT user would with ``mirror_y = 1``.  A MiniProf rail is taken with X toward the
field side (CONTACT's default, ``mirror_y = 0``).  The origin is the file's: a measured
profile must be placed with ``shift.y/z`` or ``XOffset/YOffset`` so that y = 0 is the
taping line (wheel) or the crown of the upright rail (rail); a rail file that is already
inclined (as ``MBench_UIC60_v3.prr`` is) is used with inclination 1:inf.

The points are then validated as two-column files are (monotonic lateral coordinate,
plausible extent for the unit, spikes, enough points); every problem of a file is
reported at once, with its line, as a :class:`~express.base.diagnostics.ModelError`.
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np

from express.base.diagnostics import ArgumentError, ModelError, Problem, RowProblems, excerpt
from express.base.limits import read_input_text
from express.rail.options import ProfileKind
from express.rail.profiles import Profile, check_profile_points, parse_profile

__all__ = ["PROFILE_FORMATS", "parse_miniprof", "parse_profile_format", "parse_simpack", "profile_format", "read_profile"]

#: File suffix -> (format, kind of profile it holds).
PROFILE_FORMATS: dict[str, tuple[str, ProfileKind]] = {
    ".prr": ("simpack", "rail"), ".prw": ("simpack", "wheel"),
    ".ban": ("miniprof", "rail"), ".whl": ("miniprof", "wheel"),
}
_SPLINE_NUMBERS = {
    "point.dist.min": 1e-4, "shift.y": 0.0, "shift.z": 0.0, "rotate": 0.0, "bound.y.min": -1e9,
    "bound.y.max": 1e9, "bound.z.min": -1e9, "bound.z.max": 1e9, "mirror.y": 0.0, "mirror.z": 0.0,
    "inversion": -99.0, "units.len.f": 1.0, "units.ang.f": 1.0, "approx.smooth": 0.0, "type": 0.0,
    "file.mtime": 0.0,
}
_SPLINE_TEXT = {"file", "comment", "units.len", "units.ang"}
_SECTIONS = {"header", "spline", "point"}
_MINIPROF_COLUMNS = set("XYACNK")
_SPLIT = re.compile(r"[\s,]+")


def read_profile(
    path: str | Path,
    kind: ProfileKind,
    *,
    units: str | None = None,
    name: str | None = None,
    spike_tolerance: float = 0.5e-3,
    min_points: int = 10,
) -> Profile:
    """Read and validate a profile file: two columns (see the module docstring), or by
    its suffix a ``.prr``/``.prw`` (SIMPACK) or ``.ban``/``.whl`` (MiniProf) file of
    contact software (:mod:`express.rail.profile_formats`).

    Parameters
    ----------
    path : str or Path
        The file.
    kind : {"wheel", "rail"}
        What it describes (sets the plausibility checks and the label).
    units : {"mm", "m"}, optional
        Unit of both columns when the file has no header (a header wins only if it agrees).
    name : str, optional
        The profile's name (default: the file's stem).
    spike_tolerance : float
        A point more than this [m] away from the median of itself and its four neighbours
        is reported as a spike.
    min_points : int
        Fewer points than this is an error.

    Raises
    ------
    ModelError
        With one :class:`Problem` per defect: unreadable file, wrong column count, a value
        that is not a finite number, no or conflicting unit, implausible extent for the unit,
        a lateral coordinate that is not monotonic, a spike, too few points.
    """
    path = Path(path)
    text = read_input_text(path, what="profile")  # bounded (EXPRESS_MAX_FILE_MB), UTF-8 text
    if path.suffix.lower() in (".prr", ".prw", ".ban", ".whl"):
        return parse_profile_format(text, kind, file=str(path), units=units, name=name or path.stem,
                                    spike_tolerance=spike_tolerance, min_points=min_points)
    return parse_profile(
        text, kind, file=str(path), units=units, name=name or path.stem,
        spike_tolerance=spike_tolerance, min_points=min_points,
    )


def profile_format(path: str | Path) -> tuple[str, ProfileKind] | None:
    """``(format, kind)`` of a profile file by its suffix (case-insensitive), ``None`` for
    a two-column file."""
    return PROFILE_FORMATS.get(Path(path).suffix.lower())


def parse_profile_format(text: str, kind: ProfileKind, *, file: str, units: str | None = None, name: str | None = None,
                         spike_tolerance: float = 0.5e-3, min_points: int = 10) -> Profile:
    """The profile in ``text``, read in the format of ``file``'s suffix (see the module
    docstring), as :func:`express.rail.profiles.parse_profile` reads a two-column file.

    Raises
    ------
    ModelError
        Every problem of the file, with its line: a suffix for the other kind of profile,
        a malformed section or setting, a point line without two finite numbers, a unit
        asked for that the file contradicts, and the checks of the points.
    """
    found = profile_format(file)
    if found is None:
        raise ArgumentError(f"{file}: not a .prr, .prw, .ban or .whl file")
    form, holds = found
    problems: list[Problem] = []
    if holds != kind:
        problems.append(Problem(file, None, "", f"a {Path(file).suffix} file holds a {holds} profile, given as the {kind}"))
    reader = _simpack_points if form == "simpack" else _miniprof_points
    y, z, lines, unit = reader(text, file, holds, problems)
    if units is not None and units != unit:
        problems.append(Problem(file, None, "units", f"the file gives its points in {unit}, but {units} was asked for"))
    if not len(y):
        problems.append(Problem(file, None, "", "no profile points"))
        raise ModelError(problems)
    z = -z  # CONTACT's z points down, this package's up
    if len(y) > 1 and np.all(np.diff(y) < 0):  # CONTACT orders a wheel's points by decreasing y
        y, z, lines = y[::-1], z[::-1], lines[::-1]
    if holds == kind == "wheel" and not problems:
        y, z, lines = _wheel_side(y, z, lines, file, form, problems)
    scale = 1e-3 if unit == "m" else 1.0  # checked in the file's unit, for its hints
    problems += check_profile_points(y * scale, z * scale, lines, file, kind, "m" if unit == "m" else "mm",
                                     spike_tolerance, min_points)
    if problems:
        raise ModelError(problems)
    return Profile(name or Path(file).stem, kind, y * 1e-3, z * 1e-3, file)


def _wheel_side(y, z, lines, file, form, problems):
    """A wheel's flange (its lowest z, up, more than 5 mm below the taping line) belongs
    at negative y; a wheel without one (a roller) is left as it is."""
    lowest = int(np.argmin(z))
    if len(y) < 2 or y[lowest] <= 0.0 or not z[lowest] < np.interp(0.0, y, z) - 5.0:
        return y, z, lines
    if form == "miniprof":  # the format has no mirror setting: the flange tells the side
        return -y[::-1], z[::-1], lines[::-1]
    problems.append(Problem(
        file, None, "mirror.y",
        f"the flange (lowest point, y = {y[int(np.argmin(z))]:g} mm) lies at positive y: the points describe a "
        "left-side wheel with y toward the track centre; set mirror.y = 1 in the spline section",
    ))
    return y, z, lines


# ------------------------------------------------------------------------- SIMPACK


def parse_simpack(text: str, kind: ProfileKind, *, file: str = "<profile>.prw", **options) -> Profile:
    """A ``.prr``/``.prw`` profile from its text (``file`` names it and gives the suffix)."""
    return parse_profile_format(text, kind, file=file, **options)


def _simpack_points(text: str, file: str, kind: ProfileKind, problems: list[Problem]):
    """Points ``(y, z, lines)`` in mm, CONTACT's axes (z down), after the settings."""
    settings: dict[str, float] = {}
    points: list[tuple[int, float, float]] = []
    bad = RowProblems(file)
    open_sections: list[str] = []
    header_type = None
    number = 0
    for number, raw in enumerate(text.splitlines(), start=1):
        line = _strip_comment(raw, "!%")
        if not line:
            continue
        key, sep, value = line.partition("=")
        key = key.strip().lower()
        if not sep and re.fullmatch(r"[a-z]+\.(begin|end)", key):
            _section(key, open_sections, file, number, problems)
            continue
        section = open_sections[-1] if open_sections else None
        if section == "point":
            _point_line(line, number, points, bad)
        elif not sep:
            problems.append(Problem(file, number, "", f"expected key = value or a section line, found {excerpt(line)}"))
        elif section == "header":
            header_type = _header_setting(key, value.strip(), file, number, problems, header_type)
        elif section == "spline":
            _spline_setting(key, value.strip(), file, number, settings, problems)
        else:
            problems.append(Problem(file, number, key, "a setting outside the header and spline sections"))
        if section is None and key == "spline.end":
            break
    problems += bad.problems()
    if open_sections:
        problems.append(Problem(file, number or None, "", f"the file ends inside the {open_sections[-1]} section"))
    if header_type is not None and header_type != (1 if kind == "wheel" else 0):
        problems.append(Problem(file, None, "type", f"header type = {header_type} ({'wheel' if header_type else 'rail'}) "
                                f"in a {kind} profile file (0 = rail, 1 = wheel)"))
    factor = settings.get("units.len.f", 1.0)
    unit = {1.0: "m", 1000.0: "mm"}.get(factor, f"1/{factor:g} m")
    if not points:
        return np.zeros(0), np.zeros(0), np.zeros(0, dtype=int), unit
    array = np.array(points, dtype=float)
    lines, y, z = array[:, 0].astype(int), array[:, 1], array[:, 2]
    y, z, lines = _apply_settings(y, z, lines, settings, file, problems)
    return y * 1e3 / factor, z * 1e3 / factor, lines, unit


def _strip_comment(raw: str, marks: str) -> str:
    """The line without its comment (a mark outside single quotes), stripped."""
    quoted = False
    for index, char in enumerate(raw):
        if char == "'":
            quoted = not quoted
        elif char in marks and not quoted:
            return raw[:index].strip()
    return raw.strip()


def _section(key: str, open_sections: list[str], file: str, number: int, problems: list[Problem]) -> None:
    name, _, edge = key.partition(".")
    if name not in _SECTIONS:
        problems.append(Problem(file, number, key, "unknown section (known: header, spline, point)"))
        return
    parent = "spline" if name == "point" else None
    if edge == "begin":
        if (open_sections[-1] if open_sections else None) != parent or name in open_sections:
            where = f"inside the {parent} section" if parent else "at the top level"
            problems.append(Problem(file, number, key, f"sections nest wrongly: {name} belongs {where}"))
        open_sections.append(name)
    elif open_sections and open_sections[-1] == name:
        open_sections.pop()
    else:
        problems.append(Problem(file, number, key, f"ends the {name} section, which is not open"))


def _point_line(line: str, number: int, points: list, bad: RowProblems) -> None:
    fields = line.split()
    if not 2 <= len(fields) <= 3:
        bad.add(number, "", f"expected y, z and an optional weight, found {len(fields)} values", line)
        return
    try:
        values = [float(field) for field in fields]
    except ValueError:
        bad.add(number, "point", "not a number", line, "{found} is {message}")
        return
    if not all(math.isfinite(v) for v in values):
        bad.add(number, "point", "not a finite number", line, "{found} is {message}")
        return
    points.append((number, values[0], values[1]))


def _header_setting(key, value, file, number, problems, header_type):
    if key not in ("version", "type"):
        problems.append(Problem(file, number, key, "unknown header setting (known: version, type)"))
        return header_type
    try:
        integer = int(value)
    except ValueError:
        problems.append(Problem(file, number, key, f"expected an integer, found {excerpt(value)}"))
        return header_type
    if key == "type":
        if integer not in (0, 1):
            problems.append(Problem(file, number, key, f"must be 0 (rail) or 1 (wheel), found {integer}"))
            return header_type
        return integer
    return header_type


def _spline_setting(key, value, file, number, settings, problems) -> None:
    if key in _SPLINE_TEXT:
        return
    if key not in _SPLINE_NUMBERS:
        return  # CONTACT ignores settings it does not know (with a message)
    try:
        number_value = float(value.split()[0]) if value.split() else math.nan
    except ValueError:
        number_value = math.nan
    if not math.isfinite(number_value):
        problems.append(Problem(file, number, key, f"expected a number, found {excerpt(value)}"))
        return
    if key in ("units.len.f", "units.ang.f") and not number_value > 0:
        problems.append(Problem(file, number, key, f"the unit factor must be positive, found {number_value:g}"))
        return
    if key in ("mirror.y", "mirror.z") and number_value not in (0.0, 1.0):
        problems.append(Problem(file, number, key, f"must be 0 (no mirroring) or 1 (mirrored), found {number_value:g}"))
        return
    settings[key] = number_value


def _apply_settings(y, z, lines, settings, file, problems):
    """CONTACT's modifications 1 to 8, in its order (user units)."""
    s = {**_SPLINE_NUMBERS, **settings}
    gap = max(1e-6, s["point.dist.min"]) if "point.dist.min" in settings else 1e-4
    keep = [0]
    for i in range(1, len(y)):
        if math.hypot(y[i] - y[keep[-1]], z[i] - z[keep[-1]]) >= gap:
            keep.append(i)
    y, z, lines = y[keep] + s["shift.y"], z[keep] + s["shift.z"], lines[keep]
    if abs(s["rotate"] / s["units.ang.f"]) > 1e-6:
        problems.append(Problem(file, None, "rotate", "a rotated profile is not supported (nor by CONTACT): "
                                "give the points as they lie, rotate = 0"))
    if s["bound.y.min"] < s["bound.y.max"]:
        inside = (y >= s["bound.y.min"]) & (y <= s["bound.y.max"])
        y, z, lines = y[inside], z[inside], lines[inside]
    if s["bound.z.min"] < s["bound.z.max"]:
        z = np.clip(z, s["bound.z.min"], s["bound.z.max"])
    if s["mirror.y"] == 1.0:
        y = -y
    if s["mirror.z"] == 1.0:
        z = -z
    return y, z, lines


# ------------------------------------------------------------------------ MiniProf


def parse_miniprof(text: str, kind: ProfileKind, *, file: str = "<profile>.whl", **options) -> Profile:
    """A ``.ban``/``.whl`` profile from its text (``file`` names it and gives the suffix)."""
    return parse_profile_format(text, kind, file=file, **options)


def _miniprof_points(text: str, file: str, kind: ProfileKind, problems: list[Problem]):
    """Points ``(X, Y, lines)`` in mm, CONTACT's axes (Y made positive down)."""
    lines_in = text.splitlines()
    old_style = any("MINIPROF" in raw for raw in lines_in[:3])
    if any("[FileInfo]" in raw for raw in lines_in[:3]):
        problems.append(Problem(file, 1, "", "a multi-part MiniProf file (.mpt layout) is not supported"))
        return np.zeros(0), np.zeros(0), np.zeros(0, dtype=int), "mm"
    header: dict[str, str] = {}
    rows: list[tuple[int, list[str]]] = []
    in_header = True
    for number, raw in enumerate(lines_in, start=1):
        if in_header and not raw.strip():
            in_header = False
            continue
        line = _strip_comment(raw.replace("'", " "), '!"%#')
        if not line:
            continue
        key, sep, value = line.partition("=")
        if sep and not rows:
            header[key.strip().replace(" ", "_").lower()] = value.strip()
        elif sep:
            problems.append(Problem(file, number, key.strip(), "a header line after the points"))
        elif in_header and old_style:
            continue  # an old-style file's free-text header
        else:
            in_header = False
            rows.append((number, _SPLIT.split(line)))
    columns = _column_def(header.get("columndef", ""), file, problems)
    offsets = [_offset(header, key, file, problems) for key in ("xoffset", "yoffset")]
    x, y, lines = _miniprof_rows(rows, columns, file, problems)
    if len(x):
        y = y + offsets[1]
        x = x + offsets[0]
        if _measured_up(y, kind):
            y = -y
    return x, y, lines, "mm"


def _column_def(text: str, file: str, problems: list[Problem]) -> list[str] | None:
    """Column letters; ``None`` for the default ``X,Y,*`` (further columns ignored)."""
    if not text:
        return None
    letters = [part.strip().upper() for part in text.split(",")]
    if "X" not in letters or "Y" not in letters or not set(letters) <= _MINIPROF_COLUMNS or len(set(letters)) != len(letters):
        problems.append(Problem(file, None, "ColumnDef", f"{excerpt(text)}: expected letters of X, Y, A, C, N, K "
                                "separated by commas, X and Y among them, each once"))
        return None
    return letters


def _offset(header: dict[str, str], key: str, file: str, problems: list[Problem]) -> float:
    text = header.get(key, "").split(",")[0].strip()
    if not text:
        return 0.0
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not math.isfinite(value):
        problems.append(Problem(file, None, {"xoffset": "XOffset", "yoffset": "YOffset"}[key],
                                f"expected a number [mm], found {excerpt(text)}"))
        return 0.0
    return value


def _miniprof_rows(rows, columns, file, problems):
    count = len(columns) if columns else 2
    ix, iy = (columns.index("X"), columns.index("Y")) if columns else (0, 1)
    bad = RowProblems(file)
    kept = []
    for number, fields in rows:
        values = []
        for field in fields:
            try:
                values.append(float(field))
            except ValueError:
                break  # CONTACT reads the leading numbers; a remark may follow
        if len(values) < count or (columns and len(values) > count):
            what = ",".join(columns) if columns else "X,Y"
            bad.add(number, "", f"expected {count} columns ({what}), found {len(values)} numbers", " ".join(fields))
        elif not (math.isfinite(values[ix]) and math.isfinite(values[iy])):
            bad.add(number, "point", "not a finite number", " ".join(fields), "{found} is {message}")
        else:
            kept.append((number, values[ix], values[iy]))
    problems += bad.problems()
    if not kept:
        return np.zeros(0), np.zeros(0), np.zeros(0, dtype=int)
    array = np.array(kept, dtype=float)
    return array[:, 1], array[:, 2], array[:, 0].astype(int)


def _measured_up(z: np.ndarray, kind: ProfileKind) -> bool:
    """CONTACT's ``check_z_pos_down``: True when the points have z positive up.

    A wheel's lowest z (z down) lies at a side face, at either end of the points; a
    rail's z falls from the ends toward the crown in the middle.
    """
    n = len(z)
    if n < 3:
        return False
    frac_min, frac_max = (int(np.argmin(z)) + 1) / n, (int(np.argmax(z)) + 1) / n
    if kind == "wheel":
        if frac_min < 0.05 or frac_min > 0.95:
            return False
        if frac_max < 0.05 or frac_max > 0.95:
            return True
        middle = round(n * (frac_min + frac_max) / 2.0) - 1
        return bool(z[middle] > (z.min() + z.max()) / 2.0)
    spread = max(1e-5, float(z.max() - z.min()))
    start = _first_change(z, range(1, max(2, round(0.1 * n))), 0, spread)
    end = _first_change(z, range(n - 2, max(-1, round(0.9 * n) - 2), -1), n - 1, spread)
    if start == end or end == 0:
        tendency = start
    elif start == 0:
        tendency = end
    else:
        tendency = -1
    if tendency == 0:
        return bool(frac_min < 0.1 or frac_min > 0.9)
    return tendency == 1


def _first_change(z: np.ndarray, indices, edge: int, spread: float) -> int:
    """Sign of the first change of z from ``z[edge]`` above 0.1 % of the spread."""
    for i in indices:
        change = z[i] - z[edge]
        if abs(change) > 1e-3 * spread:
            return 1 if change > 0 else -1
    return 0
