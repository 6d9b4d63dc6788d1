"""``express wear``: a wheel-wear prediction over mileage on a route
(:mod:`express.analysis.wear`, ``docs/wear.md``, "Wear prediction"): the worn profiles,
the equivalent conicity, the linear critical speed and the flange dimensions after every
step, with figures; checkpointed after every step, resumed by the same command."""

from __future__ import annotations

import os
import sys
from collections.abc import Sequence
from pathlib import Path

from express.base.diagnostics import UsageError
from express.cli import common
from express.cli.runner import run_command

__all__ = ["add_parser", "main", "run"]

DISTANCE = common.Quantity("--distance", "length", "km", 0.0, 1e7, open_low=True)
BOUND = common.Quantity("--step-bound", "length", "mm", 1e-4, 5.0)
SMOOTHING = common.Quantity("--smoothing", "length", "mm", 0.0, 20.0)
TOLERANCE = common.Quantity("--tolerance", "length", "mm", 1e-4, 5.0)


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser(
        "wear", help="wheel-wear prediction over mileage on a route: worn profiles, conicity, critical speed, Sd, Sh",
        description="Wear the model's wheel profile over --distance of a route (a TOML file of curves, speeds and "
        "shares of the distance): each step solves the route's cases as steady states with the profiles' contact (or "
        "time runs on a random track), in parallel, takes the USFD wear across the profile, smooths it and removes it, "
        "the step's distance bounded so that the profile changes by at most --step-bound (and, with --method heun, "
        "its local error estimate within --tolerance). Writes into DIR the profile of every step, wear.csv "
        "(equivalent conicity, linear critical speed, flange thickness Sd, height Sh, slope qR against the distance), "
        "wear.png, profiles.png and a checkpoint: the same command resumes an interrupted prediction, a longer "
        "--distance continues a finished one. See docs/wear.md.",
    )
    common.add_model_arguments(parser)
    parser.add_argument("--route", required=True, type=Path, metavar="FILE", help="the route file (docs/wear.md)")
    parser.add_argument("--distance", required=True, type=DISTANCE, metavar="D", help=DISTANCE.help("distance to run"))
    parser.add_argument("-o", "--output", required=True, type=Path, metavar="DIR", help="output directory (with the checkpoint)")
    parser.add_argument("--step-bound", type=BOUND, default=0.1e-3, metavar="H",
                        help=BOUND.help("largest change of the profile in one step", "0.1 mm"))
    parser.add_argument("--method", choices=("euler", "heun"), default="euler",
                        help="euler: first order, the step's distance from --step-bound (default); heun: second order "
                        "with a local error estimate, the distance also within --tolerance (docs/wear.md, \"The steps\")")
    parser.add_argument("--tolerance", type=TOLERANCE, default=0.01e-3, metavar="E",
                        help=TOLERANCE.help("largest local error estimate of a Heun step", "0.01 mm"))
    parser.add_argument("--smoothing", type=SMOOTHING, default=1e-3, metavar="S",
                        help=SMOOTHING.help("standard deviation of the Gaussian the step's wear is smoothed with", "1 mm"))
    parser.add_argument("--workers", type=common.count("--workers", 1, 64), default=None, metavar="N",
                        help="processes for a step's cases; default: the CPUs, at most the cases")
    parser.add_argument("--stop-after", type=common.count("--stop-after", 1, 100000), default=None, metavar="K",
                        help="stop after K steps of this run (the checkpoint resumes it)")
    parser.add_argument("--no-figures", action="store_true", help="write no PNG figures")
    parser.set_defaults(handler=run, numeric=True)


def run(model: Path, overrides: dict[str, str], *, route: Path, distance: float, output: Path, step_bound: float,
        smoothing: float, method: str = "euler", tolerance: float = 0.01e-3, workers: int | None = None, stop_after: int | None = None, no_figures: bool = False) -> int:
    """Read the route, check everything, then step (resuming a checkpoint); exit status."""
    from express.analysis.wear.route import read_route  # a bad route is refused before the heavy imports

    read = read_route(route)
    from express.analysis.curving.steady import CurveError
    from express.analysis.wear.prediction import WearSettings, predict_wear, prediction_identity
    from express.analysis.wear.route import route_problems
    from express.base.diagnostics import AnalysisError, ModelError
    from express.io.output import check_destination
    from express.model.parameters import expression_value

    if output.exists() and not output.is_dir():
        raise UsageError(f"-o {output}: not a directory")
    for name in ("wear.csv", "checkpoint.json"):
        check_destination(output / name, inputs=[model, route])
    vehicle = common.load_rail_vehicle(model, overrides, "wear")
    rail = vehicle.model.rail
    problems, speeds = route_problems(read, expression_value(rail.cant_base, vehicle.values),
                                      expression_value(rail.gravity, vehicle.values))
    if problems:
        raise ModelError(problems)
    settings = WearSettings(bound=step_bound, smoothing=smoothing, method=method, tolerance=tolerance)
    identity = prediction_identity(Path(model).read_text(encoding="utf-8"), overrides, read, settings)
    count = workers or max(1, min(os.cpu_count() or 1, sum(1 for c in read.cases if not c.straight or c.track)))

    def progress(row: dict) -> None:
        common.note(f"step {row['step']:3d}: {row['distance'] / 1e3:10.1f} km, conicity {row['conicity']:.4f}, "
                    f"Sd {row['flange_thickness'] * 1e3:.2f} mm, Sh {row['flange_height'] * 1e3:.2f} mm, "
                    f"largest depth {row['max_depth'] * 1e3:.3f} mm, {row['evaluations']} evaluations")

    try:
        result = predict_wear(vehicle, read, speeds, distance, output, identity=identity, settings=settings,
                              workers=count, stop_after=stop_after, figures=not no_figures, progress=progress)
    except CurveError as error:
        raise AnalysisError(f"wear: a case of the route has no steady state on the worn profile: {error} (the "
                            f"checkpoint in {output} keeps the steps before)") from None
    last = result.rows[-1]
    state = "reached" if result.finished else "stopped at"
    print(f"{vehicle.name}: wear on route {read.name!r}, {state} {last['distance'] / 1e3:g} km in {last['step']} steps "
          f"({result.run_now} now); conicity {result.rows[0]['conicity']:.4f} -> {last['conicity']:.4f}, "
          f"Sd {result.rows[0]['flange_thickness'] * 1e3:.2f} -> {last['flange_thickness'] * 1e3:.2f} mm, "
          f"Sh {result.rows[0]['flange_height'] * 1e3:.2f} -> {last['flange_height'] * 1e3:.2f} mm; wrote {output}")
    return 0


def main(argv: Sequence[str] | None = None) -> int:
    """``express wear`` with ``argv`` (default ``sys.argv[1:]``) alone: its exit status
    (:func:`express.cli.runner.run_command`, the parsing and errors of :func:`express.cli.main`)."""
    return run_command(sys.modules[__name__], argv)
