"""Command-line subcommands of the analyses (added by :func:`add_analysis_commands`).

Each command is a thin layer over a library function:

=================  =====================================================================
``simulate``       :func:`express.analysis.simulate.simulate` along a track (default: the
                   paper's Fig. 9 curve), results to CSV/NPZ/MAT, a figure, a summary
``frf``            :func:`express.analysis.frequency.frequency_response` (paper Fig. 10)
``eigen``          :func:`express.analysis.stability.eigen_analysis` at one speed
``critical-speed`` :func:`express.analysis.stability.critical_speed`, optionally against
                   the conicity (paper Fig. 11)
``demo``           :func:`express.analysis.demo.run_demo`: every figure of the paper
=================  =====================================================================

``--json`` prints a JSON summary on standard output in SI units (speeds in m/s, forces in
N, angles in rad, accelerations in m/s^2); keys ending in ``_kmh`` are the same speeds in
km/h for convenience.  Mistakes (a bad option value, a model without rail data, an
unreadable track) end with one ``error:`` line per problem and exit status 2.
"""

from __future__ import annotations

import csv
import io
import json
import math
import sys
from collections.abc import Callable
from pathlib import Path

import numpy as np

from ..diagnostics import ModelError, UsageError
from ..io.output import json_safe

__all__ = ["add_analysis_commands", "parse_range"]

KMH = 1.0 / 3.6


def add_analysis_commands(commands, add_model_arguments) -> None:
    """Register ``simulate``, ``frf``, ``eigen``, ``critical-speed`` and ``demo``."""
    simulate = commands.add_parser(
        "simulate",
        help="run a vehicle along a track (default: the paper's R = 400 m curve, Fig. 9)",
        description="Time-domain run along a track with flange contact and creep saturation. "
        "Without --track the paper's curve is used (straight, 95 m transition, R = 400 m with "
        "95 mm cant for 170 m, transition, straight) at the model's speed.",
    )
    add_model_arguments(simulate)
    simulate.add_argument("--track", metavar="FILE", help="track file (.toml, docs/track.md); default: the paper's curve")
    simulate.add_argument("--speed", metavar="KMH", help="speed in km/h (or with a unit: '30 m/s'); default: the model's")
    simulate.add_argument("--dt", type=float, default=0.005, metavar="S", help="time step [s] (default 0.005)")
    simulate.add_argument("--linear", action="store_true", help="no flange contact and no creep saturation")
    simulate.add_argument(
        "-o", "--output", action="append", metavar="FILE",
        help="write the time histories (.csv, .npz or .mat by suffix; repeatable)",
    )
    simulate.add_argument("--plot", metavar="FILE", help="figure of the run (.png, .svg or .pdf)")
    simulate.add_argument("--json", action="store_true", help="print a JSON summary (SI units)")
    simulate.set_defaults(handler=_guard(_command_simulate), needs_loader=True)

    frf = commands.add_parser(
        "frf",
        help="frequency response to a sinusoidal lateral irregularity (paper Fig. 10)",
        description="Steady-state response to yR = Y sin(2 pi f t) at the leading wheelset, "
        "delayed at the others. Reports the acceleration amplitude of the model's output "
        "points (e.g. the car-body floor above the bogie centres) and of any --dof.",
    )
    add_model_arguments(frf)
    frf.add_argument("--fmin", type=float, default=0.1, metavar="HZ", help="lowest frequency [Hz] (default 0.1)")
    frf.add_argument("--fmax", type=float, default=20.0, metavar="HZ", help="highest frequency [Hz] (default 20)")
    frf.add_argument("--points", type=int, default=200, help="number of frequencies, log-spaced (default 200)")
    frf.add_argument("--amplitude", type=float, default=1.0, metavar="MM", help="irregularity amplitude Y [mm] (default 1)")
    frf.add_argument("--speed", metavar="KMH", help="speed in km/h; default: the model's")
    frf.add_argument(
        "--dof", action="append", metavar="DOF",
        help="also report this DOF's displacement amplitude, e.g. --dof W1.y (repeatable)",
    )
    frf.add_argument("-o", "--output", metavar="FILE", help="write the amplitudes and phases as CSV")
    frf.add_argument("--plot", metavar="FILE", help="figure (.png, .svg or .pdf)")
    frf.add_argument("--json", action="store_true", help="print a JSON summary (SI units)")
    frf.set_defaults(handler=_guard(_command_frf), needs_loader=True)

    eigen = commands.add_parser(
        "eigen",
        help="eigenvalues and modes at one speed",
        description="Eigenvalues of A(v) of the linear vehicle on straight track: frequency, "
        "damping ratio, dominant DOFs and a label for every mode, least stable first.",
    )
    add_model_arguments(eigen)
    eigen.add_argument("--speed", metavar="KMH", help="speed in km/h; default: the model's")
    eigen.add_argument("--json", action="store_true", help="print a JSON summary (SI units)")
    eigen.set_defaults(handler=_guard(_command_eigen), needs_loader=True)

    critical = commands.add_parser(
        "critical-speed",
        help="hunting critical speed (optionally against the conicity, paper Fig. 11)",
        description="Lowest speed at which an eigenvalue of A(v) gets a positive real part. "
        "With --conicities START:STOP:COUNT, the critical speed for each tread conicity.",
    )
    add_model_arguments(critical)
    critical.add_argument("--vmin", default="3.6", metavar="KMH", help="lowest speed scanned [km/h] (default 3.6)")
    critical.add_argument("--vmax", default="540", metavar="KMH", help="highest speed scanned [km/h] (default 540)")
    critical.add_argument("--tolerance", type=float, default=0.1, metavar="KMH", help="bisection tolerance [km/h] (default 0.1)")
    critical.add_argument(
        "--conicities", metavar="START:STOP:COUNT",
        help="sweep the conicity, e.g. 0.02:0.4:40 (COUNT values, both ends included)",
    )
    critical.add_argument("--parameter", default="Gamma", help="parameter swept by --conicities (default Gamma)")
    critical.add_argument("-o", "--output", metavar="FILE", help="with --conicities: write the sweep as CSV")
    critical.add_argument(
        "--plot", metavar="FILE",
        help="figure (.png/.svg/.pdf): V_cr against the conicity with --conicities, else the root locus",
    )
    critical.add_argument("--json", action="store_true", help="print a JSON summary (SI units)")
    critical.set_defaults(handler=_guard(_command_critical_speed), needs_loader=True)

    demo = commands.add_parser(
        "demo",
        help="reproduce the paper's results with the bundled vehicles (figures, data, summary)",
        description="Writes the symbolic matrices of the bundled vehicles, the paper's Figs. 3, 9, "
        "10 and 11 (PNG and SVG) with their data (CSV), and summary.md comparing key numbers "
        "with the paper's.",
    )
    demo.add_argument("outdir", nargs="?", default="demo-out", help="output directory (default demo-out/)")
    demo.add_argument("--examples", metavar="DIR", help="directory of the bundled models (default: found automatically)")
    demo.set_defaults(handler=_guard(_command_demo))


# --------------------------------------------------------------------------------------
# helpers
# --------------------------------------------------------------------------------------


def _usage_error(message: str) -> UsageError:
    return UsageError(message)


def _guard(handler: Callable) -> Callable:
    """Turn library ``ValueError`` s (bad values, a model without rail data, a bad track
    file) into a clean usage error; model problems pass through unchanged."""

    def run(args, **kwargs):
        try:
            return handler(args, **kwargs)
        except (ModelError, UsageError):
            raise
        except (ValueError, OSError) as error:
            raise _usage_error(str(error) or type(error).__name__) from None

    run.__name__ = handler.__name__
    run.__doc__ = handler.__doc__
    return run


def _speed(text: str | None, what: str = "--speed") -> float | None:
    """``"120"`` (km/h) or ``"33 m/s"`` / ``"120 km/h"`` -> m/s."""
    if text is None:
        return None
    from ..units import UnitError, parse_quantity

    try:
        value, unit = parse_quantity(str(text))
    except UnitError as error:
        raise _usage_error(f'{what} "{text}": {error}') from None
    if unit and unit not in ("km/h", "m/s", "kmh", "kph"):
        raise _usage_error(f'{what} "{text}": not a speed (give km/h, e.g. {what} 120)')
    speed = value * KMH if not unit else value
    if not (math.isfinite(speed) and speed > 0):
        raise _usage_error(f'{what} "{text}": the speed must be positive')
    return speed


def parse_range(text: str, what: str = "--conicities") -> np.ndarray:
    """``"0.02:0.4:40"`` -> 40 values from 0.02 to 0.4; ``"0.05,0.1,0.2"`` -> those values.

    Raises ``UsageError`` (a ``ValueError``) for anything else.
    """
    text = text.strip()
    try:
        if ":" in text:
            parts = text.split(":")
            if len(parts) != 3:
                raise ValueError
            start, stop, count = float(parts[0]), float(parts[1]), int(parts[2])
            if count < 1 or not (math.isfinite(start) and math.isfinite(stop)):
                raise ValueError
            values = np.linspace(start, stop, count) if count > 1 else np.array([start])
        else:
            values = np.array([float(part) for part in text.split(",") if part.strip()])
            if values.size == 0 or not np.all(np.isfinite(values)):
                raise ValueError
    except ValueError:
        raise _usage_error(f'{what} "{text}": expected START:STOP:COUNT (e.g. 0.02:0.4:40) or a list 0.05,0.1') from None
    if np.any(values <= 0):
        raise _usage_error(f'{what} "{text}": every value must be positive')
    return values


#: Evaluated vehicles by model file (path, mtime, size), without ``--set``: generating the
#: symbolic equations takes about a second, re-evaluating them with other values about a
#: millisecond (:meth:`VehicleModel.with_values`), so repeated in-process calls (tests,
#: scripts calling :func:`express.cli.main`) reuse the generation.
_VEHICLES: dict[tuple, object] = {}
_VEHICLE_CACHE_SIZE = 4


def _vehicle(args, load, command: str):
    """Load the model (``--set`` applied), check it has rail data, evaluate it."""
    from ..io.output import parse_assignments
    from ..io import load_model
    from ..statespace import vehicle_model

    model = load(args)  # reports a bad file or a bad --set like every command
    if model.rail is None or not model.rail.wheelsets:
        raise _usage_error(
            f"{command}: {args.model}: the model has no rail data (no [rail] section with wheelsets); "
            "only `express generate` applies to it"
        )
    overrides = parse_assignments(args.set or [])
    path = Path(args.model).resolve()
    stat = path.stat()
    key = (str(path), stat.st_mtime_ns, stat.st_size)
    base = _VEHICLES.get(key)
    if base is None:
        try:
            base = vehicle_model(load_model(path))
        except ModelError:
            if not overrides:
                raise
            return vehicle_model(model)  # values only given with --set
        if len(_VEHICLES) >= _VEHICLE_CACHE_SIZE:
            _VEHICLES.pop(next(iter(_VEHICLES)))
        _VEHICLES[key] = base
    return base.with_values(overrides) if overrides else base


def _model_speed(vehicle, override: float | None) -> float:
    speed = override if override is not None else vehicle.speed
    if speed is None or not math.isfinite(speed) or speed <= 0:
        raise _usage_error("the model has no speed: give one with --speed KMH (or --set v=...)")
    return float(speed)


def _require_rail(vehicle, command: str) -> None:
    if vehicle.layout is None or not vehicle.wheelsets:
        raise _usage_error(
            f"{command}: the model has no rail data (no [rail] section with wheelsets); "
            "only `express generate` applies to it"
        )


def _print_json(data: dict) -> None:
    sys.stdout.write(json.dumps(json_safe(data), indent=2, allow_nan=False) + "\n")


def _check_figure_path(path: str | None) -> Path | None:
    if path is None:
        return None
    from .plots import FIGURE_SUFFIXES

    target = Path(path)
    if target.suffix.lower() not in FIGURE_SUFFIXES:
        raise _usage_error(f"--plot {path}: unknown figure format; use .png, .svg or .pdf")
    return target


def _csv_text(columns: dict[str, np.ndarray]) -> str:
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(list(columns))
    for row in np.column_stack([np.asarray(c, dtype=float) for c in columns.values()]):
        writer.writerow([f"{value:.9g}" for value in row])
    return buffer.getvalue()


def _refuse_inputs(paths, inputs) -> None:
    resolved = {Path(p).resolve() for p in inputs}
    for path in paths:
        if path is not None and Path(path).resolve() in resolved:
            raise _usage_error(f"{path}: refusing to overwrite the input file")


def _is_terminal(stream) -> bool:
    try:
        return bool(stream.isatty())
    except (AttributeError, ValueError):
        return False


def _note(message: str) -> None:
    print(message, file=sys.stderr)


# --------------------------------------------------------------------------------------
# simulate
# --------------------------------------------------------------------------------------

_SIMULATION_SUFFIXES = (".csv", ".npz", ".mat")


def _command_simulate(args, load) -> int:
    """``express simulate``."""
    from ..rail.track import paper_curve
    from .simulate import simulate

    outputs = [Path(p) for p in args.output or []]
    for path in outputs:
        if path.suffix.lower() not in _SIMULATION_SUFFIXES:
            raise _usage_error(f"-o {path}: unknown result format; use .csv, .npz or .mat")
    figure_path = _check_figure_path(args.plot)
    inputs = [Path(args.model)] + ([Path(args.track)] if args.track else [])
    _refuse_inputs(outputs + [figure_path], inputs)
    if not (math.isfinite(args.dt) and args.dt > 0):
        raise _usage_error(f"--dt {args.dt}: the time step must be positive")
    track = _load_track(args.track) if args.track else paper_curve()
    vehicle = _vehicle(args, load, "simulate")
    _require_rail(vehicle, "simulate")
    speed = _model_speed(vehicle, _speed(args.speed))
    steps = track.length / (speed * args.dt)
    if steps > 5e6:
        raise _usage_error(f"--dt {args.dt}: {steps:.3g} steps; use a larger time step")
    result = simulate(vehicle, track, speed=speed, dt=args.dt, flange=not args.linear, saturation=not args.linear,
                      progress=_is_terminal(sys.stderr))
    for path in outputs:
        path.parent.mkdir(parents=True, exist_ok=True)
        result.save(path)
        _note(f"wrote {path}")
    if figure_path is not None:
        from .plots import figure_simulation, save_figure

        title = f"{vehicle.equations.name}: {speed / KMH:.0f} km/h, {_track_name(args.track)}"
        save_figure(figure_simulation(result.distance, result.outputs, title=title), figure_path)
        _note(f"wrote {figure_path}")
    maxima = result.max_abs()
    if args.json:
        _print_json({
            "model": str(args.model),
            "track": args.track or "paper_curve",
            "speed": speed,
            "speed_kmh": speed / KMH,
            "track_length": track.length,
            "dt": args.dt,
            "linear": bool(args.linear),
            "steps": int(result.time.size),
            "max_abs": maxima,
            "outputs_written": [str(p) for p in outputs] + ([str(figure_path)] if figure_path else []),
        })
    else:
        print(f"{vehicle.equations.name}: {_track_name(args.track)}, {track.length:.1f} m at "
              f"{speed / KMH:.1f} km/h ({speed:.2f} m/s), dt = {args.dt:g} s"
              f"{', linear' if args.linear else ', flange contact and creep saturation'}")
        print("largest absolute values:")
        for name, value in maxima.items():
            print(f"  {name:<10} {_with_unit(name, value)}")
    return 0


def _load_track(path: str):
    from ..rail.track import load_track

    try:
        return load_track(path)
    except ValueError as error:  # TrackError lists every problem
        problems = getattr(error, "problems", None)
        raise _usage_error("; ".join(problems) if problems else str(error)) from None


def _track_name(path: str | None) -> str:
    return Path(path).name if path else "paper's curve (R = 400 m, 95 mm cant)"


def _with_unit(name: str, value: float) -> str:
    if name.startswith(("Q", "flange")) and not name.startswith("QP"):
        return f"{value / 1e3:10.3f} kN"
    if name.startswith(("psi", "theta")):
        return f"{value * 1e3:10.3f} mrad"
    if name.startswith(("dy", "S")):
        return f"{value * 1e3:10.3f} mm"
    if name.startswith("rho"):
        return f"{value:10.5f} 1/m"
    return f"{value:10.4f}"


# --------------------------------------------------------------------------------------
# frf
# --------------------------------------------------------------------------------------


def _command_frf(args, load) -> int:
    """``express frf``."""
    from .frequency import frequency_response

    if not (math.isfinite(args.fmin) and args.fmin > 0):
        raise _usage_error(f"--fmin {args.fmin}: must be positive")
    if not (math.isfinite(args.fmax) and args.fmax > args.fmin):
        raise _usage_error(f"--fmax {args.fmax}: must be above --fmin {args.fmin}")
    if args.points < 2 or args.points > 100000:
        raise _usage_error(f"--points {args.points}: give between 2 and 100000")
    if not (math.isfinite(args.amplitude) and args.amplitude > 0):
        raise _usage_error(f"--amplitude {args.amplitude}: must be positive (mm)")
    figure_path = _check_figure_path(args.plot)
    output = Path(args.output) if args.output else None
    _refuse_inputs([output, figure_path], [Path(args.model)])
    vehicle = _vehicle(args, load, "frf")
    _require_rail(vehicle, "frf")
    speed = _model_speed(vehicle, _speed(args.speed))
    for dof in args.dof or []:
        if dof not in vehicle.dofs:
            raise _usage_error(f"--dof {dof}: unknown DOF; DOFs: {', '.join(vehicle.dofs)}")
    points = [p.name for p in vehicle.model.rail.outputs] if vehicle.model and vehicle.model.rail else []
    if not points and not args.dof:
        raise _usage_error("frf: the model has no output points ([rail.outputs]); name a DOF with --dof W1.y")
    frequencies = np.geomspace(args.fmin, args.fmax, args.points)
    amplitude = args.amplitude * 1e-3
    response = frequency_response(vehicle, frequencies, amplitude=amplitude, speed=speed)
    series = {f"{name}": (_acceleration(response, name), "m/s^2") for name in points}
    for dof in args.dof or []:
        unit = "rad" if dof.split(".")[-1].startswith("r") else "m"
        series[dof] = (_dof_amplitude(response, vehicle, dof), unit)
    columns = {"frequency_hz": frequencies}
    for name, (values, unit) in series.items():
        kind = "acc_" if unit == "m/s^2" else ""
        columns[f"{name}_{kind}amplitude"] = np.abs(values)
        columns[f"{name}_{kind}phase_deg"] = np.degrees(np.angle(values))
    if output is not None:
        from ..io.output import write_output

        write_output(output, _csv_text(columns), inputs=[Path(args.model)])
        _note(f"wrote {output}")
    if figure_path is not None:
        from .plots import figure_frequency_response, save_figure

        accelerations = [n for n in series if series[n][1] == "m/s^2"]
        others = [n for n in series if n not in accelerations]
        if accelerations:
            curves = [{"label": _output_label(n), "values": np.abs(series[n][0])} for n in accelerations]
            ylabel = "acceleration amplitude [m/s²]"
        else:
            curves = [{"label": f"{n} [{series[n][1]}]", "values": np.abs(series[n][0])} for n in others]
            ylabel = "displacement amplitude"
        figure = figure_frequency_response(
            frequencies, curves, ylabel=ylabel,
            title=f"{vehicle.equations.name}: response to Y = {args.amplitude:g} mm at {speed / KMH:.0f} km/h",
        )
        save_figure(figure, figure_path)
        _note(f"wrote {figure_path}")
    peaks = {}
    for name, (values, unit) in series.items():
        k = int(np.argmax(np.abs(values)))
        peaks[name] = {"amplitude": float(np.abs(values[k])), "frequency_hz": float(frequencies[k]), "unit": unit}
    if args.json:
        _print_json({
            "model": str(args.model),
            "speed": speed,
            "speed_kmh": speed / KMH,
            "amplitude": amplitude,
            "frequencies": frequencies,
            "outputs": {
                name: {"unit": unit, "amplitude": np.abs(values), "phase_deg": np.degrees(np.angle(values))}
                for name, (values, unit) in series.items()
            },
            "peaks": peaks,
        })
    else:
        print(f"{vehicle.equations.name}: sinusoidal irregularity Y = {args.amplitude:g} mm at "
              f"{speed / KMH:.1f} km/h, {args.fmin:g}-{args.fmax:g} Hz ({args.points} points)")
        print(f"  {'output':<14} {'peak amplitude':>18} {'at f [Hz]':>10}")
        for name, peak in peaks.items():
            print(f"  {name:<14} {peak['amplitude']:12.4g} {peak['unit']:<5} {peak['frequency_hz']:10.3f}")
        if output is None and not args.json:
            _note("(-o FILE.csv writes every frequency; --json prints them)")
    return 0


def _output_label(name: str) -> str:
    return {
        "floor_front": "floor above the front bogie centre",
        "floor_rear": "floor above the rear bogie centre",
    }.get(name, name)


def _acceleration(response, name: str) -> np.ndarray:
    return np.asarray(response.acceleration_of(name))


def _dof_amplitude(response, vehicle, dof: str) -> np.ndarray:
    return np.asarray(response.amplitude_of(dof))


# --------------------------------------------------------------------------------------
# eigen
# --------------------------------------------------------------------------------------


def _command_eigen(args, load) -> int:
    """``express eigen``."""
    from .stability import eigen_analysis

    vehicle = _vehicle(args, load, "eigen")
    _require_rail(vehicle, "eigen")
    speed = _model_speed(vehicle, _speed(args.speed))
    result = eigen_analysis(vehicle, speed)
    eigenvalues = np.linalg.eigvals(vehicle.state_matrix(speed))
    eigenvalues = eigenvalues[np.lexsort((-eigenvalues.imag, -eigenvalues.real))]
    if args.json:
        _print_json({
            "model": str(args.model),
            "speed": speed,
            "speed_kmh": speed / KMH,
            "stable": bool(result.stable),
            "eigenvalues": [[float(z.real), float(z.imag)] for z in eigenvalues],
            "modes": [
                {
                    "eigenvalue": [mode.real, mode.imag],
                    "frequency_hz": mode.frequency_hz,
                    "damping_ratio": mode.damping_ratio,
                    "dominant": [[dof, share] for dof, share in mode.dominant],
                    "label": mode.kind,
                    "description": mode.describe(),
                }
                for mode in result.modes
            ],
        })
    else:
        print(f"{vehicle.equations.name}: {len(result.modes)} modes at {speed / KMH:.1f} km/h "
              f"({speed:.3f} m/s), least stable first; {'stable' if result.stable else 'UNSTABLE'}")
        header = f"{'Re [1/s]':>11} {'Im [rad/s]':>11} {'f [Hz]':>8} {'zeta':>8}  {'dominant DOFs (share)':<40} mode"
        print(header)
        print("-" * len(header))
        for mode in result.modes:
            dominant = ", ".join(f"{dof} {share:.0%}" for dof, share in mode.dominant[:3])
            print(f"{mode.real:11.4f} {mode.imag:11.4f} {mode.frequency_hz:8.3f} {mode.damping_ratio:8.4f}  "
                  f"{dominant:<40} {mode.kind}")
    return 0


# --------------------------------------------------------------------------------------
# critical-speed
# --------------------------------------------------------------------------------------


def _command_critical_speed(args, load) -> int:
    """``express critical-speed``."""
    from .stability import critical_speed, critical_speed_vs_conicity, root_locus

    v_min = _speed(args.vmin, "--vmin")
    v_max = _speed(args.vmax, "--vmax")
    if not v_max > v_min:
        raise _usage_error(f"--vmax {args.vmax}: must be above --vmin {args.vmin} km/h")
    if not (math.isfinite(args.tolerance) and args.tolerance > 0):
        raise _usage_error(f"--tolerance {args.tolerance}: must be positive (km/h)")
    conicities = parse_range(args.conicities) if args.conicities else None
    figure_path = _check_figure_path(args.plot)
    output = Path(args.output) if args.output else None
    if output is not None and conicities is None:
        raise _usage_error("-o is written only with --conicities")
    _refuse_inputs([output, figure_path], [Path(args.model)])
    vehicle = _vehicle(args, load, "critical-speed")
    _require_rail(vehicle, "critical-speed")
    options = {"v_min": v_min, "v_max": v_max, "tolerance_kmh": args.tolerance}
    result = critical_speed(vehicle, **options)
    summary = {
        "model": str(args.model),
        "v_min": v_min,
        "v_max": v_max,
        **_critical_fields(result),
    }
    if conicities is not None:
        if vehicle.model is None or args.parameter not in vehicle.model.parameters:
            raise _usage_error(f"--parameter {args.parameter}: the model has no such parameter")
        sweep = critical_speed_vs_conicity(vehicle, conicities, parameter=args.parameter, **options)
        speeds = np.array([c.speed if c is not None else np.nan for c in sweep])
        unstable_at_min = [bool(c is not None and c.unstable_at_min) for c in sweep]
        summary["sweep"] = {
            "parameter": args.parameter,
            "values": conicities,
            "critical_speeds": speeds,
            "critical_speeds_kmh": speeds / KMH,
            "unstable_at_min": unstable_at_min,
            "modes": [c.mode.describe() if c is not None else None for c in sweep],
        }
        if output is not None:
            from ..io.output import write_output

            text = _csv_text({args.parameter: conicities, "critical_speed_m_s": speeds,
                              "critical_speed_kmh": speeds / KMH,
                              "unstable_at_min": np.array(unstable_at_min, dtype=float)})
            write_output(output, text, inputs=[Path(args.model)])
            _note(f"wrote {output}")
        if figure_path is not None:
            from .plots import figure_critical_speed, save_figure

            figure = figure_critical_speed(
                [{"label": vehicle.equations.name, "conicity": conicities, "speed_kmh": speeds / KMH}],
                nominal_conicity=vehicle.values.get(args.parameter),
                running_speed_kmh=vehicle.speed / KMH if math.isfinite(vehicle.speed) else None,
                title=f"{vehicle.equations.name}: critical speed against {args.parameter}",
            )
            save_figure(figure, figure_path)
            _note(f"wrote {figure_path}")
    elif figure_path is not None:
        from .plots import figure_eigen_locus, save_figure

        speeds = np.linspace(v_min, v_max, 400)
        figure = figure_eigen_locus(
            speeds / KMH, root_locus(vehicle, speeds),
            title=f"{vehicle.equations.name}: real parts of the eigenvalues against speed",
            critical_kmh=result.speed_kmh if result is not None and not result.unstable_at_min else None,
        )
        save_figure(figure, figure_path)
        _note(f"wrote {figure_path}")
    if args.json:
        _print_json(summary)
    else:
        name = vehicle.equations.name
        if result is None:
            print(f"{name}: stable up to {v_max / KMH:.1f} km/h (no critical speed below --vmax)")
        else:
            print(f"{name}: {result.describe()}")
        if conicities is not None:
            print(f"  {args.parameter:>8} {'V_cr [km/h]':>12}  mode")
            for value, c in zip(conicities, sweep):
                if c is None:
                    print(f"  {value:8.4f} {'> ' + format(v_max / KMH, '.0f'):>12}  stable over the range")
                elif c.unstable_at_min:
                    print(f"  {value:8.4f} {'< ' + format(c.speed_kmh, '.1f'):>12}  unstable at the lowest speed: {c.mode.describe()}")
                else:
                    print(f"  {value:8.4f} {c.speed_kmh:12.1f}  {c.mode.describe()}")
    return 0


def _critical_fields(result) -> dict:
    if result is None:
        return {"critical_speed": None, "critical_speed_kmh": None, "mode": None,
                "frequency_hz": None, "unstable_at_min": False}
    return {
        "critical_speed": result.speed,
        "critical_speed_kmh": result.speed_kmh,
        "mode": result.mode.describe(),
        "frequency_hz": result.mode.frequency_hz,
        "unstable_at_min": bool(result.unstable_at_min),
    }


# --------------------------------------------------------------------------------------
# demo
# --------------------------------------------------------------------------------------


def _command_demo(args) -> int:
    """``express demo``."""
    from .demo import run_demo

    summary = run_demo(Path(args.outdir), examples=Path(args.examples) if args.examples else None, log=_note)
    print(f"wrote {summary.relative_to(Path.cwd()) if summary.is_relative_to(Path.cwd()) else summary}")
    return 0
