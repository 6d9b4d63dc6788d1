"""Track files (TOML) and measured irregularity profiles (CSV), read into a Track.

This module owns the file formats of ``docs/track.md``: :func:`load_track` reads a
TOML track file, :func:`track_from_dict` builds a :class:`~express.rail.track.geometry.Track`
from its parsed content, :func:`read_profile_csv` reads a measured alignment.

Bad input raises :class:`express.base.diagnostics.ModelError` listing EVERY problem, one
:class:`~express.base.diagnostics.Problem` each, printed ``file:line: item: message``:
lines come from the shared TOML line index (:mod:`express.io.toml_lines`), quantities
with units are parsed by :func:`express.base.units.parse_quantity` against the dimension
each field needs, and the ranges are those of the records themselves (their
``field_problems``), so a file and the Python API refuse the same values.

Limits, checked before anything is read or computed: a track file is at most
:data:`MAX_TRACK_FILE_BYTES`, a CSV profile at most :data:`MAX_PROFILE_BYTES`; both must
be regular files. A CSV that does not parse is reported by line, the first
:data:`MAX_ROW_PROBLEMS` bad rows listed, and only the first bad row quoted (at most
:data:`EXCERPT_CHARS` characters), since the file may not be the user's own. Nothing is
evaluated as code; TOML is parsed by :func:`express.io.toml_lines.parse_toml` (:mod:`tomllib`).
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

import numpy as np

from express.base.diagnostics import ModelError, Problem
from express.base.units import KMH, UnitError, parse_quantity
from express.io.toml_lines import KeyPath, find_line, line_index, parse_toml
from express.rail.track._common import FieldProblem, is_finite_number, is_number
from express.rail.track.component_spectra import component_seed
from express.rail.track.geometry import DIRECTIONS, TRANSITION_SHAPES, Curve, Segment, Straight, Track, Transition
from express.rail.track.irregularity import (
    Irregularity,
    NoIrregularity,
    ProfileIrregularity,
    SinusoidIrregularity,
    SpectrumIrregularity,
)
from express.rail.track.spectra import SPECTRA, SPECTRA_BY_COMPONENT, TrackSpectrum, get_spectrum
from express.rail.track.textfiles import EXCERPT_CHARS, MAX_PROFILE_BYTES, MAX_ROW_PROBLEMS
from express.rail.track.textfiles import excerpt as _excerpt
from express.rail.track.textfiles import read_text_file as _read_text

__all__ = [
    "EXCERPT_CHARS",
    "MAX_PROFILE_BYTES",
    "MAX_ROW_PROBLEMS",
    "MAX_TRACK_FILE_BYTES",
    "MAX_TRACK_SPEED",
    "load_track",
    "read_profile_csv",
    "track_from_dict",
]

#: Largest track file [bytes]: 1 MB holds some 20 000 segments.
MAX_TRACK_FILE_BYTES = 1_000_000
#: Highest nominal speed of a track file [m/s]: 1000 km/h, the command line's limit.
MAX_TRACK_SPEED = 1000.0 * KMH

_REQUIRED = object()
#: Tables of the components besides the alignment (``irregularity``), Track field names.
_COMPONENT_KEYS = ("vertical", "cross_level", "gauge")
_TOP_KEYS = ("name", "description", "speed", "seed", "segment", "irregularity", *_COMPONENT_KEYS, "measured")
#: Fields of each segment type: key -> (dimension, default); dimension None for a word.
_SEGMENT_FIELDS: dict[str, dict[str, tuple[str | None, Any]]] = {
    "straight": {"length": ("length", _REQUIRED)},
    "transition": {"length": ("length", _REQUIRED), "shape": (None, "linear")},
    "curve": {"length": ("length", _REQUIRED), "radius": ("length", _REQUIRED),
              "direction": (None, _REQUIRED), "cant": ("length", 0.0)},
}
_SEGMENT_CLASSES: dict[str, type[Straight] | type[Transition] | type[Curve]] = {
    "straight": Straight, "transition": Transition, "curve": Curve,
}
#: Types a vertical, cross-level or gauge table may have (all those of the alignment).
_COMPONENT_TYPES = ("none", "sinusoid", "csv", "points", "spectrum")
_CHOICES = {"shape": TRANSITION_SHAPES, "direction": DIRECTIONS, "spectrum": tuple(SPECTRA)}
#: The seed of a spectrum table without one: derived from the track's ``seed``.
_DERIVED = object()
#: Fields of each irregularity type, as for the segments; ``file`` and ``seed`` are raw.
_IRREGULARITY_FIELDS: dict[str, dict[str, tuple[str | None, Any]]] = {
    "none": {},
    "sinusoid": {"amplitude": ("length", _REQUIRED), "wavelength": ("length", _REQUIRED),
                 "phase": ("angle", 0.0)},
    "csv": {"file": (None, None)},
    "points": {"points": (None, _REQUIRED)},
    "spectrum": {"spectrum": (None, _REQUIRED), "seed": (None, _DERIVED), "wavelength_min": ("length", 3.0),
                 "wavelength_max": ("length", 120.0), "period": ("length", 10_000.0)},
}


class _Report:
    """Problems of one file; lines looked up in the TOML line index by key path."""

    def __init__(self, source: str, text: str | None):
        self.source = source
        self.index = line_index(text, number_arrays=True) if text else {}
        self.problems: list[Problem] = []

    def add(self, path: KeyPath, item: str, message: str) -> None:
        self.problems.append(Problem(self.source, find_line(self.index, path), item, message))

    def extend(self, problems: Iterable[Problem]) -> None:
        self.problems.extend(problems)

    def raise_if_any(self) -> None:
        """Raise them all: this file's first, those without a line first, then by line
        (stable); then those of other files (a CSV profile) in their own order."""
        if self.problems:
            order = sorted(range(len(self.problems)),
                           key=lambda i: (self.problems[i].file != self.source, self.problems[i].line or 0, i))
            raise ModelError([self.problems[i] for i in order])


def _quantity(value: Any, key: str, dimension: str) -> tuple[float | None, str | None]:
    """``(value in SI, None)`` or ``(None, what is wrong)`` for a number or ``"95 mm"``."""
    if is_number(value):
        if not is_finite_number(value):
            shown = repr(value) if len(repr(value)) <= 30 else f"a number of {len(repr(value))} digits"
            return None, f"'{key}' must be finite, got {shown}"
        return float(value), None
    if isinstance(value, str):
        try:
            return parse_quantity(value, dimension=dimension)[0], None
        except UnitError as exc:
            return None, f"'{key}': {exc}"
    return None, f"'{key}' must be a number or a string with a unit, got {type(value).__name__} {value!r}"


def _read_fields(table: Mapping[str, Any], fields: Mapping[str, tuple[str | None, Any]], report: _Report,
                 path: KeyPath, item: str, choices: Mapping[str, Iterable[str]] | None = None,
                 ) -> tuple[dict[str, Any], set[str]]:
    """The values of ``fields`` (SI for quantities) and the keys that had a problem;
    ``choices`` names the values a missing key may take (default :data:`_CHOICES`)."""
    values: dict[str, Any] = {}
    bad: set[str] = set()
    known = _CHOICES if choices is None else choices
    for key, (dimension, default) in fields.items():
        if key not in table:
            if default is _REQUIRED:
                listed = f" (one of {', '.join(known[key])})" if key in known else ""
                report.add(path, item, f"missing '{key}'{listed}")
                bad.add(key)
            values[key] = None if default is _REQUIRED else default
            continue
        if dimension is None:
            values[key] = table[key]
            continue
        values[key], message = _quantity(table[key], key, dimension)
        if message is not None:
            report.add((*path, key), item, message)
            bad.add(key)
    for key in table:
        if key not in fields and key != "type":
            allowed = ", ".join(sorted(["type", *fields]))
            report.add((*path, key), item, f"unknown key '{key}' (allowed: {allowed})")
    return values, bad


def _report_field_problems(problems: list[FieldProblem], bad: set[str], report: _Report, path: KeyPath,
                           item: str) -> bool:
    """Report the record's own problems for the keys read well; True if there were any."""
    found = bool(bad)
    for key, message in problems:
        if key not in bad:
            report.add((*path, key), item, message)
            found = True
    return found


def _kind(table: Any, kinds: Iterable[str], report: _Report, path: KeyPath, item: str) -> str | None:
    """The ``type`` of a table, or None (reported) if it is not a table or has no known type."""
    kinds = tuple(kinds)
    if not isinstance(table, Mapping):
        report.add(path, item, f"must be a table, got {table!r}")
        return None
    if "type" not in table:
        report.add(path, item, f"missing 'type' (one of {', '.join(kinds)})")
        return None
    if table["type"] not in kinds:
        report.add((*path, "type"), item, f"'type' must be one of {', '.join(kinds)}, got {table['type']!r}")
        return None
    return str(table["type"])


def _segment(i: int, table: Any, report: _Report) -> tuple[str | None, Segment | None]:
    """Segment ``i`` (from 1): its type if known and the segment if valid."""
    path: KeyPath = ("segment", i)
    kind = _kind(table, _SEGMENT_FIELDS, report, path, f"segment {i}")
    if kind is None:
        return None, None
    item = f"segment {i} ({kind})"
    values, bad = _read_fields(table, _SEGMENT_FIELDS[kind], report, path, item)
    cls = _SEGMENT_CLASSES[kind]
    if _report_field_problems(cls.field_problems(**values), bad, report, path, item):
        return kind, None
    return kind, cls(**values)


def _segments(raw: Any, report: _Report) -> list[Segment] | None:
    """All segments, or None if any is bad (every problem reported)."""
    if raw is None:
        report.add((), "track", "no [[segment]] given")
        return None
    if not isinstance(raw, list):
        report.add(("segment",), "track", "'segment' must be an array of tables ([[segment]])")
        return None
    parsed = [_segment(i, table, report) for i, table in enumerate(raw, 1)]
    for i in range(1, len(parsed)):
        if parsed[i - 1][0] == parsed[i][0] == "transition":
            report.add(("segment", i + 1), f"segment {i + 1} (transition)",
                       f"follows another transition (segment {i}); a transition ramps between its "
                       "neighbours, so put a straight or a curve between them")
    segments = [segment for _, segment in parsed]
    if any(segment is None for _, segment in parsed):
        return None
    return [segment for segment in segments if segment is not None]


def _irregularity(table: Any, report: _Report, base_dir: Path, name: str = "irregularity",
                  seed: int = 0) -> Irregularity | None:
    """The irregularity of the table ``name`` (``irregularity``: the alignment, or one of
    :data:`_COMPONENT_KEYS`), or None if it is bad (every problem reported); ``seed`` is
    the track's (a spectrum table without its own takes :func:`component_seed` of it)."""
    path: KeyPath = (name,)
    kinds = _IRREGULARITY_FIELDS if name == "irregularity" else _COMPONENT_TYPES
    kind = _kind(table, kinds, report, path, name)
    if kind is None:
        return None
    item = f"{name} ({kind})"
    component = "alignment" if name == "irregularity" else name
    names = {"spectrum": tuple(SPECTRA_BY_COMPONENT[component])}
    values, bad = _read_fields(table, _IRREGULARITY_FIELDS[kind], report, path, item, {**_CHOICES, **names})
    if kind == "none":
        return NoIrregularity()
    if kind == "sinusoid":
        if _report_field_problems(SinusoidIrregularity.field_problems(**values), bad, report, path, item):
            return None
        return SinusoidIrregularity(**values)
    if kind == "csv":
        return _csv_irregularity(values["file"], report, base_dir, item, name)
    if kind == "points":
        return None if "points" in bad else _points_irregularity(values["points"], report, path, item)
    spectrum = None if "spectrum" in bad else _component_spectrum(values["spectrum"], component)
    if isinstance(spectrum, str):
        report.add((*path, "spectrum"), item, spectrum)
        bad.add("spectrum")
    else:
        values["spectrum"] = spectrum
    if values["seed"] is _DERIVED:
        values["seed"] = component_seed(seed, component)
    if _report_field_problems(SpectrumIrregularity.field_problems(**values), bad, report, path, item):
        return None
    return SpectrumIrregularity(**values)


def _component_spectrum(name: Any, component: str) -> TrackSpectrum | str:
    """The spectrum ``name`` of ``component`` (:func:`get_spectrum`), or what is wrong."""
    if not isinstance(name, str):
        return f"'spectrum' must be the name of a spectrum (one of {', '.join(SPECTRA_BY_COMPONENT[component])}), " \
               f"got {name!r}"
    try:
        return get_spectrum(name, component)
    except KeyError as exc:
        message = str(exc.args[0])
    elsewhere = [other for other in SPECTRA_BY_COMPONENT if other != component and _known(name, other)]
    if elsewhere:
        message += f"; {name!r} is registered for the {', '.join(elsewhere)}, not the {component}"
    return message


def _known(name: str, component: str) -> bool:
    try:
        get_spectrum(name, component)
    except KeyError:
        return False
    return True


def _points_irregularity(points: Any, report: _Report, path: KeyPath, item: str) -> ProfileIrregularity | None:
    """``points = [[s, value], ...]`` [m]: a piecewise-linear shape (a cusp, a ramp, a twist)."""
    if (not isinstance(points, list) or not all(isinstance(p, list) and len(p) == 2 and all(is_number(x) for x in p)
                                                for p in points)):
        report.add((*path, "points"), item, "'points' must be an array of [distance, value] pairs of numbers [m], "
                                            "e.g. [[0, 0], [10, 0.003], [20, 0]]")
        return None
    distance = np.array([float(p[0]) for p in points])
    value = np.array([float(p[1]) for p in points])
    problems = ProfileIrregularity.field_problems(distance, value)
    if problems:
        for _, message in problems:
            report.add((*path, "points"), item, message.replace("yr", "value"))
        return None
    return ProfileIrregularity(distance, value, source=item)


def _measured(table: Any, report: _Report, base_dir: Path, others: list[str]) -> dict[str, Irregularity] | None:
    """The four components of a ``[measured]`` table's CSV file (:mod:`.measured`)."""
    from express.rail.track.measured import read_measured_csv

    path: KeyPath = ("measured",)
    if not isinstance(table, Mapping) or set(table) != {"file"} or not isinstance(table["file"], str) or not table["file"]:
        report.add(path, "measured", "must be a table with one key, 'file': the path of the CSV file "
                                     "(distance and the four components, each with its unit)")
        return None
    if others:
        report.add(path, "measured", f"gives every component, so it cannot be combined with [{'], ['.join(others)}]")
        return None
    name = Path(table["file"])
    try:
        return dict(read_measured_csv(name if name.is_absolute() else base_dir / name))
    except ModelError as exc:
        report.extend(exc.problems)
        return None


def _csv_irregularity(name: Any, report: _Report, base_dir: Path, item: str,
                      table: str = "irregularity") -> ProfileIrregularity | None:
    if not isinstance(name, str) or not name:
        report.add((table, "file"), item, f"'file' must be the path of a CSV file, got {name!r}")
        return None
    path = Path(name)
    try:
        return read_profile_csv(path if path.is_absolute() else base_dir / path, item=item)
    except ModelError as exc:
        report.extend(exc.problems)
        return None


def track_from_dict(
    d: Mapping[str, Any],
    source: str = "<dict>",
    *,
    text: str | None = None,
    base_dir: str | Path | None = None,
) -> Track:
    """Build a :class:`~express.rail.track.geometry.Track` from a parsed track file.

    Parameters
    ----------
    d : mapping
        Parsed TOML: optional ``speed``, ``name``, ``description``, ``seed`` (an
        integer >= 0, default 0: the seed every spectrum table without its own derives
        its seed from, :func:`~express.rail.track.component_spectra.component_seed`); an
        array of ``segment`` tables; optional ``irregularity`` (the alignment),
        ``vertical``, ``cross_level`` and ``gauge`` tables, each of type none, sinusoid,
        csv, points or spectrum (a spectrum of that component, ``get_spectrum(name,
        component)``), or a ``measured`` table (``docs/track.md``).
        Quantities are numbers in SI units or strings with a unit (``"95 mm"``,
        ``"400 m"``, ``"120 km/h"``, ``"90 deg"``), checked against the dimension
        of the field (length, speed, angle).
    source : str
        Name of the file, used in messages.
    text : str, optional
        The TOML text ``d`` was parsed from; only used to give line numbers.
    base_dir : path, optional
        Directory against which a relative CSV ``file`` is resolved; default the
        directory of ``source``.

    Returns
    -------
    Track

    Raises
    ------
    ModelError
        Listing every problem, each ``<file>:<line>: <item>: <what is wrong>``, the
        item being ``track``, ``segment <i> (<type>)`` (numbered from 1 in file order)
        or ``<table> (<type>)`` (``irregularity (spectrum)``, ``gauge (points)``, ...); a
        CSV profile's problems carry its own file and line. Two spectrum tables with the
        same seed are refused (they would draw the same phases).
    """
    report = _Report(source, text)
    base = Path(base_dir) if base_dir is not None else Path(source).parent
    if not isinstance(d, Mapping):
        raise ModelError([Problem(source, None, "track", f"the track must be a table, got {type(d).__name__}")])
    for key in d:
        if key not in _TOP_KEYS:
            report.add((key,), "track", f"unknown key '{key}' (allowed: {', '.join(sorted(_TOP_KEYS))})")
    for key in ("name", "description"):
        if key in d and not isinstance(d[key], str):
            report.add((key,), "track", f"'{key}' must be a string")
    speed = _track_speed(d, report)
    seed = _track_seed(d, report)
    segments = _segments(d.get("segment"), report)
    irregularity: Irregularity | None = NoIrregularity()
    if "irregularity" in d:
        irregularity = _irregularity(d["irregularity"], report, base, seed=seed)
    components = {key: _irregularity(d[key], report, base, key, seed) for key in _COMPONENT_KEYS if key in d}
    _shared_seeds({"irregularity": irregularity, **components}, report)
    if "measured" in d:
        measured = _measured(d["measured"], report, base, [key for key in ("irregularity", *_COMPONENT_KEYS) if key in d])
        if measured is not None:
            irregularity = measured.pop("alignment")
            components.update(measured)
    if segments is not None:
        for _, message in Track.field_problems(segments):
            report.add(("segment",), "track", message)
    report.raise_if_any()
    assert segments is not None and irregularity is not None  # else a problem was raised
    return Track(tuple(segments), irregularity, speed, **components)  # type: ignore[arg-type]


def _track_seed(d: Mapping[str, Any], report: _Report) -> int:
    """The track's ``seed`` (default 0; 0 if bad, reported)."""
    seed = d.get("seed", 0)
    if not isinstance(seed, int) or isinstance(seed, bool) or seed < 0:
        report.add(("seed",), "track", f"'seed' must be a non-negative integer, got {seed!r}")
        return 0
    return seed


def _shared_seeds(tables: Mapping[str, Irregularity | None], report: _Report) -> None:
    """Report a spectrum table whose seed another one has: the two would draw the same
    phases (correlated components, against the stated independence)."""
    first: dict[int, str] = {}
    for name, irregularity in tables.items():
        if not isinstance(irregularity, SpectrumIrregularity):
            continue
        seed = int(irregularity.seed)
        if seed in first:
            report.add((name, "seed"), f"{name} (spectrum)",
                       f"seed {seed} is that of [{first[seed]}] too: the two would draw the same phases "
                       "(correlated components); give another seed, or leave 'seed' out to derive each "
                       "component's from the track's 'seed'")
        else:
            first[seed] = name


def _track_speed(d: Mapping[str, Any], report: _Report) -> float | None:
    if "speed" not in d:
        return None
    speed, message = _quantity(d["speed"], "speed", "speed")
    if message is None and speed is not None and not 0 < speed <= MAX_TRACK_SPEED:
        message = (f"'speed' must be > 0 and at most 1000 km/h ({MAX_TRACK_SPEED:.4g} m/s), "
                   f"got {d['speed']!r}")
    if message is not None:
        report.add(("speed",), "track", message)
        return None
    return speed


# ---------------------------------------------------------------------------------------
# Files
# ---------------------------------------------------------------------------------------


def load_track(path: str | Path) -> Track:
    """Read a TOML track file (format in ``docs/track.md``), or give a bundled track.

    Parameters
    ----------
    path : str or Path
        The track file, a regular file of at most :data:`MAX_TRACK_FILE_BYTES`; or, as a
        str, the name of a bundled track (``"R250"``, ``"R400"``, ``"R600"``, ``"R1000"``,
        ``"R3000"``, ``"paper"``: :mod:`express.rail.track.named`), which is taken before
        a file of that name, as ``--track`` takes it.

    Returns
    -------
    Track

    Raises
    ------
    ModelError
        If the file cannot be read or parsed, or describes a bad track; one problem per
        line, ``<file>:<line>: <item>: <what is wrong>``, every problem at once.
    """
    if isinstance(path, str):
        from express.rail.track.named import NAMED_CURVES, named_track

        if path in NAMED_CURVES or path == "paper":
            return named_track(path)[0]
    path = Path(path)
    source = str(path)
    text = _read_text(path, MAX_TRACK_FILE_BYTES, "track", "utf-8-sig")
    data = parse_toml(text, source)
    return track_from_dict(data, source, text=text, base_dir=path.parent)


_CELLS = re.compile(r"[,;\s]+")


def _floats(cells: list[str]) -> list[float] | None:
    try:
        return [float(cell) for cell in cells]
    except ValueError:
        return None


def _row_problem(cells: list[str], numbers: list[float] | None, previous: tuple[int, float, float] | None) -> str | None:
    """What is wrong with one data row of a CSV profile (None if it is good)."""
    if len(cells) != 2:
        return f"expected 2 columns (distance, yR), got {len(cells)}"
    if numbers is None:
        return "not a number"
    if not all(math.isfinite(x) for x in numbers):
        return "values must be finite"
    if previous is not None and numbers[0] <= previous[1]:
        return f"distance {numbers[0]} is not greater than {previous[1]} on line {previous[0]}"
    return None


def _profile_rows(text: str, source: str, item: str) -> tuple[list[tuple[int, float, float]], list[Problem]]:
    """Rows ``(line, distance, yR)`` of a CSV profile, and the problems of the bad rows."""
    rows: list[tuple[int, float, float]] = []
    problems: list[Problem] = []
    bad = 0
    header_allowed = True
    for lineno, raw in enumerate(text.splitlines(), 1):
        line = raw.strip()
        if not line or line.startswith("#"):
            continue
        cells = [cell for cell in _CELLS.split(line) if cell]
        numbers = _floats(cells)
        if header_allowed and numbers is None:
            header_allowed = False
            continue  # a header line
        header_allowed = False
        message = _row_problem(cells, numbers, rows[-1] if rows else None)
        if message is None and numbers is not None:
            rows.append((lineno, numbers[0], numbers[1]))
            continue
        bad += 1
        if bad == 1:  # the file may not be the user's own: quote one short excerpt only
            message = f"{message}: {_excerpt(line)}"
        if bad <= MAX_ROW_PROBLEMS:
            problems.append(Problem(source, lineno, item, str(message)))
    if bad > MAX_ROW_PROBLEMS:
        problems.append(Problem(source, None, item, f"{bad} bad rows in all, the first {MAX_ROW_PROBLEMS} listed"))
    return rows, problems


def read_profile_csv(path: str | Path, *, item: str = "profile") -> ProfileIrregularity:
    """Read a measured alignment from a CSV file.

    Two columns: distance s [m], yR [m]; separated by commas (or semicolons, tabs,
    spaces). Blank lines and lines starting with ``#`` are skipped; the first other
    line may be a header (any non-numeric first line). Distances must be strictly
    increasing. Values are linearly interpolated
    (:class:`~express.rail.track.irregularity.ProfileIrregularity`).

    Parameters
    ----------
    path : str or Path
        The CSV file, a regular UTF-8 text file of at most :data:`MAX_PROFILE_BYTES`.
    item : str
        The item named in messages; default ``"profile"``.

    Raises
    ------
    ModelError
        One problem per bad row, ``<file>:<line>: <item>: <what is wrong>`` (the first
        :data:`MAX_ROW_PROBLEMS` rows, then a count; only the first quotes the row, at
        most :data:`EXCERPT_CHARS` characters), or one if the file cannot be read.
    """
    path = Path(path)
    source = str(path)
    text = _read_text(path, MAX_PROFILE_BYTES, item, "utf-8-sig")
    rows, problems = _profile_rows(text, source, item)
    if not problems and len(rows) < 2:
        problems.append(Problem(source, None, item, f"need at least two data rows, found {len(rows)}"))
    if not problems:
        distance = np.array([row[1] for row in rows])
        yr = np.array([row[2] for row in rows])
        field_problems = ProfileIrregularity.field_problems(distance, yr)
        problems += [Problem(source, None, item, message) for _, message in field_problems]
    if problems:
        raise ModelError(problems)
    for arr in (distance, yr):
        arr.setflags(write=False)
    return ProfileIrregularity(distance, yr, source=source)
