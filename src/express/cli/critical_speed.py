"""``express critical-speed``: the hunting critical speed, optionally against the
conicity (paper Fig. 11), :func:`express.analysis.stability.stability.critical_speed`."""

from __future__ import annotations

import argparse
import math
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from express.analysis.stability.critical_options import CriticalOptions
from express.base.diagnostics import UsageError
from express.cli import common
from express.cli.common import SEARCH
from express.cli.runner import run_command
from express.rail.options import DEFAULT_CREEP_LAW, CreepLaw

__all__ = ["MAX_SWEEP", "add_parser", "main", "parse_range", "run"]

#: Most values of one ``--conicities`` sweep.
MAX_SWEEP = 10_000
#: ``--vstart``: the first speed of the ramp-down (``--nonlinear``).
VSTART = common.Quantity("--vstart", "speed", "km/h", 0.0, 1000.0, open_low=True)
#: ``--threshold``: the smallest amplitude that counts as a limit cycle (``--nonlinear``).
THRESHOLD = common.Quantity("--threshold", "length", "mm", 0.0, 50.0, open_low=True)
#: ``--disturbance``: the wheelsets' initial lateral displacement (``--nonlinear``).
DISTURBANCE = common.Quantity("--disturbance", "length", "mm", 0.0, 50.0, open_low=True)


def parse_range(text: str, option: str = "--conicities") -> list[float]:
    """``"0.02:0.4:40"`` -> 40 values from 0.02 to 0.4 (ends included); ``"0.05,0.1"``
    -> those values.  Each value positive and finite, at most :data:`MAX_SWEEP` of them.

    Raises
    ------
    argparse.ArgumentTypeError
        Naming the expected form or the range.

    Examples
    --------
    >>> parse_range("0.1:0.3:3")
    [0.1, 0.2, 0.3]
    >>> parse_range("0.1,,0.2")
    Traceback (most recent call last):
    ...
    argparse.ArgumentTypeError: "0.1,,0.2": an empty item in the list (two commas, or one at an end)
    """
    usage = f'"{text}": expected START:STOP:COUNT (e.g. 0.02:0.4:40) or a list 0.05,0.1'
    parts = text.strip().split(":")
    try:
        if len(parts) == 3:
            start, stop, count = float(parts[0]), float(parts[1]), int(parts[2])
        elif len(parts) == 1:
            items = text.strip().split(",")
            if not all(item.strip() for item in items):  # "0.1,,0.2": an empty item, not two values
                raise argparse.ArgumentTypeError(f'"{text}": an empty item in the list (two commas, or one at an end)')
            values = [float(item) for item in items]
            start, stop, count = 0.0, 0.0, len(values)
        else:
            raise ValueError
    except ValueError:
        raise argparse.ArgumentTypeError(usage) from None
    if not 1 <= count <= MAX_SWEEP:
        raise argparse.ArgumentTypeError(f'"{text}": {count} values; give 1 <= COUNT <= {MAX_SWEEP}')
    if len(parts) == 3:
        import numpy as np

        values = np.linspace(start, stop, count).tolist()
    if not all(math.isfinite(value) and value > 0 for value in values):
        raise argparse.ArgumentTypeError(f'"{text}": every value must be positive and finite')
    return values


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser(
        "critical-speed", help="hunting critical speed (optionally against the conicity, paper Fig. 11)",
        description="Lowest speed at which an eigenvalue of A(v) gets a positive real part. With "
        "--conicities START:STOP:COUNT, the critical speed for each tread conicity.",
    )
    common.add_model_arguments(parser)
    common.add_search_arguments(parser, tolerance=True)
    parser.add_argument("--conicities", type=parse_range, metavar="START:STOP:COUNT",
                        help=f"sweep the conicity, e.g. 0.02:0.4:40 (COUNT values, ends included; "
                        f"1 <= COUNT <= {MAX_SWEEP}), or a list 0.05,0.1")
    parser.add_argument("--parameter", default="Gamma", help="parameter swept by --conicities (default Gamma)")
    parser.add_argument("-o", "--output", metavar="FILE", help="with --conicities: the sweep as CSV (- for standard output)")
    parser.add_argument("--plot", type=common.figure_path, metavar="FILE",
                        help="figure (.png/.svg/.pdf): V_cr against the conicity with --conicities, the "
                        "bifurcation diagram with --nonlinear, else the root locus")
    parser.add_argument("--nonlinear", action="store_true",
                        help="also the nonlinear critical speed: ramp-down from above the linear one with a "
                        "disturbance (contact from the profiles' tables when the model has them); -o writes the "
                        "bifurcation diagram's points")
    parser.add_argument("--vstart", type=VSTART, metavar="SPEED",
                        help=VSTART.help("with --nonlinear: first speed of the ramp-down", "1.2 x the linear V_cr"))
    parser.add_argument("--threshold", type=THRESHOLD, metavar="LENGTH",
                        help=THRESHOLD.help("with --nonlinear: the smallest amplitude of the leading wheelset "
                                            "that counts as a limit cycle", "0.1 mm"))
    parser.add_argument("--disturbance", type=DISTURBANCE, metavar="LENGTH",
                        help=DISTURBANCE.help("with --nonlinear: every wheelset's lateral displacement at the start",
                                              "5 mm"))
    common.add_creep_law_argument(parser)
    common.add_json_option(parser)
    common.add_linearisation_arguments(parser)
    parser.set_defaults(handler=run, numeric=True)


def run(
    model: Path, overrides: dict[str, str], *, vmin: float = SEARCH.v_min, vmax: float = SEARCH.v_max,
    tolerance: float = SEARCH.tolerance,
    conicities: list[float] | None = None, parameter: str = "Gamma", output: str | None = None,
    plot: Path | None = None, as_json: bool = False, nonlinear: bool = False, vstart: float | None = None,
    threshold: float | None = None, disturbance: float | None = None, creep_law: CreepLaw | None = None, linearisation: str = "tangent", element_amplitude: float | None = None, element_angle: float | None = None, element_frequency: float | None = None,
) -> int:
    """Find the critical speed (and the sweep) and write the outputs all together."""
    spec = common.linearisation_spec(linearisation, element_amplitude, element_angle, element_frequency)
    from express.io.output import output_transaction

    if not vmax > vmin:
        raise UsageError(f"--vmax {vmax / common.KMH:g} km/h: must be above --vmin {vmin / common.KMH:g} km/h")
    if nonlinear:
        if conicities is not None:
            raise UsageError("--nonlinear and --conicities: choose one")
        if spec.kind != "tangent":
            raise UsageError("--nonlinear marches the whole nonlinear elements: --linearisation is for the linear critical speed")
        return _run_nonlinear(model, overrides, vmin, vmax, tolerance, output, plot, as_json, vstart,
                              creep_law or DEFAULT_CREEP_LAW,
                              {k: v for k, v in (("threshold", threshold), ("disturbance", disturbance)) if v is not None})
    for option, value in (("--vstart", vstart), ("--threshold", threshold), ("--disturbance", disturbance),
                          ("--creep-law", creep_law)):
        if value is not None:
            raise UsageError(f"{option} is used only with --nonlinear")
    if output is not None and conicities is None:
        raise UsageError("-o is written only with --conicities or --nonlinear")
    if output == "-" and as_json:
        raise UsageError("-o - and --json both write to standard output; choose one")
    options = CriticalOptions(v_min=vmin, v_max=vmax, tolerance=tolerance)
    with output_transaction([model]) as transaction:
        if output is not None:
            transaction.declare(output)
        if plot is not None:
            transaction.declare(plot, binary=True)
        vehicle = common.linearised_vehicle(common.load_rail_vehicle(model, overrides, "critical-speed"), spec)
        if conicities is not None and parameter not in vehicle.facts.parameters:
            raise UsageError(f"--parameter {parameter}: the model has no such parameter")
        result, sweep = _compute(vehicle, options, conicities, parameter)
        if output is not None and conicities is not None and sweep is not None:
            _write_sweep(output, parameter, conicities, sweep)
        if plot is not None:
            _figure(vehicle, plot, vmin, vmax, result, conicities, parameter, sweep)
    for path in [p for p in (output, plot) if p is not None and str(p) != "-"]:
        common.note(f"wrote {path}")
    summary = {"model": str(model), "v_min": vmin, "v_max": vmax, **_fields(result),
               "linearisation": common.note_linearisation(vehicle)}
    if conicities is not None and sweep is not None:
        from express.analysis.stability.stability import sweep_as_dict

        summary["sweep"] = sweep_as_dict(parameter, conicities, sweep)
    if as_json:
        common.print_json(summary)
    else:
        _print(vehicle.name, result, vmax, conicities, parameter, sweep, sys.stderr if output == "-" else sys.stdout)
    return 0


def _compute(vehicle: Any, options: CriticalOptions, conicities: list[float] | None,
             parameter: str) -> tuple[Any, list | None]:
    from express.analysis.stability.stability import critical_speed, critical_speed_vs_conicity

    result = critical_speed(vehicle, options)
    sweep = None
    if conicities is not None:
        sweep = critical_speed_vs_conicity(vehicle, conicities, options, parameter=parameter)
    return result, sweep


def _speeds(sweep: list) -> Any:
    import numpy as np

    return np.array([c.speed if c.found else np.nan for c in sweep])


def _write_sweep(output: str, parameter: str, conicities: list[float], sweep: list) -> None:
    from express.io.output import write_csv

    speeds = _speeds(sweep)
    columns = {parameter: conicities, "critical_speed": speeds, "critical_speed_kmh": speeds / common.KMH,
               "unstable_at_min": [int(c.unstable_at_min) for c in sweep]}
    # a conicity stable up to --vmax has no critical speed: an empty cell (docs/analyses.md)
    write_csv(output, columns, {"critical_speed": "m/s"}, markers=("critical_speed", "critical_speed_kmh"))


def _fields(result: Any) -> dict:
    return result.as_dict()


def _figure(vehicle: Any, plot: Path, vmin: float, vmax: float, result: Any, conicities: list[float] | None,
            parameter: str, sweep: list | None) -> None:
    import numpy as np

    from express.analysis import plots
    from express.analysis.stability.stability import root_locus, unstable_windows

    name = vehicle.name
    if conicities is not None and sweep is not None:
        speeds_kmh = _speeds(sweep) / common.KMH
        at_min = np.array([bool(c.unstable_at_min) for c in sweep])
        windows = unstable_windows(vehicle, np.asarray(conicities), speeds_kmh, at_min, parameter=parameter,
                                   v_max=vmax)
        figure = plots.figure_critical_speed(
            [{"label": name, "conicity": np.asarray(conicities), "speed_kmh": speeds_kmh,
              "unstable_at_min": at_min, "window_end_kmh": windows}],
            nominal_conicity=vehicle.values.get(parameter),
            running_speed_kmh=vehicle.speed / common.KMH if math.isfinite(vehicle.speed) else None,
            title=f"{name}: critical speed against {parameter}",
        )
    else:
        speeds = np.linspace(vmin, vmax, 400)
        figure = plots.figure_eigen_locus(
            speeds / common.KMH, root_locus(vehicle, speeds),
            title=f"{name}: real parts of the eigenvalues against speed",
            critical_kmh=result.speed_kmh if result.found and not result.unstable_at_min else None,
        )
    plots.save_figure(figure, plot)


def _print(name: str, result: Any, vmax: float, conicities: list[float] | None, parameter: str, sweep: list | None,
           stream: Any) -> None:
    if not result.found:
        print(f"{name}: stable up to {vmax / common.KMH:.1f} km/h (no critical speed below --vmax)", file=stream)
    else:
        print(f"{name}: {result.describe()}", file=stream)
    if conicities is None or sweep is None:
        return
    print(f"  {parameter:>8} {'V_cr [km/h]':>12}  mode", file=stream)
    for value, c in zip(conicities, sweep, strict=True):
        if not c.found:
            print(f"  {value:8.4f} {'> ' + format(vmax / common.KMH, '.0f'):>12}  stable over the range", file=stream)
        elif c.unstable_at_min:
            print(f"  {value:8.4f} {'< ' + format(c.speed_kmh, '.1f'):>12}  unstable at the lowest speed: "
                  f"{c.mode.describe()}", file=stream)
        else:
            print(f"  {value:8.4f} {c.speed_kmh:12.1f}  {c.mode.describe()}", file=stream)


# ------------------------------------------------------------------ --nonlinear


def _run_nonlinear(model: Path, overrides: dict[str, str], vmin: float, vmax: float, tolerance: float,
                   output: str | None, plot: Path | None, as_json: bool, vstart: float | None, creep_law: CreepLaw,
                   search: dict[str, float]) -> int:
    """The linear and the nonlinear critical speed (ramp-down), the bifurcation diagram and
    the attractors; ``search`` the ramp's ``threshold`` and ``disturbance`` when given [m]."""
    from express.base.diagnostics import AnalysisError
    from express.io.output import output_transaction

    if output == "-" and as_json:
        raise UsageError("-o - and --json both write to standard output; choose one")
    if vstart is not None and not vstart > vmin:
        raise UsageError(f"--vstart {vstart / common.KMH:g} km/h: must be above --vmin {vmin / common.KMH:g} km/h")
    with output_transaction([model]) as transaction:
        if output is not None:
            transaction.declare(output)
        if plot is not None:
            transaction.declare(plot, binary=True)
        vehicle = common.load_rail_vehicle(model, overrides, "critical-speed")
        from express.analysis.stability.nonlinear_stability import nonlinear_critical_speed
        from express.analysis.stability.stability import critical_speed

        linear = critical_speed(vehicle, CriticalOptions(v_min=vmin, v_max=vmax, tolerance=tolerance))
        if vstart is None and (not linear.found or linear.unstable_at_min):
            raise AnalysisError(f"no linear critical speed between --vmin and --vmax ({vmax / common.KMH:g} km/h) to "
                                "start the ramp-down above: give --vstart")
        result = nonlinear_critical_speed(vehicle, v_start=vstart, v_min=vmin, tolerance=tolerance,
                                          creep_law=creep_law, linear=linear,
                                          threshold=search.get("threshold", 0.1e-3),
                                          disturbance=search.get("disturbance", 5e-3))
        if output is not None:
            _write_bifurcation(output, result)
        if plot is not None:
            _bifurcation_figure(vehicle, plot, result)
    for path in [p for p in (output, plot) if p is not None and str(p) != "-"]:
        common.note(f"wrote {path}")
    name = vehicle.name
    summary = {"model": str(model), **_fields(linear), "nonlinear": result.as_dict()}
    if as_json:
        common.print_json(summary)
    else:
        stream = sys.stderr if output == "-" else sys.stdout
        print(f"{name}: {linear.describe() if linear.found else 'no linear critical speed in the range'}",
              file=stream)
        print(f"{name}: {result.describe()}", file=stream)
        for attractor in result.attractors:
            print(f"  {attractor.describe()}", file=stream)
    return 0


def _write_bifurcation(output: str, result: Any) -> None:
    from express.io.output import write_csv

    points = result.points
    columns = {"speed": [p.speed for p in points], "speed_kmh": [p.speed_kmh for p in points],
               "amplitude": [p.amplitude for p in points], "limit_cycle": [int(p.alive) for p in points],
               "flange_force": [p.flange_force for p in points],
               "flange_contact": [int(p.flange_contact) for p in points],
               "instability": [p.instability for p in points]}
    # no contact tables, no flange force: an empty cell (docs/cli.md)
    write_csv(output, columns, {"speed": "m/s", "amplitude": "m", "flange_force": "N"},
              markers=("flange_force", "instability"))


def _bifurcation_figure(vehicle: Any, plot: Path, result: Any) -> None:
    from express.analysis import plots
    from express.analysis.plots.bifurcation import figure_bifurcation

    points = result.points
    linear = result.linear
    figure = figure_bifurcation(
        [p.speed_kmh for p in points], [p.amplitude * 1e3 for p in points], [p.alive for p in points],
        title=f"{vehicle.name}: hunting limit cycles, contact {result.contact}",
        nonlinear_kmh=result.speed_kmh,
        linear_kmh=linear.speed_kmh if linear is not None and linear.found and not linear.unstable_at_min else None,
    )
    plots.save_figure(figure, plot)


def main(argv: Sequence[str] | None = None) -> int:
    """``express critical-speed`` with ``argv`` (default ``sys.argv[1:]``) alone: its exit status
    (:func:`express.cli.runner.run_command`, the parsing and errors of :func:`express.cli.main`)."""
    return run_command(sys.modules[__name__], argv)
