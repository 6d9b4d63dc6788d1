"""``express simulate``: a vehicle run along a track (:func:`express.analysis.time.simulate.simulate`).

A run that leaves the model's range of validity is not a result: when a state becomes
non-finite, or a wheelset moves more than ten flange clearances
from its rail, the command exits with status 1, names the time, the track position and
the least-damped eigenvalue at the speed, leaves the requested outputs untouched and
keeps the history up to that point in ``<name>.diverged<suffix>`` beside each of them
(:mod:`express.analysis.time.divergence` finds the step).  With ``--assess`` a run whose
assessment fails (a criterion beyond its limit, a derailment) exits with status 3 after
writing everything: a result, judged.
"""

from __future__ import annotations

import argparse
import math
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from express.base.diagnostics import EXIT_ASSESSMENT, AnalysisError, UsageError
from express.cli import common
from express.cli.runner import run_command

__all__ = ["MAX_STEPS", "add_parser", "main", "run"]

TABLE_SUFFIXES = (".csv", ".npz", ".mat")
#: A run is refused beyond this many time steps (track length / (speed * dt)).
MAX_STEPS = 5_000_000


def table_path(text: str) -> str:
    """``-o FILE``: .csv, .npz or .mat by suffix; ``-`` is CSV on standard output."""
    if text != "-" and Path(text).suffix.lower() not in TABLE_SUFFIXES:
        raise argparse.ArgumentTypeError(f"{text}: unknown result format; use .csv, .npz or .mat (or - for CSV on standard output)")
    return text


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser(
        "simulate", help="run a vehicle along a track (default: the paper's R = 400 m curve, Fig. 9)",
        description="Time-domain run along a track with flange contact and creep saturation. Without "
        "--track the paper's curve is used (straight, 95 m transition, R = 400 m with 95 mm cant for "
        "170 m, transition, straight) at the model's speed. Exit status 1 when the run diverges.",
    )
    common.add_model_arguments(parser)
    parser.add_argument("--track", metavar="NAME|FILE", help="track file (.toml, docs/track.md) or a bundled curve "
                        "(R250, R400, R600, R1000, R3000, paper; docs/curving.md); default: the paper's curve, said so")
    parser.add_argument("--speed", type=common.SPEED, metavar="SPEED",
                        help=common.SPEED.help("running speed", "the track's speed, else the model's"))
    parser.add_argument("--dt", type=common.DT, default=0.005, metavar="DT",
                        help=common.DT.help("time step", f"0.005 s; at most {MAX_STEPS:,} steps"))
    parser.add_argument("--linear", action="store_true", help="no flange contact and no creep saturation")
    common.add_creep_law_argument(parser)
    parser.add_argument("-o", "--output", dest="outputs", action="append", default=[], type=table_path, metavar="FILE",
                        help="time histories: .csv (units in the header), .npz or .mat by suffix, - for CSV on "
                        "standard output (repeatable)")
    parser.add_argument("--plot", type=common.figure_path, metavar="FILE", help="figure of the run (.png, .svg or .pdf)")
    parser.add_argument("--assess", action="store_true",
                        help="EN 14363 running safety: (Y/Q)2m against 0.8 and Nadal, (ΣY)2m against Prud'homme, "
                        "the instability criterion (ΣY rms over 100 m against (ΣY)lim/2), ΔQ/Q0, each with its "
                        "limit and pass/fail (docs/curving.md); the per-wheel outputs join the histories; exit "
                        "status 3 when a criterion fails or the vehicle derails (the histories are still written)")
    parser.add_argument("--no-step-check", dest="step_check", action="store_false",
                        help="with --assess, do not check the step: by default the assessed run is repeated at twice "
                             "its step and the step halved (at most 3 times) until every EN 14363 quantity moves by "
                             "less than 1 %% of its limit; the summary says the step used and its estimated error "
                             "(docs/curving.md)")
    common.add_json_option(parser)
    parser.set_defaults(handler=run, numeric=True)


def run(
    model: Path, overrides: dict[str, str], *, track: str | None = None, speed: float | None = None,
    dt: float = 0.005, linear: bool = False, outputs: list[str] | None = None, plot: Path | None = None,
    assess: bool = False, as_json: bool = False, step_check: bool = True, creep_law: str | None = None,
) -> int:
    """Simulate and write the outputs all together; returns the exit status."""
    from express.io.output import output_transaction

    outputs = list(outputs or [])
    if "-" in outputs and as_json:
        raise UsageError("-o - and --json both write to standard output; choose one")
    if assess and linear:
        raise UsageError("--assess judges the forces of the nonlinear wheel/rail contact, which a --linear run "
                         "leaves out; drop one of them")
    inputs = [model] + ([Path(track)] if track is not None and Path(track).is_file() else [])
    failure = None
    assessment = None
    check = None
    with output_transaction(inputs) as transaction:
        for path in outputs:
            transaction.declare(path, binary=Path(path).suffix.lower() in (".npz", ".mat"))
        if plot is not None:
            transaction.declare(plot, binary=True)
        road, where = common.track_and_name(track)
        transaction.add_inputs(_files_read_by(road))
        vehicle = common.load_rail_vehicle(model, overrides, "simulate")
        law = common.creep_law_options(vehicle, creep_law, nonlinear=not linear)
        v, where = _speed_and_source(vehicle, speed, road, where)
        from express.analysis.curving.steady import track_problems

        problems = track_problems(vehicle, road, v)
        if problems:
            raise UsageError("\n".join(f"simulate: {problem}" for problem in problems))
        steps = road.length / (v * dt)
        if steps > MAX_STEPS:
            raise UsageError(f"--dt {dt:g} s: {steps:,.0f} steps for {road.length:g} m at {v / common.KMH:g} km/h; "
                             f"at most {MAX_STEPS:,} (give a larger --dt)")
        result = _simulate(vehicle, road, v, dt, linear, law)
        from express.analysis.time.divergence import find_divergence

        divergence = find_divergence(result, vehicle)
        if divergence is None:
            if assess:
                assessment = _assess(vehicle, road, result)
                if step_check:
                    result, assessment, check = _step_check(vehicle, road, v, dt, (result, assessment), law)
                    dt = check.dt
            _write(result, outputs, plot, f"{vehicle.equations.name}: {v / common.KMH:.0f} km/h, {_track_name(track)}")
        else:
            failure = _diverged(result, vehicle, divergence, [p for p in outputs if p != "-"])
    if failure is not None:
        raise AnalysisError(failure)
    for path in [p for p in outputs if p != "-"] + ([str(plot)] if plot is not None else []):
        common.note(f"wrote {path}")
    summary = {
        "model": str(model), "track": str(track) if track is not None else "paper", "track_used": where, "speed": v,
        "speed_kmh": v / common.KMH, "track_length": road.length, "dt": dt, "linear": bool(linear),
        "contact": result.options.get("contact", "deadband"), "steps": int(result.time.size),
        "max_abs": result.max_abs(),
        "outputs_written": [p for p in outputs if p != "-"] + ([str(plot)] if plot is not None else []),
    }
    if assessment is not None:
        summary["assessment"] = assessment.as_dict()
    if check is not None:
        summary["step_check"] = check.as_dict()
    stream = sys.stderr if "-" in outputs else sys.stdout
    if as_json:
        common.print_json(summary)
    else:
        _print_summary(vehicle.equations.name, summary, track, stream)
        if assessment is not None:
            _print_assessment(assessment, stream)
        if check is not None:
            print(check.sentence(), file=stream)
    if assessment is None or (assessment.passed and assessment.derailment is None):
        return 0
    failed = [c.name for c in assessment.criteria if c.passed is False]
    if assessment.derailment is not None:
        common.note(f"error: simulate: the vehicle derails: {assessment.derailment}; the histories were written")
    if failed:
        common.note(f"error: simulate: the assessment fails: {', '.join(failed)} beyond their limits")
    return EXIT_ASSESSMENT


def _speed_and_source(vehicle: Any, speed: float | None, road: Any, where: str) -> tuple[float, str]:
    """The running speed: ``--speed``, else the track's, else the model's; and the track
    sentence saying which was used (a track's speed is never silently ignored)."""
    if speed is not None:
        note = f"; --speed {speed / common.KMH:g} km/h"
        if road.speed is not None and abs(road.speed - speed) > 1e-9:
            note += f" (the track's own speed {road.speed / common.KMH:g} km/h is overridden)"
        return speed, where + note
    if road.speed is not None:
        return road.speed, where + f"; at the track's speed {road.speed / common.KMH:g} km/h"
    v = common.running_speed(vehicle, None)
    return v, where + f"; at the model's speed {v / common.KMH:g} km/h"


def _assess(vehicle: Any, road: Any, result: Any) -> Any:
    """EN 14363 running safety of the run; its per-wheel outputs join the histories."""
    from express.analysis.curving.assessment import assess_run

    wheel_rail, assessment = assess_run(vehicle, road, result)
    result.outputs.update({name: values for name, values in wheel_rail.columns().items() if name not in result.outputs})
    return assessment


def _step_check(vehicle: Any, road: Any, speed: float, dt: float, first: tuple[Any, Any],
                law: dict) -> tuple[Any, Any, Any]:
    """The assessed run checked against twice its step, halved until its quantities agree
    (:func:`express.analysis.time.step_check.checked_simulation`)."""
    from express.analysis.time.step_check import checked_simulation

    smallest = max(1e-5, road.length / (speed * MAX_STEPS))
    return checked_simulation(vehicle, lambda step: _simulate(vehicle, road, speed, step, False, law),
                              lambda result: (result, _assess(vehicle, road, result)), dt, first=first,
                              smallest=smallest)


def _print_assessment(assessment: Any, stream: Any) -> None:
    print("running safety (EN 14363 quantities, docs/curving.md):", file=stream)
    if assessment.filtering is not None:
        print(f"  {assessment.filtering.note}; percentiles of each force in --json", file=stream)
    for c in assessment.criteria:
        verdict = "n/a (no limit)" if c.passed is None else ("pass" if c.passed else "FAIL")
        scale, unit = (1e-3, " kN") if c.unit == "N" else (1.0, "")
        limit = "-" if c.limit is None else f"{c.limit * scale:.3f}{unit}"
        print(f"  {c.name:<12} {c.value * scale:9.3f}{unit}  limit {limit:<12} {verdict}", file=stream)
    if assessment.derailment is not None:
        print(f"  DERAILMENT: {assessment.derailment}", file=stream)
    if assessment.wear:
        print("wear and RCF per wheel (docs/wear.md; max / mean over the run):", file=stream)
        print(f"  {'wheel':<6} {'Tgamma [N]':>17} {'wear [ug/(m mm^2)]':>19} {'RCF index [-]':>21}", file=stream)
        for w in assessment.wear:
            print(f"  {w.wheel:<6} {w.tgamma_max:8.2f} {w.tgamma_mean:8.2f} {w.wear_max:9.3f} {w.wear_mean:9.3f} "
                  f"{w.rcf_max:10.3e} {w.rcf_mean:10.3e}", file=stream)


def _files_read_by(road: Any) -> list[str]:
    """Data files a track read besides itself (a measured profile)."""
    source = getattr(road.irregularity, "source", None)
    return [source] if isinstance(source, str) and Path(source).is_file() else []


def _simulate(vehicle: Any, road: Any, speed: float, dt: float, linear: bool, law: dict) -> Any:
    import numpy as np

    from express.analysis.time.simulate import simulate

    with np.errstate(over="ignore", invalid="ignore"):  # a diverging run is reported: analysis.divergence
        return simulate(vehicle, road, speed=speed, dt=dt, flange=not linear, saturation=not linear,
                        progress=common.is_terminal(sys.stderr), **law)


def _write(result: Any, outputs: list[str], plot: Path | None, title: str) -> None:
    for path in outputs:
        result.save(path)
    if plot is not None:
        from express.analysis.plots import figure_simulation, save_figure

        save_figure(figure_simulation(result.distance, result.outputs, title=title), plot)


def _diverged(result: Any, vehicle: Any, divergence: Any, outputs: list[str]) -> str:
    """Keep the history before ``divergence`` beside each output; return the message."""
    from express.analysis.time.divergence import divergence_message, truncate

    k = divergence.index
    message = "simulate: " + divergence_message(result, vehicle, divergence)
    if k > 0 and outputs:
        kept = truncate(result, k)
        names = []
        for path in outputs:
            marked = _marked(path)
            kept.save(marked)
            names.append(marked)
        message += f"; the history up to t = {result.time[k - 1]:.4g} s is in {', '.join(names)}"
    return message + "; no output was replaced"


def _marked(path: str) -> str:
    target = Path(path)
    return str(target.with_name(f"{target.stem}.diverged{target.suffix}"))


def _track_name(track: str | None) -> str:
    return Path(track).name if track is not None else "paper's curve (R = 400 m, 95 mm cant)"


def _print_summary(name: str, summary: dict, track: str | None, stream: Any) -> None:
    v = summary["speed"]
    print(f"track: {summary['track_used']}", file=stream)
    print(f"{name}: {_track_name(track)}, {summary['track_length']:.1f} m at {v / common.KMH:.1f} km/h "
          f"({v:.2f} m/s), dt = {summary['dt']:g} s"
          f"{', linear' if summary['linear'] else _contact_words(summary['contact'])}", file=stream)
    print("largest absolute values:", file=stream)
    for key, value in summary["max_abs"].items():
        print(f"  {key:<10} {_with_unit(key, value)}", file=stream)


def _contact_words(contact: str) -> str:
    """How the summary names the run's wheel/rail contact."""
    if contact == "deadband":
        return ", flange contact and creep saturation (dead-band)"
    return f", contact {contact.replace('(', '(creep law ')}"


def _with_unit(name: str, value: float) -> str:
    from express.analysis.time.simulate import output_unit

    unit = output_unit(name)
    if name.startswith("Tgamma"):
        return f"{value:10.3f} N"
    if name.startswith("wear"):
        return f"{value:10.4f} ug/(m mm^2)"
    if name.startswith("rcf"):
        return f"{value:10.3e}"
    if unit == "N":
        return f"{value / 1e3:10.3f} kN"
    if unit == "rad":
        return f"{value * 1e3:10.3f} mrad"
    if unit == "m":
        return f"{value * 1e3:10.3f} mm"
    if unit == "1/m":
        return f"{value:10.5f} 1/m"
    return f"{value:10.4f}" if math.isfinite(value) else f"{value:>10}"


def main(argv: Sequence[str] | None = None) -> int:
    """``express simulate`` with ``argv`` (default ``sys.argv[1:]``) alone: its exit status
    (:func:`express.cli.runner.run_command`, the parsing and errors of :func:`express.cli.main`)."""
    return run_command(sys.modules[__name__], argv)
