"""``express eigen``: eigenvalues and modes at one speed
(:func:`express.analysis.stability.stability.eigen_analysis`)."""

from __future__ import annotations

import sys
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from express.base.diagnostics import AnalysisError, UsageError
from express.cli import common
from express.cli.runner import run_command

__all__ = ["add_parser", "main", "run"]


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser(
        "eigen", help="eigenvalues and modes at one speed",
        description="Eigenvalues of A(v) of the linear vehicle on straight track: frequency, damping "
        "ratio, dominant DOFs and a label for every mode, least stable first. A model without rail data: its "
        "modes (independent of the speed).",
    )
    common.add_model_arguments(parser)
    parser.add_argument("--speed", type=common.SPEED, metavar="SPEED", help=common.SPEED.help("running speed", "the model's speed"))
    common.add_json_option(parser)
    common.add_linearisation_arguments(parser)
    parser.add_argument("--mode", type=common.count("--mode", 1, 100000), metavar="N",
                        help="mode number N of the table (1 = least stable) for --plot/--animate")
    parser.add_argument("--plot", type=common.figure_path, metavar="FILE",
                        help="with --mode: the mode shape in plan, side and end views (.png, .svg, .pdf)")
    parser.add_argument("--animate", metavar="FILE", help="with --mode: the mode shape animated (.gif or .html)")
    parser.set_defaults(handler=run, numeric=True)


def run(model: Path, overrides: dict[str, str], *, speed: float | None = None, as_json: bool = False,
        mode: int | None = None, plot: Path | None = None, animate: str | None = None,
        linearisation: str = "tangent", element_amplitude: float | None = None, element_angle: float | None = None, element_frequency: float | None = None) -> int:
    """Print the modes (and draw one); returns the exit status."""
    spec = common.linearisation_spec(linearisation, element_amplitude, element_angle, element_frequency)
    if (plot or animate) and mode is None:
        raise UsageError("--plot and --animate draw one mode: give --mode N")
    if animate and Path(animate).suffix.lower() not in (".gif", ".html"):
        raise UsageError(f"--animate {animate}: use .gif or .html")
    if mode is not None and not (plot or animate):
        raise UsageError("--mode N is drawn by --plot FILE or --animate FILE; give one")
    if mode is not None:
        from express.io.output import output_transaction

        with output_transaction(inputs=[model]) as outputs:
            for path in (plot, animate):
                if path is not None:
                    outputs.declare(path, binary=True)
            status = _table(model, overrides, speed, as_json, spec)
            _draw_mode(model, overrides, speed, mode, plot, animate, spec)
        for path in (plot, animate):
            if path is not None:
                common.note(f"wrote {path}")
        return status
    return _table(model, overrides, speed, as_json, spec)


def _draw_mode(model: Path, overrides: dict[str, str], speed: float | None, number: int,
               plot: Path | None, animate: str | None, spec: Any) -> None:
    from express.analysis.plots import save_figure
    from express.analysis.stability.stability import eigen_analysis
    from express.cli.draw import model_geometry_of
    from express.drawing.modes import animate_mode_shape, figure_mode_shape, mode_shape
    from express.io.output import write_bytes

    vehicle = common.linearised_vehicle(common.load_rail_vehicle(model, overrides, "eigen"), spec)
    v = common.running_speed(vehicle, speed)
    shape = mode_shape(vehicle, v, number)  # ArgumentError names the modes there are
    label = eigen_analysis(vehicle, v).modes[number - 1].kind
    geometry = model_geometry_of(vehicle.model)
    if plot is not None:
        save_figure(figure_mode_shape(geometry, shape, label), plot)
    if animate is not None:
        write_bytes(animate, animate_mode_shape(geometry, shape, Path(animate).suffix.lower(), label))


def _table(model: Path, overrides: dict[str, str], speed: float | None, as_json: bool, spec: Any) -> int:
    from express.analysis.stability.stability import eigen_analysis
    from express.numeric.statespace import load_vehicle

    vehicle = common.linearised_vehicle(load_vehicle(model, overrides), spec)  # any model: without rail data A has no speed
    rail = vehicle.layout is not None and bool(vehicle.wheelsets)
    v: float | None = common.running_speed(vehicle, speed) if rail else None
    try:
        result = eigen_analysis(vehicle, v)
    except AnalysisError as error:
        raise AnalysisError(f"eigen: {error}") from None
    eigenvalues = result.eigenvalues  # every one, from the same eig as the modes
    name = vehicle.name
    seen = common.note_linearisation(vehicle)
    if as_json:
        common.print_json({
            "model": str(model), "speed": v, "speed_kmh": v / common.KMH if v is not None else None,
            "linearisation": seen,
            "stable": bool(result.stable),
            "eigenvalues": [[float(z.real), float(z.imag)] for z in eigenvalues],
            "modes": [
                {"eigenvalue": [mode.real, mode.imag], "frequency_hz": mode.frequency_hz,
                 "natural_frequency_hz": mode.natural_frequency_hz, "damping_ratio": mode.damping_ratio, "dominant": [[dof, share] for dof, share in mode.dominant],
                 "series_dissipation": [[element, share] for element, share in mode.series],
                 "label": mode.kind, "description": mode.describe()}
                for mode in result.modes
            ],
        })
        return 0
    where = f"at {v / common.KMH:.1f} km/h ({v:.3f} m/s)" if v is not None else "(no rail data: independent of speed)"
    print(f"{name}: {len(result.modes)} modes {where}, least stable first; "
          f"{'stable' if result.stable else 'UNSTABLE'}")
    header = f"{'Re [1/s]':>11} {'Im [rad/s]':>11} {'f [Hz]':>8} {'zeta':>8}  {'dominant DOFs (share)':<40} mode"
    print(header)
    print("-" * len(header))
    for mode in result.modes:
        dominant = ", ".join(f"{dof} {share:.0%}" for dof, share in mode.dominant[:3])
        series = ", ".join(f"{element} {share:.0%}" for element, share in mode.series[:2] if share >= 0.1)
        print(f"{mode.real:11.4f} {mode.imag:11.4f} {mode.frequency_hz:8.3f} {mode.damping_ratio:8.4f}  "
              f"{dominant:<40} {mode.kind}" + (f" [series dampers: {series}]" if series else ""))
    return 0


def main(argv: Sequence[str] | None = None) -> int:
    """``express eigen`` with ``argv`` (default ``sys.argv[1:]``) alone: its exit status
    (:func:`express.cli.runner.run_command`, the parsing and errors of :func:`express.cli.main`)."""
    return run_command(sys.modules[__name__], argv)
