"""The route of a wear prediction: a distribution of curves, speeds and cant deficiencies,
each with its share of the distance run (``docs/wear.md``, "The route file").

A route file is TOML::

    [route]
    name = "mixed main line"          # optional

    [[case]]
    radius = "400 m"                  # omit (or "straight") for straight track
    cant = "100 mm"                   # default 0
    speed = "100 km/h"                # or cant_deficiency = "0.8 m/s^2"
    share = 0.25                      # of the distance; all shares sum to 1
    track = "erri_low"                # optional: run on this random alignment (a time run)
    run_length = "500 m"              # of the random track read (default 500 m)
    seed = 0                          # of the random phases (default 0)

Quantities take a unit; a bare number is SI (a speed in m/s: a file is not the command
line).  :func:`read_route` reports every problem at once, each with its file, line and
item (:class:`~express.base.diagnostics.ModelError`); :func:`route_problems` adds those
that need the vehicle (a speed that asks for more unbalanced acceleration than a steady
curve may have).
"""

from __future__ import annotations

import hashlib
import math
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from express.base.diagnostics import ModelError, Problem
from express.base.names import did_you_mean
from express.base.units import UnitError, parse_quantity
from express.io.toml_lines import find_line, line_index, parse_toml

__all__ = ["CASE_KEYS", "SHARE_TOLERANCE", "Route", "RouteCase", "read_route", "route_problems", "route_text"]

#: The keys of a ``[[case]]``.
CASE_KEYS = ("name", "radius", "cant", "speed", "cant_deficiency", "share", "track", "run_length", "seed")
#: Default length of a random track's run that is read [m], and the longest allowed.
RUN_LENGTH, MAX_RUN_LENGTH = 500.0, 20_000.0
#: How far the shares' sum may be from 1.
SHARE_TOLERANCE = 1e-6
#: Most cases a route may have.
MAX_CASES = 500


@dataclass(frozen=True)
class RouteCase:
    """One case of a route.

    Attributes
    ----------
    name : str
    radius : float
        [m]; ``inf`` for straight track.
    cant : float
        [m], toward the curve's centre.
    speed : float or None
        [m/s], or None when given by ``cant_deficiency``.
    cant_deficiency : float or None
        Unbalanced lateral acceleration in the track plane [m/s^2] (negative: excess).
    share : float
        Share of the distance run [-].
    track : str or None
        Name of the random alignment spectrum
        (:data:`~express.rail.track.spectra.SPECTRA`) the case runs on as a time run
        (``docs/wear.md``, "Random track"); None: the steady state.
    run_length : float
        Length of the random track's run that is read [m].
    seed : int
        Seed of the random alignment's phases.
    line : int or None
        Line of its ``[[case]]`` in the file.
    """

    name: str
    radius: float
    cant: float
    speed: float | None
    cant_deficiency: float | None
    share: float
    line: int | None = None
    track: str | None = None
    run_length: float = RUN_LENGTH
    seed: int = 0

    @property
    def straight(self) -> bool:
        return math.isinf(self.radius)


@dataclass(frozen=True)
class Route:
    """A route read from ``source``: its ``cases`` and the SHA-256 of its text."""

    name: str
    cases: tuple[RouteCase, ...]
    source: str
    digest: str


def route_text(path: str | Path) -> str:
    """The route file's text (ModelError naming the file when it cannot be read)."""
    try:
        return Path(path).read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as error:
        raise ModelError([Problem(str(path), None, "route", f"cannot read the file ({error})")]) from None


def _quantity(value: Any, dimension: str, where: str, problems: list[Problem], source: str,
              line: int | None) -> float | None:
    if isinstance(value, bool) or not isinstance(value, (int, float, str)):
        problems.append(Problem(source, line, where, f"expected a {dimension} (a number or a text with a unit), "
                                                     f"got {value!r}"))
        return None
    if isinstance(value, (int, float)):
        number = float(value)
    else:
        try:
            number = parse_quantity(value, dimension)[0]
        except UnitError as error:
            problems.append(Problem(source, line, where, str(error)))
            return None
    if not math.isfinite(number):
        problems.append(Problem(source, line, where, f"{value!r} is not a finite {dimension}"))
        return None
    return number


def _case(entry: Any, number: int, index: dict, source: str, problems: list[Problem]) -> RouteCase | None:
    where = f"case {number}"
    line = find_line(index, ("case", number))
    if not isinstance(entry, dict):
        problems.append(Problem(source, line, where, "each case is a [[case]] table"))
        return None
    count = len(problems)
    for key in entry:
        if key not in CASE_KEYS:
            problems.append(Problem(source, find_line(index, ("case", number, key)), f"{where}: {key}",
                                    f"unknown key{did_you_mean(key, CASE_KEYS)} (a case has {', '.join(CASE_KEYS)})"))

    def at(key: str) -> int | None:
        return find_line(index, ("case", number, key))

    text = entry.get("radius", "straight")
    radius: float | None = math.inf
    if not (isinstance(text, str) and text.strip().lower() == "straight"):
        radius = _quantity(text, "length", f"{where}: radius", problems, source, at("radius"))
        if radius is not None and not radius > 0:
            problems.append(Problem(source, at("radius"), f"{where}: radius", f"must be positive, got {radius:g} m"))
    cant = _quantity(entry.get("cant", 0.0), "length", f"{where}: cant", problems, source, at("cant"))
    speed = deficiency = None
    if "speed" in entry:
        speed = _quantity(entry["speed"], "speed", f"{where}: speed", problems, source, at("speed"))
        if speed is not None and not speed > 0:
            problems.append(Problem(source, at("speed"), f"{where}: speed", f"must be positive, got {speed:g} m/s"))
    if "cant_deficiency" in entry:
        deficiency = _quantity(entry["cant_deficiency"], "acceleration", f"{where}: cant_deficiency", problems,
                               source, at("cant_deficiency"))
    if ("speed" in entry) == ("cant_deficiency" in entry) and radius is not None and math.isfinite(radius):
        problems.append(Problem(source, line, where, "give one of speed and cant_deficiency for a curve"
                                + (", not both" if "speed" in entry else "")))
    share = entry.get("share")
    if isinstance(share, bool) or not isinstance(share, (int, float)) or not 0.0 < float(share) <= 1.0:
        problems.append(Problem(source, at("share") or line, f"{where}: share",
                                f"a share of the distance in (0, 1] is needed, got {share!r}"))
    track, run_length, seed = _random_track(entry, where, at, source, problems)
    name = entry.get("name", f"case {number}")
    if not isinstance(name, str):
        problems.append(Problem(source, at("name"), f"{where}: name", f"expected a text, got {name!r}"))
    if len(problems) > count:
        return None
    assert radius is not None and cant is not None and isinstance(share, (int, float))
    return RouteCase(str(name), radius, cant, speed, deficiency, float(share), line, track, run_length, seed)


def _random_track(entry: dict, where: str, at: Callable[[str], int | None], source: str,
                  problems: list[Problem]) -> tuple[str | None, float, int]:
    """A case's ``track``, ``run_length`` and ``seed`` (problems appended)."""
    from express.rail.track.spectra import SPECTRA

    track = entry.get("track")
    if track is not None and (not isinstance(track, str) or track.strip().lower() not in SPECTRA):
        problems.append(Problem(source, at("track"), f"{where}: track",
                                f"a random alignment is one of {', '.join(SPECTRA)}, got {track!r}"
                                + (did_you_mean(track, tuple(SPECTRA)) if isinstance(track, str) else "")))
        track = None
    run_length = _quantity(entry.get("run_length", RUN_LENGTH), "length", f"{where}: run_length", problems, source,
                           at("run_length"))
    if run_length is not None and not 10.0 <= run_length <= MAX_RUN_LENGTH:
        problems.append(Problem(source, at("run_length"), f"{where}: run_length",
                                f"must be 10 m .. {MAX_RUN_LENGTH:g} m, got {run_length:g} m"))
    seed = entry.get("seed", 0)
    if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
        problems.append(Problem(source, at("seed"), f"{where}: seed", f"a whole number >= 0, got {seed!r}"))
        seed = 0
    for key in ("run_length", "seed"):
        if key in entry and "track" not in entry:
            problems.append(Problem(source, at(key), f"{where}: {key}", "belongs to a random track (track = \"...\")"))
    return (None if track is None else track.strip().lower()), float(run_length or RUN_LENGTH), int(seed)


def read_route(path: str | Path, text: str | None = None) -> Route:
    """The route of a route file (module docstring).

    Raises
    ------
    ModelError
        Every problem of the file at once, with its line: TOML syntax, unknown tables or
        keys, quantities of the wrong dimension, a curve without (or with both) speed and
        cant deficiency, shares outside (0, 1] or not summing to 1.
    """
    source = str(path)
    text = route_text(path) if text is None else text
    data = parse_toml(text, source)
    index = line_index(text, number_arrays=True)
    problems: list[Problem] = []
    for key in data:
        if key not in ("route", "case"):
            problems.append(Problem(source, find_line(index, (key,)), key,
                                    f"unknown table{did_you_mean(key, ('route', 'case'))}; a route has [route] and [[case]]"))
    head = data.get("route", {})
    name = head.get("name", Path(source).stem) if isinstance(head, dict) else Path(source).stem
    if not isinstance(head, dict) or any(key != "name" for key in head) or not isinstance(name, str):
        problems.append(Problem(source, find_line(index, ("route",)), "[route]", "holds only name = \"...\""))
    entries = data.get("case", [])
    if not isinstance(entries, list) or not entries:
        problems.append(Problem(source, None, "[[case]]", "a route needs at least one [[case]]"))
        entries = []
    if len(entries) > MAX_CASES:
        problems.append(Problem(source, None, "[[case]]", f"{len(entries)} cases, more than {MAX_CASES}"))
    cases = [_case(entry, number, index, source, problems) for number, entry in enumerate(entries, start=1)]
    shares = [entry.get("share") for entry in entries if isinstance(entry, dict)]
    numbers = [float(s) for s in shares if isinstance(s, (int, float)) and not isinstance(s, bool)]
    if len(numbers) == len(entries) and entries and abs(sum(numbers) - 1.0) > SHARE_TOLERANCE:
        problems.append(Problem(source, find_line(index, ("case", 1)), "share",
                                f"the shares sum to {sum(numbers):.9g}, not 1 (within {SHARE_TOLERANCE:g})"))
    if problems:
        raise ModelError(problems)
    digest = hashlib.sha256(text.encode("utf-8")).hexdigest()
    return Route(str(name), tuple(c for c in cases if c is not None), source, digest)


def route_problems(route: Route, cant_base: float, gravity: float) -> tuple[list[Problem], list[float | None]]:
    """The problems of ``route`` on a vehicle of ``cant_base`` [m] and ``gravity``
    [m/s^2] (a case no speed gives, or beyond the steady curve's unbalanced
    acceleration), and each case's speed [m/s] (None for straight track without one)."""
    from express.analysis.curving.steady import CurveError, SteadyCurve

    problems: list[Problem] = []
    speeds: list[float | None] = []
    for number, case in enumerate(route.cases, start=1):
        speed = case.speed
        if case.straight:
            if case.track is not None and speed is None:
                problems.append(Problem(route.source, case.line, f"case {number}",
                                        "a straight case on a random track (track = ...) needs its speed"))
            speeds.append(speed)
            continue
        curve = SteadyCurve(case.radius, case.cant)
        try:
            if speed is None:
                assert case.cant_deficiency is not None
                speed = curve.speed_for(case.cant_deficiency, cant_base, gravity)
            problems += [Problem(route.source, case.line, f"case {number}", message)
                         for message in curve.problems(speed, cant_base, gravity)]
        except CurveError as error:
            problems.append(Problem(route.source, case.line, f"case {number}", str(error)))
        speeds.append(speed)
    return problems, speeds
