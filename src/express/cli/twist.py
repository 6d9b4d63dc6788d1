"""``express twist``: the quasi-static wheel unloading ``dQ/Q0`` of a vehicle on EN 14363's
combined twist (the default), or passing a cross-level ramp or a track file, and with
``--assess`` the derailment-on-twist assessment (:mod:`express.analysis.twist`,
``docs/track.md``, "Twisted track"); a failed assessment exits 3."""

from __future__ import annotations

import argparse
import math
import sys
from collections.abc import Sequence
from pathlib import Path

from express.base.diagnostics import EXIT_ASSESSMENT, UsageError
from express.cli import common
from express.cli.runner import run_command

__all__ = ["add_parser", "main", "run"]

LENGTH = common.Quantity("--length", "length", "m", 0.1, 10000.0, open_low=True)
RADIUS = common.Quantity("--radius", "length", "m", 50.0, 10000.0)
STEP = common.Quantity("--step", "length", "m", 0.01, 10.0)


def _twist(text: str) -> float:
    """``--twist`` in mm/m (a bare number), to m/m."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r}: give the gradient of the cross level in mm/m, e.g. 3") from None
    if not (-100.0 <= value <= 100.0) or value == 0:
        raise argparse.ArgumentTypeError(f"{text}: must be non-zero and at most 100 mm/m in size")
    return value * 1e-3


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser(
        "twist", help="quasi-static wheel unloading dQ/Q0 on a twisted track; --assess: derailment on twist",
        description="The static solution K q = P u of the linear vehicle on a twist and each wheel's load change from "
        "the model's wheel-on-rail springs; for a vehicle with friction elements or characteristics, a slow time run "
        "(1 m/s) onto the twist, the friction slipping. By default the vehicle stands on EN 14363's combined twist (g* = g_lim(2a*) "
        "over its bogie centres, g+ = g_lim(2a+) over the leading bogie's wheelbase); --twist mm/m (over --length) or "
        "--track FILE runs a passage instead. --assess checks the largest unloading against 0.6 and the leading outer "
        "wheel's Y/Q in a 150 m curve on the twist against Nadal (mu 0.36); a failed assessment exits 3. "
        "See docs/track.md, 'Twisted track'.",
    )
    common.add_model_arguments(parser)
    parser.add_argument("--twist", type=_twist, default=None, metavar="MM_PER_M",
                        help="a cross-level ramp of this gradient [mm/m], + the right rail rising, instead of the "
                        "standard twist")
    parser.add_argument("--length", type=LENGTH, default=None, metavar="LENGTH",
                        help=LENGTH.help("length of the ramp", "30 m"))
    parser.add_argument("--track", type=Path, metavar="FILE", help="a track file instead of the ramp (docs/track.md)")
    parser.add_argument("--step", type=STEP, default=0.5, metavar="STEP",
                        help=STEP.help("distance between the positions of a passage", "0.5 m"))
    parser.add_argument("--body-twist", type=_twist, default=None, metavar="MM_PER_M",
                        help="g* of the standard twist [mm/m] instead of g_lim(2a*)")
    parser.add_argument("--bogie-twist", type=_twist, default=None, metavar="MM_PER_M",
                        help="g+ of the standard twist [mm/m] instead of g_lim(2a+)")
    parser.add_argument("--assess", action="store_true",
                        help="EN 14363 derailment on twist: -dQ/Q0 against 0.6 and the flange climb; exit 3 if it fails")
    parser.add_argument("--no-climb", dest="climb", action="store_false",
                        help="with --assess, leave out the flange-climb check (the curving run)")
    parser.add_argument("--radius", type=RADIUS, default=150.0, metavar="RADIUS",
                        help=RADIUS.help("radius of the flange-climb curve", "150 m"))
    common.add_json_option(parser)
    parser.set_defaults(handler=run, numeric=True)


def run(model: Path, overrides: dict[str, str], *, twist: float | None = None, length: float | None = None,
        track: Path | None = None, step: float = 0.5, body_twist: float | None = None,
        bogie_twist: float | None = None, assess: bool = False, climb: bool = True, radius: float = 150.0,
        as_json: bool = False) -> int:
    """Print the unloading of every wheel (and the assessment); returns the exit status."""
    passage = twist is not None or length is not None or track is not None
    if passage and (assess or body_twist is not None or bogie_twist is not None):
        raise UsageError("twist: --assess, --body-twist and --bogie-twist take the standard twist; leave out "
                         "--twist, --length and --track")
    if track is not None and twist is not None:
        raise UsageError("twist: give --twist or --track, not both")
    vehicle = common.load_rail_vehicle(model, overrides, "twist")
    if passage:
        return _passage(vehicle, model, 0.003 if twist is None else twist, 30.0 if length is None else length,
                        track, step, as_json)
    from express.analysis.twist import assess_twist, standard_twist

    shape = standard_twist(vehicle, body_twist, bogie_twist)
    found = assess_twist(vehicle, shape, climb=assess and climb, radius=radius)
    if as_json:
        common.print_json({"command": "twist", "model": str(model), "standard_twist": shape.describe(),
                           "assessed": assess} | found.as_dict())
    else:
        _print_standard(vehicle, found, assess)
    if not assess or found.passed:
        return 0
    failed = [c.name for c in found.assessment.criteria if c.passed is False]
    common.note(f"error: twist: the assessment fails: {', '.join(failed)} beyond their limits")
    return EXIT_ASSESSMENT


def _print_standard(vehicle, found, assess: bool) -> None:
    print(f"{vehicle.name} on the standard twist: {found.twist.describe()} ({found.method})")
    print(f"{'wheelset':>8}  {'c [mm]':>7}  {'-dQ/Q0 L':>8}  {'-dQ/Q0 R':>8}  {'Q0 [kN]':>7}")
    for i, w in enumerate(vehicle.wheelsets):
        ratio = -found.delta_q[i] / found.wheel_load[i]
        print(f"{w.name:>8}  {found.twist.cross_level[i] * 1e3:7.2f}  {ratio[0]:8.4f}  {ratio[1]:8.4f}  "
              f"{found.wheel_load[i] / 1e3:7.2f}")
    if found.climb is not None:
        c = found.climb
        print(f"flange climb, {c.wheel}: Y/Q {c.y_over_q_curve:.3f} in the curve (Q {c.q_curve / 1e3:.2f} kN, "
              f"{c.source}), with dQ {c.delta_q / 1e3:.2f} kN on the twist "
              + (f"Y/Q {c.y_over_q:.3f}" if math.isfinite(c.y_over_q) else "the wheel lifts (Q + dQ <= 0)"))
    if not assess:
        print("no limit applied (--assess applies them)")
        return
    for c in found.assessment.criteria:
        value = f"{c.value:.4g}" if math.isfinite(c.value) else "lifts"
        print(f"{'pass' if c.passed else 'FAIL'}  {c.name}: {value} against {c.limit:.4g} ({c.quantity})")
    if found.assessment.derailment:
        print(f"derailment: {found.assessment.derailment}")


def _passage(vehicle, model: Path, twist: float, length: float, track: Path | None, step: float,
             as_json: bool) -> int:
    """The largest unloading of every wheel along a ramp or a track file."""
    import numpy as np

    from express.analysis.twist import twist_passage, twisted_track
    from express.analysis.twist.assessment import STATIC_METHOD
    from express.analysis.twist.passage import run_passage, slips

    road = common.load_track(track) if track is not None else twisted_track(twist, length)
    if "cross_level" not in road.applied_components:
        raise UsageError("twist: the track has no cross level: a twist does not reach the wheels "
                         "(docs/track.md, 'Twisted track')")
    if slips(vehicle):  # friction elements or characteristics: a slow time run
        distance, delta, wheel_load, found = run_passage(vehicle, road, step)
        method = found.method
    else:
        distance, delta, wheel_load = twist_passage(vehicle, road, step)
        method = STATIC_METHOD
    ratio = delta / wheel_load[None, :, None]
    rows = []
    for i, w in enumerate(vehicle.wheelsets):
        for side, name in enumerate(("left", "right")):
            if np.all(np.isnan(ratio[:, i, side])):
                continue
            k = int(np.nanargmin(ratio[:, i, side]))
            rows.append({"wheelset": w.name, "wheel": name, "unloading": float(max(0.0, -ratio[k, i, side])),
                         "delta_q": float(delta[k, i, side]), "q0": float(wheel_load[i]), "at": float(distance[k])})
    worst = max(rows, key=lambda row: row["unloading"])
    if as_json:
        common.print_json({"command": "twist", "model": str(model), "track": str(track) if track else
                           f"twist ramp {twist * 1e3:g} mm/m over {length:g} m", "step": step, "method": method, "wheels": rows,
                           "largest_unloading": worst["unloading"], "limit": None})
        return 0
    title = str(track) if track else f"twist ramp {twist * 1e3:g} mm/m over {length:g} m"
    print(f"{vehicle.name} on {title} ({method}, every {step:g} m)")
    print(f"{'wheelset':>8}  {'wheel':>5}  {'-dQ/Q0':>7}  {'dQ [kN]':>8}  {'Q0 [kN]':>7}  {'at [m]':>7}")
    for row in rows:
        print(f"{row['wheelset']:>8}  {row['wheel']:>5}  {row['unloading']:7.4f}  {row['delta_q'] / 1e3:8.3f}  "
              f"{row['q0'] / 1e3:7.2f}  {row['at']:7.1f}")
    print(f"largest unloading {worst['unloading']:.4f} ({worst['wheelset']} {worst['wheel']}); no limit applied")
    return 0


def main(argv: Sequence[str] | None = None) -> int:
    """``express twist`` with ``argv`` (default ``sys.argv[1:]``) alone: its exit status
    (:func:`express.cli.runner.run_command`, the parsing and errors of :func:`express.cli.main`)."""
    return run_command(sys.modules[__name__], argv)
