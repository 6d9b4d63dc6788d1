"""``express study``: a parameter study, optimisation or Sobol analysis from a study file
(:func:`express.analysis.study.run.run_study`, ``docs/studies.md``)."""

from __future__ import annotations

import math
import sys
from collections.abc import Sequence
from pathlib import Path

from express.base.diagnostics import UsageError
from express.cli import common
from express.cli.runner import run_command

__all__ = ["add_parser", "main", "run"]


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser(
        "study", help="parameter study, optimisation or Sobol indices from a study file (docs/studies.md)",
        description="Evaluate the outputs of a study file (critical speed, damping, Q/P on a track, FRF peak) at "
        "every point of a grid, a Latin hypercube or a Sobol sequence, optimise, or compute Sobol indices. "
        "Points run on all local cores by default, or on a Dask cluster (--scheduler). Results are "
        "checkpointed beside the output as they arrive; --resume continues a killed study.",
    )
    parser.add_argument("study", type=Path, help="study file (.toml with a [study] table)")
    parser.add_argument("-o", "--output", required=True, metavar="RESULTS",
                        help="results file: .csv, .parquet or .nc (netCDF)")
    parser.add_argument("--workers", type=common.count("--workers", 1, 4096), metavar="N",
                        help="local worker processes (default: all local cores)")
    parser.add_argument("--scheduler", metavar="ADDRESS",
                        help="run on a Dask cluster: the scheduler's address, e.g. tcp://10.0.0.5:8786")
    parser.add_argument("--resume", action="store_true",
                        help="continue from the checkpoint beside RESULTS, computing only the missing points")
    parser.add_argument("--max-hours", type=_hours, metavar="H",
                        help="run a study estimated (from a few points timed before it starts) to take up to H "
                        "hours on the workers at hand; default 24")
    parser.add_argument("--plot", type=common.figure_path, metavar="FILE",
                        help="grid of one or two parameters: the first output against them (.png, .svg, .pdf)")
    common.add_json_option(parser)
    parser.set_defaults(handler=run, numeric=True)


def _hours(text: str) -> float:
    """``--max-hours``: a number of hours, 0 < H <= 1e6."""
    import argparse

    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f'"{text}" is not a number of hours') from None
    if not 0 < value <= 1e6:
        raise argparse.ArgumentTypeError(f'"{text}" is outside the valid range 0 < --max-hours <= 1e6')
    return value


def run(study: Path, output: str, *, workers: int | None = None, scheduler: str | None = None, resume: bool = False,
        plot: Path | None = None, as_json: bool = False, max_hours: float | None = None) -> int:
    """Run the study and write its results; returns the exit status."""
    from express.analysis.study.run import run_study
    from express.analysis.study.spec import read_study

    if scheduler is not None and workers is not None:
        raise UsageError("--workers is for local processes; with --scheduler the cluster's workers run the points")
    spec = read_study(study)
    if plot is not None:
        _check_plot(spec, plot)
    summary = run_study(spec, output, workers=workers, scheduler=scheduler, resume=resume,
                        progress=common.is_terminal(sys.stderr) and not as_json, max_hours=max_hours)
    if plot is not None:
        _plot(spec, Path(output), plot)
        summary.extra["files"].append(str(plot))
    if as_json:
        common.print_json(summary.as_dict())
    else:
        _print(spec, summary)
    return 0


def _check_plot(spec, plot: Path) -> None:
    if spec.kind != "grid" or not 1 <= len(spec.parameters) <= 2:
        raise UsageError("--plot draws a grid study of one or two parameters")
    from express.io.output import check_destination

    check_destination(plot, inputs=[spec.path, spec.model], binary=True)


def _plot(spec, output: Path, plot: Path) -> None:
    import numpy as np

    from express.analysis.plots import save_figure
    from express.analysis.study.figures import figure_study_map
    from express.analysis.study.outputs import OUTPUTS
    from express.analysis.study.results import read_table

    table = read_table(output)
    name = spec.outputs[0]
    shape = tuple(len(r.values) for r in spec.parameters)
    unit = OUTPUTS[name][0]
    scale, shown = (common.KMH, "km/h") if unit == "m/s" else (1.0, unit)
    axes = [(r.name, np.asarray(r.values), *_display(r), r.scale) for r in spec.parameters]
    figure = figure_study_map(axes, table[name].reshape(shape), label=name, scale=scale, unit=shown,
                              title=spec.title or f"{spec.model.stem}: {name}")
    save_figure(figure, plot)


def _display(r) -> tuple[float, str]:
    """Display factor and unit of a parameter: as the study file wrote it."""
    from express.base.units import unit_factor

    if r.unit:
        return unit_factor(r.unit), r.unit
    return 1.0, ""


def _print(spec, summary) -> None:
    rate = summary.computed / summary.seconds if summary.seconds > 0 else math.inf
    print(f"{spec.path.name}: {summary.points} points ({summary.computed} computed now, {summary.failed} without "
          f"a value) on {summary.workers} worker{'s' if summary.workers != 1 else ''} in {summary.seconds:.1f} s "
          f"({rate:.0f} points/s)")
    for path in summary.extra.get("files", []):
        print(f"wrote {path}")
    best = summary.extra.get("best")
    if spec.kind == "optimise":
        if best is None:
            print("no feasible point found")
        else:
            values = ", ".join(f"{k} = {v:.6g}" for k, v in best["parameters"].items())
            outputs = ", ".join(f"{k} = {v:.6g}" for k, v in best["outputs"].items())
            print(f"best (point {best['point']} of {best['evaluations']}): {values}: {outputs}")
    indices = summary.extra.get("indices")
    if indices:
        for output, entry in indices.items():
            print(f"Sobol indices of {output}:" + (f" {entry['note']}" if "note" in entry else ""))
            for k, name in enumerate(entry["parameters"]):
                print(f"  {name:<12} S1 = {entry['S1'][k]:7.3f}   ST = {entry['ST'][k]:7.3f}")


def main(argv: Sequence[str] | None = None) -> int:
    """``express study`` with ``argv`` (default ``sys.argv[1:]``) alone: its exit status
    (:func:`express.cli.runner.run_command`, the parsing and errors of :func:`express.cli.main`)."""
    return run_command(sys.modules[__name__], argv)
