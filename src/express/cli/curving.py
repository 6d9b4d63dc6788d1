"""``express curving``: the steady state of a vehicle in constant curves
(:mod:`express.analysis.curving.steady`), one curve or a sweep over radius, speed or cant
deficiency, with the wheel/rail outputs of ``docs/curving.md``."""

from __future__ import annotations

import argparse
import math
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from express.base.diagnostics import AnalysisError, UsageError
from express.cli import common
from express.cli.runner import run_command

__all__ = ["MAX_CURVES", "add_parser", "main", "quantities", "run"]

#: Most steady states one command computes.
MAX_CURVES = 2000
RADIUS = common.Quantity("--radius", "length", "m", 0.0, 1e6, open_low=True)
CANT = common.Quantity("--cant", "length", "mm", -500.0, 500.0)
DEFICIENCY = common.Quantity("--cant-deficiency", "acceleration", "m/s^2", -5.0, 5.0)


def quantities(quantity: common.Quantity):
    """``VALUE``, ``A,B,C`` or ``START:STOP:STEP`` (each with an optional unit, the
    bare unit of ``quantity`` otherwise) -> a list of SI values (the ``type=`` of argparse)."""

    def parse(text: str) -> list[float]:
        body, _, unit = text.strip().partition(" ")
        tail = f" {unit.strip()}" if unit.strip() else ""
        if body.count(":") == 2:
            start, stop, step = (quantity(part + tail) for part in body.split(":"))
            if not step > 0 or stop < start:
                raise argparse.ArgumentTypeError(f'"{text}": need STEP > 0 and STOP >= START')
            count = math.floor((stop - start) / step + 1e-9) + 1
            if count > MAX_CURVES:
                raise argparse.ArgumentTypeError(f'"{text}": {count} values, more than {MAX_CURVES}')
            return [start + k * step for k in range(count)]
        return [quantity(part + tail) for part in body.split(",")]

    parse.__name__ = quantity.option.lstrip("-")
    return parse


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser(
        "curving", help="steady-state curving: wheel loads, Y/Q, track shift force, angle of attack in constant curves",
        description="The equilibrium of the nonlinear vehicle in a constant curve, solved directly (not a time run): "
        "per wheel Q, Y, Y/Q, creep force, contact position and angle, flange contact; per wheelset the track shift "
        "force and the angle of attack; the vehicle's wheel unloading. Give --radius (and --cant, --speed), or "
        "--track for the circular curves of a track file or a bundled curve (R250, R400, R600, R1000, R3000, "
        "paper). A list A,B,C or a range START:STOP:STEP of radii, speeds or cant deficiencies gives a sweep. "
        "See docs/curving.md.",
    )
    common.add_model_arguments(parser)
    parser.add_argument("--radius", type=quantities(RADIUS), metavar="R", help=RADIUS.help("curve radius (a list or range sweeps)"))
    parser.add_argument("--cant", type=CANT, default=None, metavar="C", help=CANT.help("cant (rail height difference)", "0"))
    parser.add_argument("--direction", choices=("left", "right"), default="right", help="curve direction; default right")
    speed = parser.add_mutually_exclusive_group()
    speed.add_argument("--speed", type=quantities(common.SPEED), metavar="V",
                       help=common.SPEED.help("speed (a list or range sweeps)", "the track's, else the model's"))
    speed.add_argument("--cant-deficiency", type=quantities(DEFICIENCY), metavar="A",
                       help=DEFICIENCY.help("cant deficiency in the track plane, giving the speed in each curve "
                                            "(negative: excess; a list or range sweeps)"))
    parser.add_argument("--track", metavar="NAME|FILE", help="take the curves (and speed) from a track: a bundled name "
                        "(R250, R400, R600, R1000, R3000, paper) or a track file")
    parser.add_argument("--contact", choices=("tables", "deadband"), default=None,
                        help="wheel/rail contact: the profiles' tables (default when the model has profiles) or the "
                        "paper's dead-band flange and creep saturation")
    parser.add_argument("--linear", action="store_true", help="linear creep and no flange contact")
    common.add_creep_law_argument(parser)
    parser.add_argument("-o", "--output", metavar="FILE", help="every output of every curve as CSV (units in the header; - for standard output)")
    parser.add_argument("--plot", type=common.figure_path, metavar="FILE", help="the outputs against the sweep (.png, .svg or .pdf)")
    common.add_json_option(parser)
    parser.set_defaults(handler=run, numeric=True)


def run(
    model: Path, overrides: dict[str, str], *, radius: list[float] | None = None, cant: float | None = None,
    direction: str = "right", speed: list[float] | None = None, cant_deficiency: list[float] | None = None,
    track: str | None = None, contact: str | None = None, linear: bool = False, output: str | None = None,
    plot: Path | None = None, as_json: bool = False, creep_law: str | None = None,
) -> int:
    """Solve every curve and write the outputs together; returns the exit status."""
    from express.analysis.curving.settled import curving_or_settled
    from express.io.output import output_transaction, write_csv

    if output == "-" and as_json:
        raise UsageError("-o - and --json both write to standard output; choose one")
    if (radius is None) == (track is None):
        raise UsageError("curving: give --radius R (with --cant and --speed) or --track NAME|FILE")
    if track is not None and (cant is not None or direction != "right"):
        raise UsageError("curving: --cant and --direction come from the track; give them only with --radius")
    inputs = [model] + ([Path(track)] if track is not None and Path(track).is_file() else [])
    with output_transaction(inputs) as transaction:
        for path, binary in ((output, False), (plot, True)):
            if path is not None:
                transaction.declare(path, binary=binary)
        vehicle = common.load_rail_vehicle(model, overrides, "curving")
        curves, speeds, where = _cases(vehicle, radius, cant or 0.0, direction, speed, cant_deficiency, track)
        law = common.creep_law_options(vehicle, creep_law, nonlinear=not linear, contact=contact)
        found = curving_or_settled(vehicle, curves, speeds, contact=contact, flange=not linear, saturation=not linear,
                                   **law)
        results = [steady for steady, _ in found if steady is not None]
        settled = [run for _, run in found if run is not None]
        if not results and (output is not None or plot is not None):
            raise AnalysisError("no equilibrium in any curve, so no table or figure of equilibria: " + "; ".join(
                f"{run.reason}: the run into R = {run.curve.radius:g} m {run.describe()}" for run in settled))
        rows = [result.columns() for result in results]
        units = results[0].units() if results else {}
        if output is not None:
            write_csv(output, {name: [row[name] for row in rows] for name in rows[0]}, units)
        if plot is not None:
            from express.analysis.plots import save_figure
            from express.analysis.plots.curving import figure_steady_curving

            save_figure(figure_steady_curving(results, title=f"{vehicle.equations.name}: steady curving, {where}"), plot)
    for path in [p for p in (output, plot) if p is not None and str(p) != "-"]:
        common.note(f"wrote {path}")
    from express.analysis.curving.assessment import assess_steady

    assessments = [assess_steady(vehicle, result) for result in results]
    if as_json:
        common.print_json({"model": str(model), "curves": where,
                           "contact": results[0].contact if results else None,
                           "loads": results[0].wheel_rail.loads if results else None, "units": units, "results": rows,
                           "assessments": [a.as_dict() for a in assessments],
                           "stability": [{"growth": r.growth, "stable": r.stable} for r in results],
                           "paths": [r.path for r in results],
                           "settled": [run.as_dict() for run in settled]})
    elif output != "-":
        if results:
            _print_table(vehicle.equations.name, where, results, assessments, sys.stdout)
        _print_settled(settled, sys.stdout)
    return 0


def _print_settled(settled: list, stream) -> None:
    """Each curve without a stable equilibrium: where the vehicle run into it settles, or
    the limit cycle it keeps (:mod:`express.analysis.curving.settled`)."""
    for run in settled:
        mean, amplitude = run.mean, run.amplitude
        print(f"R = {run.curve.radius:g} m at {run.speed / common.KMH:.1f} km/h: {run.reason}; the time run into it "
              f"(step {run.dt * 1e3:g} ms, d {run.window[0]:.0f}-{run.window[1]:.0f} m) {run.describe()}", file=stream)
        for j in range(1, 1 + sum(1 for name in mean if name.startswith("aoa"))):
            print(f"  ws{j}: aoa {mean[f'aoa{j}'] * 1e3:8.3f} +- {amplitude[f'aoa{j}'] * 1e3:.3f} mrad   Y/Q max "
                  f"{max(mean[f'YQ{j}L'], mean[f'YQ{j}R']):6.3f}   SY {mean[f'SY{j}'] / 1e3:8.3f} +- "
                  f"{amplitude[f'SY{j}'] / 1e3:.3f} kN", file=stream)


def _cases(vehicle: Any, radius, cant: float, direction: str, speed, deficiency, track: str | None):
    """The curves and speeds to solve, and a sentence saying where they came from."""
    from express.analysis.curving.steady import SteadyCurve, curves_of_track

    if track is not None:
        road, where = common.track_and_name(track)
        curves = curves_of_track(road)
        if not curves:
            raise UsageError(f"curving: the track {track} has no circular curve")
        if speed is None and deficiency is None and road.speed is not None:
            speed = [road.speed]
            where += f"; at the track's speed {road.speed / common.KMH:g} km/h"
    else:
        curves = [SteadyCurve(r, cant, direction) for r in radius]
        where = f"{direction} curve{'s' if len(curves) > 1 else ''}, {cant * 1e3:g} mm cant"
    if deficiency is not None:
        pairs = [(c, a) for c in curves for a in deficiency]
        return [c for c, _ in pairs], [_speed_for(vehicle, c, a) for c, a in pairs], where
    values = speed if speed is not None else [common.running_speed(vehicle, None)]
    if speed is None and track is None:
        where += f"; at the model's speed {values[0] / common.KMH:g} km/h"
    pairs = [(c, v) for c in curves for v in values]
    if len(pairs) > MAX_CURVES:
        raise UsageError(f"curving: {len(pairs)} curves, more than {MAX_CURVES}")
    return [c for c, _ in pairs], [v for _, v in pairs], where


def _speed_for(vehicle: Any, curve: Any, deficiency: float) -> float:
    from express.model.parameters import expression_value

    rail = vehicle.model.rail
    return curve.speed_for(deficiency, expression_value(rail.cant_base, vehicle.values),
                           expression_value(rail.gravity, vehicle.values))


def _print_table(name: str, where: str, results: list, assessments: list, stream) -> None:
    first = results[0]
    print(f"{name}: steady curving, {where}; contact {first.contact}, wheel loads {first.wheel_rail.loads}", file=stream)
    count = first.wheel_rail.wheelsets
    head = "  R [m]  cant [mm]  V [km/h]  a_q [m/s2]  dQ/Q0  EN 14363 " + "".join(
        f"| ws{j + 1}: aoa [mrad]  Y/Q max  SY [kN]  flange " for j in range(count))
    print(head, file=stream)
    for result, assessment in zip(results, assessments, strict=True):
        out = result.wheel_rail
        verdict = "derails" if assessment.derailment else ("pass" if assessment.passed else "FAIL")
        cells = [f"{result.curve.radius:7.0f}  {result.curve.cant * 1e3:9.1f}  {result.speed / common.KMH:8.1f}  "
                 f"{result.unbalanced_acceleration:10.3f}  {out.vehicle_unloading[0]:5.3f}  {verdict:>8} "]
        for j in range(count):
            flanging = "".join(s for s, on in zip("LR", out.flange_contact[0, j], strict=True) if on) or "-"
            cells.append(f"| {out.angle_of_attack[0, j] * 1e3:16.3f}  {out.y_over_q[0, j].max():7.3f}  "
                         f"{out.track_shift_force[0, j] / 1e3:7.2f}  {flanging:>6} ")
        print("".join(cells), file=stream)
    _print_stability(results, stream)
    paths = sorted({r.path for r in results if r.path})
    for path in paths:  # with friction elements the path decides the state
        print(f"friction: the state reached {path}", file=stream)


def _print_stability(results: list, stream) -> None:
    """Whether each equilibrium is stable: the largest real part of the eigenvalues of the
    equations linearised there (docs/curving.md)."""
    unstable = [r for r in results if r.stable is False]
    known = [r.growth for r in results if r.growth is not None]
    if not known:
        print("stability of the equilibria: not computed (the model is too large)", file=stream)
    elif not unstable:
        print(f"every equilibrium is stable (largest growth rate {max(known):.3g} 1/s of the linearisation there)",
              file=stream)
    for r in unstable:
        print(f"UNSTABLE equilibrium at R = {r.curve.radius:g} m, {r.speed / common.KMH:.1f} km/h (growth rate "
              f"{r.growth:.3g} 1/s): a time run does not stay there (express simulate)", file=stream)


def main(argv: Sequence[str] | None = None) -> int:
    """``express curving`` with ``argv`` (default ``sys.argv[1:]``) alone: its exit status
    (:func:`express.cli.runner.run_command`, the parsing and errors of :func:`express.cli.main`)."""
    return run_command(sys.modules[__name__], argv)
