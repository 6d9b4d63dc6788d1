"""Options shared by the commands: the model and ``--set``, quantities with units and
their valid ranges, output paths, and the loaders that turn them into library objects.

The quantity rule (``docs/cli.md``): a number with a unit is checked against the
option's dimension; a bare number is SI, except speeds (km/h, rail usage) and the
irregularity amplitude (mm, as documented since the first release).  Every numeric
option has a valid range, checked while the command line is parsed, before any work;
the message names the option and the range.

Nothing heavy is imported here at module level: ``express --help`` stays quick.
"""

from __future__ import annotations

import argparse
import math
import re
import sys
from collections.abc import Callable
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

from express.analysis.stability.critical_options import CriticalOptions
from express.base.diagnostics import UsageError
from express.base.names import did_you_mean
from express.base.units import KMH

__all__ = [
    "AMPLITUDE",
    "DT",
    "ELEMENT_AMPLITUDE",
    "ELEMENT_ANGLE",
    "ELEMENT_FREQUENCY",
    "FMAX",
    "FMIN",
    "LINEARISATIONS",
    "SEARCH",
    "SPEED",
    "TOLERANCE",
    "VMAX",
    "VMIN",
    "Quantity",
    "add_json_option",
    "add_linearisation_arguments",
    "add_model_arguments",
    "add_search_arguments",
    "count",
    "figure_path",
    "join_negative_values",
    "linearisation",
    "linearisation_spec",
    "linearised_vehicle",
    "load_rail_vehicle",
    "note",
    "note_linearisation",
    "print_json",
    "require_package",
    "running_speed",
]

#: Options whose value may start with a minus sign followed by a digit (``--y-range
#: -10:10:0.5``): argparse takes such a token for an option unless it is a plain number.
NEGATIVE_VALUE_OPTIONS = ("--y-range", "--cant-deficiency", "--cant")
_NEGATIVE_START = re.compile(r"-\.?\d")


def join_negative_values(argv: list[str]) -> list[str]:
    """``["--y-range", "-10:10:0.5"]`` -> ``["--y-range=-10:10:0.5"]`` for the options of
    :data:`NEGATIVE_VALUE_OPTIONS`; every other token unchanged.

    Examples
    --------
    >>> join_negative_values(["contact-geometry", "S1002", "60E1", "--y-range", "-5:5:1"])
    ['contact-geometry', 'S1002', '60E1', '--y-range=-5:5:1']
    """
    out: list[str] = []
    tokens = iter(argv)
    for token in tokens:
        if token == "--":
            out.append(token)
            out.extend(tokens)
            break
        if token in NEGATIVE_VALUE_OPTIONS:
            following = next(tokens, None)
            if following is not None and _NEGATIVE_START.match(following):
                out.append(f"{token}={following}")
                continue
            out.append(token)
            if following is not None:
                out.append(following)
            continue
        out.append(token)
    return out


_BARE_NUMBER = re.compile(r"\s*[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?\s*\Z")
_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")


@dataclass(frozen=True)
class Quantity:
    """A command-line quantity: its dimension, the unit of a bare number and its range.

    Calling it converts the text of the option to SI (the ``type=`` of argparse).

    Attributes
    ----------
    option : str
        The option's name, for messages (``--speed``).
    dimension : str
        Expected dimension (a name of :mod:`express.base.units`, e.g. ``"speed"``).
    bare_unit : str
        Unit of a number given without one (``"km/h"``, ``"s"``).
    low, high : float
        Valid range in ``bare_unit``; ``low`` is excluded when ``open_low``.
    open_low : bool
        The range is ``low < x <= high`` rather than ``low <= x <= high``.
    """

    option: str
    dimension: str
    bare_unit: str
    low: float
    high: float
    open_low: bool = False

    @property
    def range_text(self) -> str:
        sign = "<" if self.open_low else "<="
        return f"{self.low:g} {sign} {self.option} <= {self.high:g} {self.bare_unit}"

    def help(self, what: str, default: str | None = None) -> str:
        """Help text: what it is, the unit of a bare number, the range and the default."""
        tail = f"; default {default}" if default else ""
        return f"{what} [bare number: {self.bare_unit}; or with a unit]; {self.range_text}{tail}"

    def __call__(self, text: str) -> float:
        from express.base.units import to_si, unit_factor

        try:
            if _BARE_NUMBER.match(text):
                value = to_si(float(text), self.bare_unit)
            else:
                value = _parse_with_unit(text, self.dimension)
        except (ValueError, OverflowError, ArithmeticError) as error:
            raise argparse.ArgumentTypeError(f'"{text}": {error}') from None
        low = self.low * unit_factor(self.bare_unit)
        high = self.high * unit_factor(self.bare_unit)
        inside = (low < value if self.open_low else low <= value) and value <= high
        if not (math.isfinite(value) and inside):
            raise argparse.ArgumentTypeError(f'"{text}" is outside the valid range {self.range_text}')
        return value


def _parse_with_unit(text: str, dimension: str) -> float:
    """``"30 m/s"`` -> 30.0, refusing a unit of another dimension."""
    from express.base.units import parse_quantity

    value, _unit = parse_quantity(text, dimension)
    return float(value)


SPEED = Quantity("--speed", "speed", "km/h", 0.0, 1000.0, open_low=True)
VMIN = Quantity("--vmin", "speed", "km/h", 0.0, 1000.0, open_low=True)
VMAX = Quantity("--vmax", "speed", "km/h", 0.0, 1000.0, open_low=True)
TOLERANCE = Quantity("--tolerance", "speed", "km/h", 1e-3, 100.0)
#: The critical-speed search's defaults (one set, SI: :class:`CriticalOptions`).
SEARCH = CriticalOptions()


def add_search_arguments(parser: argparse.ArgumentParser, tolerance: bool = False) -> None:
    """``--vmin``, ``--vmax`` (and ``--tolerance``) of a critical-speed search, with the
    defaults of :data:`SEARCH`."""
    parser.add_argument("--vmin", type=VMIN, default=SEARCH.v_min, metavar="SPEED",
                        help=VMIN.help("lowest speed scanned", f"{SEARCH.v_min / KMH:g} km/h"))
    parser.add_argument("--vmax", type=VMAX, default=SEARCH.v_max, metavar="SPEED",
                        help=VMAX.help("highest speed scanned, above --vmin", f"{SEARCH.v_max / KMH:g} km/h"))
    if tolerance:
        parser.add_argument("--tolerance", type=TOLERANCE, default=SEARCH.tolerance, metavar="SPEED",
                            help=TOLERANCE.help("width of the final bisection bracket", f"{SEARCH.tolerance / KMH:g} km/h"))
FMIN = Quantity("--fmin", "frequency", "Hz", 1e-4, 1000.0)
FMAX = Quantity("--fmax", "frequency", "Hz", 1e-4, 1000.0)
AMPLITUDE = Quantity("--amplitude", "length", "mm", 0.0, 100.0, open_low=True)
DT = Quantity("--dt", "time", "s", 1e-5, 0.1)


def count(option: str, low: int, high: int) -> Callable[[str], int]:
    """An integer option with its range (the ``type=`` of argparse)."""

    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f'"{text}" is not a whole number') from None
        if not low <= value <= high:
            raise argparse.ArgumentTypeError(f"{value} is outside the valid range {low} <= {option} <= {high}")
        return value

    parse.__name__ = option.lstrip("-")  # argparse names the type in some messages
    return parse


# --------------------------------------------------------------------------------------
# the model and --set
# --------------------------------------------------------------------------------------


class _Assignments(argparse.Action):
    """``--set NAME=TEXT`` (repeatable) -> ``{NAME: TEXT}``, the last one winning.

    The text is kept as written, marked as typed on the command line
    (:class:`express.model.parameters.CommandLineText`): the library converts it with the
    parameter's dimension, a bare speed in km/h, everything else SI.
    """

    def __call__(self, parser, namespace, values, option_string=None):
        item = str(values)
        name, sep, text = item.partition("=")
        name, text = name.strip(), text.strip()
        if not sep or not _NAME.match(name) or not text:
            raise argparse.ArgumentError(self, f'"{item}": expected NAME=VALUE, e.g. --set Gamma=0.05 or --set "v=100 km/h"')
        from express.model.parameters import CommandLineText

        assignments = dict(getattr(namespace, self.dest, None) or {})
        assignments[name] = CommandLineText(text)
        setattr(namespace, self.dest, assignments)


def add_model_arguments(parser: argparse.ArgumentParser) -> None:
    """The model file and ``--set NAME=VALUE`` (handlers receive ``model`` and ``overrides``)."""
    parser.add_argument("model", type=Path, help="model file: classic (.exp) or modern (.toml)")
    parser.add_argument(
        "--set", dest="overrides", action=_Assignments, default={}, metavar="NAME=VALUE",
        help="override a parameter, e.g. --set Gamma=0.05 --set 'mc=35 t' (repeatable); "
        "a bare number is SI, except a speed (km/h: --set v=100)",
    )


def add_json_option(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--json", dest="as_json", action="store_true", help="print a JSON summary (SI units)")


def require_package(module: str, extra: str, purpose: str) -> None:
    """Refuse, before any work, a command that needs an optional package not installed:
    ``--format fmu needs the optional package pythonfmu: pip install 'express[interop]'``.

    Raises
    ------
    UsageError
        When ``module`` cannot be imported.
    """
    import importlib.util

    try:
        found = importlib.util.find_spec(module) is not None
    except (ImportError, ValueError):
        found = False
    if not found:
        raise UsageError(f"{purpose} needs the optional package {module}: pip install 'express[{extra}]'")


def figure_path(text: str) -> Path:
    """``--plot FILE``: a figure file by suffix (the ``type=`` of argparse)."""
    from express.analysis.plots import FIGURE_SUFFIXES

    path = Path(text)
    if path.suffix.lower() not in FIGURE_SUFFIXES:
        raise argparse.ArgumentTypeError(f"{text}: unknown figure format; use {', '.join(FIGURE_SUFFIXES)}")
    return path


def load_rail_vehicle(model: Path, overrides: dict[str, str], command: str) -> Any:
    """The numerical vehicle of ``model`` with ``overrides`` (read once), which must
    have rail data.

    Raises
    ------
    ModelError
        A bad file or override.
    UsageError
        The model has no rail data.
    """
    from express.numeric.statespace import load_vehicle

    vehicle = load_vehicle(model, overrides)
    if vehicle.layout is None or not vehicle.wheelsets:
        raise UsageError(
            f"{command}: {model}: the model has no rail data (no [rail] section with wheelsets); "
            "only `express generate` applies to it"
        )
    return vehicle


def add_creep_law_argument(parser: argparse.ArgumentParser) -> None:
    """``--creep-law`` of the commands that run the nonlinear contact from profiles."""
    from express.rail.options import CREEP_LAWS

    parser.add_argument("--creep-law", choices=CREEP_LAWS, default=None,
                        help="with the contact from profiles: the creep law (default table: the tables of the exact "
                             "theory; fastsim, polach; docs/contact.md)")


def creep_law_options(vehicle: Any, creep_law: str | None, *, nonlinear: bool, contact: str | None = None) -> dict:
    """``{"creep_law": creep_law}`` for the library's call, ``{}`` without ``--creep-law``;
    a :class:`~express.base.diagnostics.UsageError` where no creep law applies (a linear
    run, the dead-band contact, a model without profiles)."""
    if creep_law is None:
        return {}
    from express.rail.profile_contact import profile_nodes

    if not nonlinear:
        raise UsageError("--creep-law is for the nonlinear contact: drop --linear or --creep-law")
    if contact == "deadband":
        raise UsageError("--creep-law is for the contact from profiles: the dead-band contact has its own saturation")
    if vehicle.model is None or not profile_nodes(vehicle.model):
        raise UsageError("--creep-law is for the contact from profiles: the model's wheelsets have none "
                         "(docs/contact.md)")
    return {"creep_law": creep_law}


#: The linearisations of :data:`express.forces.linearisation.KINDS` (for --help without
#: importing NumPy; a test keeps the two equal).
LINEARISATIONS = ("tangent", "equivalent", "statistical")
ELEMENT_AMPLITUDE = Quantity("--element-amplitude", "length", "mm", 0.0, 1000.0, open_low=True)
ELEMENT_ANGLE = Quantity("--element-angle", "angle", "mrad", 0.0, 1000.0, open_low=True)
ELEMENT_FREQUENCY = Quantity("--element-frequency", "frequency", "Hz", 0.0, 1000.0, open_low=True)


def add_linearisation_arguments(parser: argparse.ArgumentParser, statistical: bool = False) -> None:
    """``--linearisation`` of the nonlinear elements and the amplitude, angle and frequency
    of ``equivalent`` (handlers receive ``linearisation``, ``element_amplitude``,
    ``element_angle``, ``element_frequency``; :func:`linearised_vehicle` applies them)."""
    kinds = LINEARISATIONS if statistical else LINEARISATIONS[:2]
    parser.add_argument("--linearisation", choices=kinds, default="tangent",
                        help="how this linear analysis sees the friction elements and characteristics: tangent at "
                        "the static state (friction stuck; default), equivalent (describing functions at "
                        "--element-amplitude/--element-angle and --element-frequency)"
                        + (", statistical (Gaussian, at each element's own rms response, iterated)" if statistical
                           else "") + "; docs/analyses.md")
    parser.add_argument("--element-amplitude", type=ELEMENT_AMPLITUDE, metavar="X",
                        help=ELEMENT_AMPLITUDE.help("equivalent: deflection amplitude of the translational elements",
                                                    "1 mm"))
    parser.add_argument("--element-angle", type=ELEMENT_ANGLE, metavar="A",
                        help=ELEMENT_ANGLE.help("equivalent: deflection amplitude of the rotational elements", "1 mrad"))
    parser.add_argument("--element-frequency", type=ELEMENT_FREQUENCY, metavar="F",
                        help=ELEMENT_FREQUENCY.help("equivalent: frequency of the harmonic motion", "2 Hz"))


def linearisation_spec(linearisation: str = "tangent", element_amplitude: float | None = None,
                       element_angle: float | None = None, element_frequency: float | None = None) -> Any:
    """The :class:`express.forces.linearisation.Linearisation` the options ask for.

    Raises
    ------
    UsageError
        An amplitude, angle or frequency without ``--linearisation equivalent``.
    """
    given = [name for name, value in (("--element-amplitude", element_amplitude), ("--element-angle", element_angle),
                                      ("--element-frequency", element_frequency)) if value is not None]
    if given and linearisation != "equivalent":
        raise UsageError(f"{', '.join(given)}: the amplitude and frequency of --linearisation equivalent")
    from express.forces.linearisation_choice import Linearisation

    default = Linearisation(linearisation)
    return Linearisation(linearisation,
                         amplitude=default.amplitude if element_amplitude is None else element_amplitude,
                         angle=default.angle if element_angle is None else element_angle,
                         frequency=default.frequency if element_frequency is None else element_frequency)


def linearised_vehicle(vehicle: Any, spec: Any) -> Any:
    """``vehicle`` seen as ``spec`` says (:func:`express.forces.linearisation.linearised`;
    ``statistical`` is the ride's own iteration, not applied here)."""
    if spec.kind != "equivalent":
        return vehicle
    from express.forces.linearisation import linearised

    return linearised(vehicle, spec)


def linearisation(vehicle: Any) -> dict[str, str]:
    """How the linear analyses see the model's nonlinear elements, by element (empty when
    it has none): friction elements stuck, their pre-slip springs in K (the tangent at
    the static state, ``docs/model-format.md``, "Friction elements"); characteristics
    their tangents at the static state in K or C ("Nonlinear characteristics"); a
    linearised vehicle (``--linearisation``) its equivalent values."""
    spec = getattr(vehicle, "linearisation", None)
    if spec is not None:
        return {e.element: f"{spec.describe()}: {e.describe().split(': ', 1)[1]}" for e in vehicle.elements}
    facts = vehicle.facts
    seen = dict.fromkeys(facts.stuck, "stuck (pre-slip spring in K: the tangent at the static state)")
    for element, matrix in facts.tangents:  # from the facts: a warm command derives nothing
        rate = matrix == "C"
        seen[element] = (f"tangent at the static state (the characteristic's slope at zero "
                         f"{'velocity' if rate else 'deflection'}, in {matrix})")
    return seen


def note_linearisation(vehicle: Any) -> dict[str, str]:
    """:func:`linearisation`, said once on standard error when there is anything to say."""
    seen = linearisation(vehicle)
    spec = getattr(vehicle, "linearisation", None)
    if spec is not None:
        groups: dict[str, list[str]] = {}  # elements seen alike, said once
        for e in vehicle.elements:
            groups.setdefault(e.describe().split(": ", 1)[1], []).append(e.element)
        shown = "; ".join(f"{names[0]}{f' (and {len(names) - 1} alike)' if len(names) > 1 else ''}: {text}"
                          for text, names in groups.items())
        note(f"nonlinear elements seen by this linear analysis as {spec.describe()}: {shown}")
        return seen
    stuck = [name for name, text in seen.items() if text.startswith("stuck")]
    tangents = [name for name in seen if name not in stuck]
    if stuck:
        note(f"friction elements seen stuck by this linear analysis (their pre-slip springs in K, the tangent at "
             f"the static state): {', '.join(stuck)}")
    if tangents:
        note(f"nonlinear characteristics seen by this linear analysis as their tangents at the static state "
             f"(slope at zero deflection or velocity, in K or C): {', '.join(tangents)}")
    return seen


def running_speed(vehicle: Any, speed: float | None) -> float:
    """``--speed`` if given, else the model's own speed, checked against :data:`SPEED`'s range [m/s]."""
    if speed is not None:
        return speed
    own = float(vehicle.speed)
    if not math.isfinite(own):
        raise UsageError("the model has no speed: give one with --speed KMH (or --set v=...)")
    if not 0 < own <= SPEED.high * KMH:
        raise UsageError(
            f"the model's speed {own / KMH:g} km/h is outside the valid range {SPEED.range_text}; give --speed"
        )
    return own


def load_track(path: Path | None) -> Any:
    """The track of ``--track`` (default: the paper's curve)."""
    from express.rail.track import load_track as read_track
    from express.rail.track import paper_curve

    if path is None:
        return paper_curve()
    return read_track(path)


def track_and_name(text: str | Path | None) -> tuple[Any, str]:
    """The track of ``--track`` and how to name it in outputs: a bundled name (``R250``,
    ``R400``, ``R600``, ``R1000``, ``R3000``, ``paper``; :mod:`express.rail.track.named`)
    or a track file; none given: the paper's curve, said so."""
    from express.rail.track import load_track as read_track
    from express.rail.track.named import NAMED_CURVES, named_track

    if text is None:  # the paper's layout, at the model's speed (the track carries none)
        road, _ = named_track("paper")
        return (replace(road, speed=None),
                "no --track given: the paper's Fig. 9 curve (R = 400 m left curve, 95 mm cant, 95 m sine transitions, "
                "170 m circular)")
    name = str(text)
    if name in NAMED_CURVES or name == "paper":
        road, description = named_track(name)
        return road, f"bundled track {name}: {description}"
    if "." not in Path(name).name and not Path(name).exists():
        raise UsageError(f"--track {name}: no such file, and not a bundled track{did_you_mean(name, [*NAMED_CURVES, 'paper'])} "
                         f"({', '.join([*NAMED_CURVES, 'paper'])})")
    return read_track(Path(name)), f"track file {name}"


# --------------------------------------------------------------------------------------
# printing
# --------------------------------------------------------------------------------------


def note(message: str) -> None:
    """A progress or ``wrote FILE`` line on standard error."""
    print(message, file=sys.stderr)


def print_json(data: dict) -> None:
    """``data`` as indented JSON on standard output (NumPy values converted, nan -> null)."""
    from express.io.text_formats import json_text

    sys.stdout.write(json_text(data))


def is_terminal(stream: Any) -> bool:
    try:
        return bool(stream.isatty())
    except (AttributeError, ValueError):
        return False


def load_model_with(model: Path, overrides: dict[str, str]) -> Any:
    """The model read once with ``overrides`` applied (``generate``, ``convert``).

    Raises
    ------
    ModelError
        A bad file or override (every problem at once).
    """
    from express.io import load_model
    from express.model.parameters import with_values

    loaded = load_model(model)
    return with_values(loaded, overrides) if overrides else loaded


def print_warnings(warnings: Any) -> None:
    for warning in warnings:
        print(f"warning: {warning}", file=sys.stderr)
