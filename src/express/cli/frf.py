"""``express frf``: response to a sinusoidal lateral irregularity (paper Fig. 10),
:func:`express.analysis.frequency.frequency.frequency_response`."""

from __future__ import annotations

import sys
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from express.base.diagnostics import AnalysisError, UsageError
from express.base.names import did_you_mean
from express.cli import common
from express.cli.runner import run_command
from express.model.modal_body import coordinate_unit

__all__ = ["MAX_POINTS", "add_parser", "main", "run"]

#: Most frequencies one run computes.
MAX_POINTS = 100_000

_LABELS = {"floor_front": "floor above the front bogie centre", "floor_rear": "floor above the rear bogie centre"}


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser(
        "frf", help="frequency response to a sinusoidal lateral irregularity (paper Fig. 10)",
        description="Steady-state response to yR = Y sin(2 pi f t) at the leading wheelset, delayed at "
        "the others. Reports the acceleration amplitude of the model's output points (e.g. the car-body "
        "floor above the bogie centres) and the displacement amplitude of any --dof. A model without rail "
        "data: the displacement of every --dof (default: all) for each ground input alone, named DOF/input.",
    )
    common.add_model_arguments(parser)
    parser.add_argument("--fmin", type=common.FMIN, default=0.1, metavar="F",
                        help=common.FMIN.help("lowest frequency", "0.1 Hz"))
    parser.add_argument("--fmax", type=common.FMAX, default=20.0, metavar="F",
                        help=common.FMAX.help("highest frequency, above --fmin", "20 Hz"))
    parser.add_argument("--points", type=common.count("--points", 2, MAX_POINTS), default=200,
                        help=f"number of frequencies, log-spaced; 2 <= --points <= {MAX_POINTS}; default 200")
    parser.add_argument("--amplitude", type=common.AMPLITUDE, default=1e-3, metavar="Y",
                        help=common.AMPLITUDE.help("irregularity amplitude Y", "1 mm"))
    parser.add_argument("--speed", type=common.SPEED, metavar="SPEED", help=common.SPEED.help("running speed", "the model's speed"))
    parser.add_argument("--dof", dest="dofs", action="append", default=[], metavar="DOF",
                        help="also report this DOF's displacement amplitude, e.g. --dof W1.y (repeatable)")
    parser.add_argument("--input", dest="components", action="append", default=[],
                        choices=("alignment", "vertical", "cross_level", "gauge"),
                        help="track irregularity driving the vehicle, one at a time (repeatable): the output "
                        "points' accelerations and displacements in every direction, named POINT.aZ/INPUT and "
                        "POINT.uZ/INPUT (docs/ride.md for the rail grounds that carry vertical inputs); "
                        "default: the lateral alignment of paper Fig. 10")
    parser.add_argument("--log", action="store_true", help="--plot with logarithmic amplitude axes")
    parser.add_argument("-o", "--output", metavar="FILE", help="amplitudes and phases as CSV (- for standard output)")
    parser.add_argument("--plot", type=common.figure_path, metavar="FILE", help="figure (.png, .svg or .pdf)")
    common.add_json_option(parser)
    common.add_linearisation_arguments(parser)
    parser.set_defaults(handler=run, numeric=True)


def run(
    model: Path, overrides: dict[str, str], *, fmin: float = 0.1, fmax: float = 20.0, points: int = 200,
    amplitude: float = 1e-3, speed: float | None = None, dofs: list[str] | None = None,
    output: str | None = None, plot: Path | None = None, as_json: bool = False,
    components: list[str] | None = None, log: bool = False, linearisation: str = "tangent", element_amplitude: float | None = None, element_angle: float | None = None, element_frequency: float | None = None,
) -> int:
    """Compute the response and write the outputs all together; returns the exit status."""
    import numpy as np

    from express.io.output import output_transaction, write_csv

    dofs = list(dofs or [])
    spec = common.linearisation_spec(linearisation, element_amplitude, element_angle, element_frequency)
    if not fmax > fmin:
        raise UsageError(f"--fmax {fmax:g} Hz: must be above --fmin {fmin:g} Hz")
    if output == "-" and as_json:
        raise UsageError("-o - and --json both write to standard output; choose one")
    components = list(dict.fromkeys(components or []))
    if components and dofs:
        raise UsageError("--dof goes with the alignment response (no --input): --input reports the output points")
    with output_transaction([model]) as transaction:
        if output is not None:
            transaction.declare(output)
        if plot is not None:
            transaction.declare(plot, binary=True)
        from express.numeric.statespace import load_vehicle

        vehicle = common.linearised_vehicle(load_vehicle(model, overrides), spec)  # any model: from its ground inputs
        rail = vehicle.layout is not None and bool(vehicle.wheelsets)
        v = common.running_speed(vehicle, speed) if rail else float("nan")
        frequencies = np.geomspace(fmin, fmax, points)
        if components and not rail:
            raise UsageError("--input: the model has no rail data (wheelsets): no track drives it")
        if components:
            series = _track_series(vehicle, components, frequencies, amplitude, v)
        else:
            series = _series(vehicle, dofs, frequencies, amplitude, v) if rail else _ground_series(vehicle, dofs, frequencies, amplitude)
        if output is not None:
            columns, units = _columns(frequencies, series)
            write_csv(output, columns, units)
        if plot is not None:
            _figure(vehicle, frequencies, series, amplitude, v, plot, log)
    for path in [p for p in (output, plot) if p is not None and str(p) != "-"]:
        common.note(f"wrote {path}")
    seen = common.note_linearisation(vehicle)
    peaks = {}
    for name, (values, unit) in series.items():
        k = int(np.argmax(np.abs(values)))
        peaks[name] = {"amplitude": float(np.abs(values[k])), "frequency_hz": float(frequencies[k]), "unit": unit}
    if as_json:
        common.print_json({
            "model": str(model), "speed": v if v == v else None, "speed_kmh": v / common.KMH if v == v else None,
            "amplitude": amplitude, "linearisation": seen,
            "frequencies": frequencies,
            "outputs": {name: {"unit": unit, "amplitude": np.abs(values), "phase_deg": np.degrees(np.angle(values))}
                        for name, (values, unit) in series.items()},
            "peaks": peaks,
        })
        return 0
    stream = sys.stderr if output == "-" else sys.stdout
    kind = " and ".join(components) if components else "lateral alignment"
    where = f"sinusoidal {kind} Y = {amplitude * 1e3:g} mm at {v / common.KMH:.1f} km/h" if v == v else (
        f"each ground input alone, amplitude {amplitude * 1e3:g} mm (DOF/input)")
    print(f"{vehicle.name}: {where}, {fmin:g}-{fmax:g} Hz ({points} points)", file=stream)
    width = max([14, *(len(name) for name in peaks)])
    print(f"  {'output':<{width}} {'peak amplitude':>18} {'at f [Hz]':>10}", file=stream)
    for name, peak in peaks.items():
        print(f"  {name:<{width}} {peak['amplitude']:12.4g} {peak['unit']:<5} {peak['frequency_hz']:10.3f}", file=stream)
    if output is None:
        common.note("(-o FILE.csv writes every frequency; --json prints them)")
    return 0


def _series(vehicle: Any, dofs: list[str], frequencies: Any, amplitude: float, speed: float) -> dict:
    """name -> (complex amplitudes, unit): output points' accelerations, then the DOFs."""
    import numpy as np

    from express.analysis.frequency.frequency import frequency_response

    for dof in dofs:
        if dof not in vehicle.dofs:
            raise UsageError(f"--dof {dof}: unknown DOF{did_you_mean(dof, vehicle.dofs)} (DOFs: {', '.join(vehicle.dofs)})")
    points = [point.name for point in vehicle.facts.outputs]
    if not points and not dofs:
        raise UsageError("frf: the model has no output points ([rail.outputs]); name a DOF with --dof W1.y")
    response = frequency_response(vehicle, frequencies, amplitude=amplitude, speed=speed)
    series: dict[str, tuple[Any, str]] = {name: (np.asarray(response.acceleration_of(name)), "m/s^2") for name in points}
    for dof in dofs:
        series[dof] = (np.asarray(response.amplitude_of(dof)), coordinate_unit(dof))
    for name, (values, _unit) in series.items():
        if not np.all(np.isfinite(values)):
            raise AnalysisError(f"frf: the response of {name} is not finite at some frequency (a resonance "
                                "without damping, or values out of range)")
    return series


def _track_series(vehicle: Any, components: list[str], frequencies: Any, amplitude: float, speed: float) -> dict:
    """``<point>.a<axis>/<input>`` [m/s^2] and ``<point>.u<axis>/<input>`` [m] of every
    output point for each track component alone
    (:func:`express.analysis.frequency.track_response.track_frequency_response`)."""
    from express.analysis.frequency.track_response import track_frequency_response
    from express.base.diagnostics import ArgumentError

    try:
        response = track_frequency_response(vehicle, frequencies, components=components, amplitude=amplitude, speed=speed)
    except ArgumentError as error:
        raise UsageError(str(error)) from None
    points = [name for name, unit in zip(response.names, response.units, strict=True) if unit == "m/s^2"]
    if not points:
        raise UsageError("frf --input: the model has no output points ([rail.outputs])")
    series: dict[str, tuple[Any, str]] = {}
    for component in components:
        for name in points:
            series[f"{name}/{component}"] = (response.of(name, component), "m/s^2")
        for name in points:
            point, _, axis = name.rpartition(".")
            series[f"{point}.u{axis[1:]}/{component}"] = (response.displacement_of(name, component), "m")
    return series


def _ground_series(vehicle: Any, dofs: list[str], frequencies: Any, amplitude: float) -> dict:
    """Without rail data: ``<dof>/<input>`` -> displacement amplitude of the DOF for the
    input alone at ``amplitude`` (:func:`express.analysis.frequency.frequency.ground_response`)."""
    import numpy as np

    from express.analysis.frequency.frequency import ground_response

    for dof in dofs:
        if dof not in vehicle.dofs:
            raise UsageError(f"--dof {dof}: unknown DOF{did_you_mean(dof, vehicle.dofs)} (DOFs: {', '.join(vehicle.dofs)})")
    response = ground_response(vehicle, frequencies)
    series: dict[str, tuple[Any, str]] = {}
    for dof in dofs or vehicle.dofs:
        for name in response.inputs:
            unit = coordinate_unit(dof)
            series[f"{dof}/{name}"] = (amplitude * response.of(dof, name), unit)
    for name, (values, _unit) in series.items():
        if not np.all(np.isfinite(values)):
            raise AnalysisError(f"frf: the response of {name} is not finite at some frequency")
    return series


def _columns(frequencies: Any, series: dict) -> tuple[dict, dict]:
    """CSV columns (SI, units in the header): frequency, then amplitude and phase of each."""
    import numpy as np

    columns: dict[str, Any] = {"frequency": frequencies}
    units = {"frequency": "Hz"}
    for name, (values, unit) in series.items():
        kind = "acc_" if unit == "m/s^2" else ""
        columns[f"{name}_{kind}amplitude"] = np.abs(values)
        units[f"{name}_{kind}amplitude"] = unit
        columns[f"{name}_{kind}phase"] = np.degrees(np.angle(values))
        units[f"{name}_{kind}phase"] = "deg"
    return columns, units


def _figure(vehicle: Any, frequencies: Any, series: dict, amplitude: float, speed: float, plot: Path,
            log: bool = False) -> None:
    """One axis per unit (accelerations, displacements, rotations), log scales with ``log``."""
    import numpy as np

    from express.analysis.plots import figure_frequency_responses, save_figure

    panels: dict[str, list[dict]] = {}
    for name, (values, unit) in series.items():
        label = _LABELS.get(name, name)
        panels.setdefault(unit, []).append({"label": label, "values": np.abs(values)})
    title = (f"{vehicle.name}: response to Y = {amplitude * 1e3:g} mm at {speed / common.KMH:.0f} km/h"
             if speed == speed else f"{vehicle.name}: response to each ground input ({amplitude * 1e3:g} mm)")
    save_figure(figure_frequency_responses(frequencies, panels, title=title, log=log), plot)


def main(argv: Sequence[str] | None = None) -> int:
    """``express frf`` with ``argv`` (default ``sys.argv[1:]``) alone: its exit status
    (:func:`express.cli.runner.run_command`, the parsing and errors of :func:`express.cli.main`)."""
    return run_command(sys.modules[__name__], argv)
