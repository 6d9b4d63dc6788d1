"""``express twist``: the quasi-static wheel unloading ``dQ/Q0`` of a vehicle passing a
twisted track (:mod:`express.analysis.twist`, ``docs/track.md``, "Twisted track")."""

from __future__ import annotations

import argparse
from pathlib import Path

from express.base.diagnostics import UsageError
from express.cli import common

__all__ = ["add_parser", "run"]

LENGTH = common.Quantity("--length", "length", "m", 0.1, 10000.0, open_low=True)
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
        "twist", help="quasi-static wheel unloading dQ/Q0 on a twisted track",
        description="The static solution K q = P u of the linear vehicle at every position along a cross-level ramp "
        "(--twist mm/m over --length, or the track file of --track), and each wheel's load change from the model's "
        "wheel-on-rail springs: the largest unloading -dQ/Q0 of every wheel and where. The model needs per-rail "
        "grounds (<W>_railL, <W>_railR) for the twist to reach its wheels. No limit is applied. See docs/track.md.",
    )
    common.add_model_arguments(parser)
    parser.add_argument("--twist", type=_twist, default=0.003, metavar="MM_PER_M",
                        help="gradient of the cross level [mm/m], + the right rail rising; default 3")
    parser.add_argument("--length", type=LENGTH, default=30.0, metavar="LENGTH",
                        help=LENGTH.help("length of the ramp", "30 m"))
    parser.add_argument("--track", type=Path, metavar="FILE", help="a track file instead of the ramp (docs/track.md)")
    parser.add_argument("--step", type=STEP, default=0.5, metavar="STEP",
                        help=STEP.help("distance between the positions", "0.5 m"))
    common.add_json_option(parser)
    parser.set_defaults(handler=run, numeric=True)


def run(model: Path, overrides: dict[str, str], *, twist: float = 0.003, length: float = 30.0,
        track: Path | None = None, step: float = 0.5, as_json: bool = False) -> int:
    """Print the largest unloading of every wheel; returns the exit status."""
    import warnings

    import numpy as np

    from express.analysis.time.track_inputs import ground_plan
    from express.analysis.twist import twist_passage, twisted_track

    vehicle = common.load_rail_vehicle(model, overrides, "twist")
    road = common.load_track(track) if track is not None else twisted_track(twist, length)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ignored = ground_plan(vehicle, road).ignored
    if "cross_level" in ignored or "cross_level" not in road.applied_components:
        why = ("the track has no cross level" if "cross_level" not in road.applied_components
               else f"{model}: the model takes no cross level (no per-rail grounds <W>_railL, <W>_railR)")
        raise UsageError(f"twist: {why}: a twist does not reach the wheels (docs/track.md, 'Twisted track')")
    distance, delta, wheel_load = twist_passage(vehicle, road, step)
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
                           f"twist ramp {twist * 1e3:g} mm/m over {length:g} m", "step": step, "wheels": rows,
                           "largest_unloading": worst["unloading"], "limit": None})
        return 0
    title = str(track) if track else f"twist ramp {twist * 1e3:g} mm/m over {length:g} m"
    print(f"{vehicle.name} on {title} (quasi-static, K q = P u every {step:g} m)")
    print(f"{'wheelset':>8}  {'wheel':>5}  {'-dQ/Q0':>7}  {'dQ [kN]':>8}  {'Q0 [kN]':>7}  {'at [m]':>7}")
    for row in rows:
        print(f"{row['wheelset']:>8}  {row['wheel']:>5}  {row['unloading']:7.4f}  {row['delta_q'] / 1e3:8.3f}  "
              f"{row['q0'] / 1e3:7.2f}  {row['at']:7.1f}")
    print(f"largest unloading {worst['unloading']:.4f} ({worst['wheelset']} {worst['wheel']}); no limit applied")
    return 0
