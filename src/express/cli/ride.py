"""``express ride``: ride comfort and wheel forces on a random track,
:func:`express.analysis.ride.vehicle.ride_response` (``docs/ride.md``)."""

from __future__ import annotations

import csv
import math
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from express.base.diagnostics import AnalysisError, ModelError, Problem, UsageError
from express.cli import common
from express.cli.runner import run_command

__all__ = ["MAX_POINTS", "TRACK_CLASSES", "add_parser", "main", "read_psd_table", "run"]

#: Most frequencies one run computes.
MAX_POINTS = 100_000
#: The track classes of :data:`express.analysis.ride.vehicle.TRACK_CLASSES`, for --help
#: without importing NumPy (a test keeps the two equal).
TRACK_CLASSES = ("ERRI-low", "ERRI-high", *(f"FRA-{k}" for k in range(1, 7)), *(f"AAR-{k}" for k in range(1, 7)))
#: RMS below which a direction counts as not excited (not drawn) [m/s^2].
_NEGLIGIBLE = 1e-9
_PSD_UNITS = {"n": ("1/m", {"m^2/(1/m)", "m^3"}), "omega": ("rad/m", {"m^2/(rad/m)", "m^3/rad", "m^3"})}
#: Largest PSD value of a table [m^3]: over a band of 1e-3 1/m an irregularity of 1 m RMS, far
#: beyond any track; larger values (1e300) only overflow the response (docs/reliability.md).
PSD_MAX = 1e3
#: Largest wavenumber of a table [1/m or rad/m]: a wavelength below a millimetre.
WAVENUMBER_MAX = 1e4


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser(
        "ride", help="ride comfort (Sperling Wz, EN 12299 N_MV) and wheel forces on a random track",
        description="Stationary random response of the vehicle to track irregularity spectra (alignment, "
        "vertical, cross level, gauge), wheelsets delayed behind the leading one: per output point the RMS "
        "accelerations, Sperling's Wz and EN 12299's N_MV; per wheelset the lateral wheel force Y, the "
        "dynamic wheel load dQ and Y/Q. See docs/ride.md.",
    )
    common.add_model_arguments(parser)
    parser.add_argument("--track", required=True, metavar="CLASS|FILE.csv|FILE.toml",
                        help=f"track class ({', '.join(TRACK_CLASSES)}), a CSV table of PSD against "
                        "wavenumber, or a track file whose components are spectra (each over its band; "
                        "docs/ride.md)")
    parser.add_argument("--speed", type=common.SPEED, metavar="SPEED", help=common.SPEED.help("running speed", "the model's speed"))
    parser.add_argument("--fmin", type=common.FMIN, default=0.1, metavar="F",
                        help=common.FMIN.help("lowest frequency", "0.1 Hz"))
    parser.add_argument("--fmax", type=common.FMAX, default=50.0, metavar="F",
                        help=common.FMAX.help("highest frequency, above --fmin", "50 Hz"))
    parser.add_argument("--points", type=common.count("--points", 16, MAX_POINTS), default=2000,
                        help=f"number of frequencies, log-spaced; 16 <= --points <= {MAX_POINTS}; default 2000")
    parser.add_argument("-o", "--output", metavar="FILE", help="the PSDs as CSV, units in the header (- for standard output)")
    parser.add_argument("--plot", type=common.figure_path, metavar="FILE", help="acceleration PSDs with weighted curves (.png, .svg or .pdf)")
    parser.add_argument("--modes-convergence", action="store_true",
                        help="with flexible bodies: the floor RMS and N_MV with 0, 1, ... of their modes kept, "
                        "by frequency (a dropped mode's shapes set to zero; docs/ride.md, 'How many modes')")
    common.add_json_option(parser)
    common.add_linearisation_arguments(parser, statistical=True)
    parser.set_defaults(handler=run, numeric=True)


def run(
    model: Path, overrides: dict[str, str], *, track: str, speed: float | None = None, fmin: float = 0.1,
    fmax: float = 50.0, points: int = 2000, output: str | None = None, plot: Path | None = None,
    as_json: bool = False, modes_convergence: bool = False, linearisation: str = "tangent", element_amplitude: float | None = None, element_angle: float | None = None, element_frequency: float | None = None,
) -> int:
    """Compute the response and write the outputs all together; returns the exit status."""
    import numpy as np

    spec = common.linearisation_spec(linearisation, element_amplitude, element_angle, element_frequency)

    if modes_convergence:
        if output is not None or plot is not None:
            raise UsageError("--modes-convergence prints a table (or --json); -o and --plot go without it")
        if not fmax > fmin:
            raise UsageError(f"--fmax {fmax:g} Hz: must be above --fmin {fmin:g} Hz")
        if spec.kind == "statistical":
            raise UsageError("--modes-convergence: with --linearisation tangent or equivalent (the statistical "
                             "iteration is of one response)")
        return _modes_convergence(model, overrides, track, speed, np.geomspace(fmin, fmax, points), as_json, spec)
    from express.analysis.ride.summaries import point_comfort, wheel_forces
    from express.analysis.ride.vehicle import linear_instability
    from express.io.finite import require_finite
    from express.io.output import output_transaction

    if not fmax > fmin:
        raise UsageError(f"--fmax {fmax:g} Hz: must be above --fmin {fmin:g} Hz")
    if output == "-" and as_json:
        raise UsageError("-o - and --json both write to standard output; choose one")
    table = _is_table(track)
    with output_transaction([model, *([track] if table or _is_track_file(track) else [])]) as transaction:
        for path, binary in ((output, False), (plot, True)):
            if path is not None:
                transaction.declare(path, binary=binary)
        spectra, track_name, track_notes = _spectra(track, table)
        vehicle = common.linearised_vehicle(common.load_rail_vehicle(model, overrides, "ride"), spec)
        v = common.running_speed(vehicle, speed)
        instability = linear_instability(vehicle, v)
        if instability is not None:  # no PSD exists: the nonlinear run's ride, nothing written
            nonlinear = _nonlinear(vehicle, spectra, v)
        else:
            response, vehicle = _response(vehicle, spectra, v, np.geomspace(fmin, fmax, points), spec)
            require_finite("ride: the response PSD (output x frequency)", response.psd)  # before the comfort sums
            comfort = point_comfort(response)
            wheels = wheel_forces(response, vehicle)
            if output is not None:
                _write_csv(output, response)
            if plot is not None:
                _figure(vehicle, response, track_name, plot)
    if instability is not None:
        return _report_nonlinear(model, vehicle.equations.name, track_name, instability, nonlinear, as_json,
                                 [p for p in (output, plot) if p is not None], track_notes)
    for path in [p for p in (output, plot) if p is not None and str(p) != "-"]:
        common.note(f"wrote {path}")
    summary = {**_summary(model, track_name, response, comfort, wheels),
               "linearisation": common.note_linearisation(vehicle)}
    summary["notes"] = [*track_notes, *summary["notes"]]
    if as_json:
        common.print_json(summary)
    else:
        _print_table(vehicle.equations.name, summary, sys.stderr if output == "-" else sys.stdout)
    for line in summary["notes"]:
        common.note(f"note: {line}")
    return 0


def _response(vehicle: Any, spectra: dict, speed: float, frequencies: Any, spec: Any) -> tuple[Any, Any]:
    """The ride response and the vehicle it is of: with ``--linearisation statistical``
    the fixed point of :func:`express.analysis.ride.statistical.statistical_ride`."""
    if spec.kind != "statistical":
        from express.analysis.ride.vehicle import ride_response

        return ride_response(vehicle, spectra, speed, frequencies), vehicle
    from express.analysis.ride.statistical import statistical_ride

    result = statistical_ride(vehicle, spectra, speed, frequencies)
    if not result.success:
        raise AnalysisError(f"ride: --linearisation statistical: {result.message}")
    common.note(f"statistical linearisation: {result.message} after {result.iterations} iterations")
    return result.response, result.vehicle


def _nonlinear(vehicle: Any, spectra: dict, speed: float) -> Any:
    """The ride of the nonlinear run (:func:`express.analysis.ride.nonlinear.simulated_ride`)."""
    from express.analysis.ride.nonlinear import simulated_ride
    from express.base.diagnostics import InputError

    try:
        return simulated_ride(vehicle, spectra, speed)
    except InputError as error:
        raise UsageError(str(error)) from None


def _report_nonlinear(model: Path, name: str, track: str, instability: str, ride: Any, as_json: bool,
                      not_written: list, track_notes: tuple[str, ...] = ()) -> int:
    """Print the linear model's instability and the nonlinear run's comfort; exit 0."""
    notes = [*track_notes, *ride.notes] + [f"{path}: not written (no PSD exists above the linear critical speed)"
                                           for path in not_written]
    if as_json:
        common.print_json({
            "model": str(model), "track": track, "speed": ride.speed, "speed_kmh": ride.speed / common.KMH,
            "linear": {"stable": False, "reason": instability},
            "nonlinear_run": {"length_m": ride.length, "dt_s": ride.dt, "components": list(ride.components),
                              "flange_contact": ride.flange_contact,
                              "output_points": {point: c.as_dict() for point, c in ride.comfort.items()}},
            "notes": notes, "units": {"rms": "m/s^2", "weighted_rms": "m/s^2", "a_p95": "m/s^2", "speed": "m/s"},
        })
    else:
        print(f"{name}: track {track} at {ride.speed / common.KMH:.1f} km/h: the linear model is unstable "
              f"({instability}), no stationary PSD exists; the ride of the nonlinear run ({ride.length:g} m, "
              f"step {ride.dt * 1e3:g} ms, flange contact {'reached' if ride.flange_contact else 'not reached'}):")
        print(f"  {'point':<14} {'a_x rms':>9} {'a_y rms':>9} {'a_z rms':>9} {'Wz_y':>6} {'Wz_z':>6} {'N_MV':>6}   (m/s^2)")
        for point, c in ride.comfort.items():
            rms = "".join(f" {c.rms[a]:9.4f}" if a in c.rms else f" {'-':>9}" for a in "xyz")
            wz = "".join(f" {c.wz[a]:6.2f}" if a in c.wz else f" {'-':>6}" for a in "yz")
            print(f"  {point:<14}{rms}{wz} {c.n_mv:6.2f}")
    for line in notes:
        common.note(f"note: {line}")
    return 0


def _modes_convergence(model: Path, overrides: dict[str, str], track: str, speed: float | None, frequencies: Any,
                       as_json: bool, spec: Any) -> int:
    """``--modes-convergence``: the comfort with 0, 1, ... modes kept
    (:func:`express.analysis.ride.mode_count.mode_count_convergence`)."""
    from express.analysis.ride.mode_count import mode_count_convergence
    from express.base.diagnostics import ArgumentError

    spectra, track_name, track_notes = _spectra(track, _is_table(track))
    for line in track_notes:
        common.note(f"note: {line}")
    vehicle = common.linearised_vehicle(common.load_rail_vehicle(model, overrides, "ride"), spec)
    v = common.running_speed(vehicle, speed)
    try:
        steps = mode_count_convergence(vehicle, spectra, v, frequencies)
    except ArgumentError as error:
        raise UsageError(f"--modes-convergence: {error}") from None
    if as_json:
        common.print_json({"model": str(model), "track": track_name, "speed": v, "speed_kmh": v / common.KMH,
                           "frequency_band_hz": [float(frequencies[0]), float(frequencies[-1])],
                           "steps": [step.as_dict() for step in steps],
                           "units": {"rms": "m/s^2", "weighted_rms": "m/s^2", "frequency_hz": "Hz"}})
        return 0
    points = list(steps[0].comfort)
    print(f"{vehicle.equations.name}: ride against the flexible modes kept (by frequency), track {track_name} at "
          f"{v / common.KMH:.1f} km/h, {frequencies[0]:g}-{frequencies[-1]:g} Hz ({len(frequencies)} points)")
    print(f"  {'modes kept':<50}" + "".join(f" {p[:19]:>19}" for p in points))
    print(f"  {'':<50}" + "".join(f" {'a_z rms':>10} {'N_MV':>8}" for _ in points) + "   (m/s^2)")
    for step in steps:
        added = "0  rigid" if step.added is None else f"{step.count}  + {step.label} ({step.frequency_hz:.2f} Hz)"
        cells = "".join(f" {step.comfort[p].rms.get('z', float('nan')):10.5f} {step.comfort[p].n_mv:8.4f}" for p in points)
        print(f"  {added:<50}{cells}")
    return 0


# --- the track ---------------------------------------------------------------------------


def _is_track_file(track: str) -> bool:
    return track.lower().endswith(".toml")


def _is_table(track: str) -> bool:
    """A PSD table: a .csv name, or any other existing path but a track file (a device or
    directory: refused by its kind)."""
    return not _is_track_file(track) and (track.lower().endswith(".csv") or Path(track).exists())


def _spectra(track: str, table: bool) -> tuple[dict, str, tuple[str, ...]]:
    """The spectra by component, the track's name and notes on how they were taken."""
    from express.analysis.ride.vehicle import track_class_spectra
    from express.base.diagnostics import InputError

    if _is_track_file(track):
        return _track_file_spectra(Path(track))
    if table:
        return read_psd_table(Path(track)), track, ()
    try:
        spectra = track_class_spectra(track)
    except InputError as error:
        raise UsageError(f"--track: {error}") from None
    return spectra, track, ()


def _track_file_spectra(path: Path) -> tuple[dict, str, tuple[str, ...]]:
    """The spectra of a track file's random components (``type = "spectrum"``), each over
    the band its realisation is drawn over (:func:`express.rail.track.component_spectra.
    track_spectra`), and notes: the components taken, the shapes left out, the layout."""
    from express.rail.track import Straight, load_track
    from express.rail.track.component_spectra import track_spectra

    loaded = load_track(path)  # a bad file: ModelError, every problem with its line
    spectra, notes = track_spectra(loaded)
    if not spectra:
        raise UsageError(f"--track {path}: the track file has no random component: give [irregularity], "
                         "[vertical], [cross_level] or [gauge] a type = \"spectrum\" (docs/track.md), or use a "
                         "track class or a PSD table")
    taken = [f"{component} from {spectrum.name}" for component, spectrum in spectra.items()]
    lines = [f"track file {path}: {'; '.join(taken)} (mutually uncorrelated, each fully coherent between the "
             "wheelsets with its delay: docs/ride.md)", *notes]
    if any(not isinstance(segment, Straight) for segment in loaded.segments):
        lines.append(f"track file {path}: its curves and cant are not used (the ride is on straight track)")
    return spectra, str(path), tuple(lines)


def _header_cell(cell: str) -> tuple[str, str | None]:
    name, _, unit = cell.strip().partition("[")
    return name.strip(), (unit.rstrip().rstrip("]").replace(" ", "") if unit else None)


def read_psd_table(path: Path) -> dict:
    """A user's track spectra: CSV, first column ``n [1/m]`` (cycles per metre) or
    ``Omega [rad/m]``, then one column per component (``alignment``, ``vertical``,
    ``cross_level``, ``gauge``) of PSD per that wavenumber (``m^2/(1/m)`` or
    ``m^2/(rad/m)``; units in brackets optional).  ``#`` lines are comments.

    Returns
    -------
    dict of str to express.rail.track.tabulated_spectra.TabulatedSpectrum

    Raises
    ------
    ModelError
        Every problem with its line: header, numbers, negative PSD, wavenumbers that do
        not increase.
    UsageError
        The file cannot be read.
    """
    from express.rail.track.spectra import COMPONENTS
    from express.rail.track.tabulated_spectra import TabulatedSpectrum

    source = str(path)
    from express.base.limits import read_input_text

    text = read_input_text(path, "PSD table", what="the PSD table")  # bounded, UTF-8, refused by its kind
    rows = [(number, cells) for number, cells in enumerate(csv.reader(text.splitlines()), 1)
            if cells and "".join(cells).strip() and not cells[0].lstrip().startswith("#")]
    problems: list[Problem] = []
    if not rows:
        raise ModelError([Problem(source, None, "PSD table", "empty: need a header and at least two rows")])
    header_line, header = rows[0]
    columns = [_header_cell(cell) for cell in header]
    first, first_unit = columns[0][0].lower(), columns[0][1]
    if first not in _PSD_UNITS:
        problems.append(Problem(source, header_line, "PSD table", f"first column must be 'n [1/m]' or 'Omega [rad/m]', got {header[0].strip()!r}"))
        first = "n"
    elif first_unit is not None and first_unit != _PSD_UNITS[first][0]:
        problems.append(Problem(source, header_line, f"column {columns[0][0]}", f"unit must be {_PSD_UNITS[first][0]}, got {first_unit!r}"))
    seen: set[str] = set()
    for name, unit in columns[1:]:
        if name in seen:
            problems.append(Problem(source, header_line, f"column {name}", "given twice: one column per component"))
        seen.add(name)
        if name not in COMPONENTS:
            problems.append(Problem(source, header_line, f"column {name or '(empty)'}", f"unknown component; known: {', '.join(COMPONENTS)}"))
        elif unit is not None and unit not in _PSD_UNITS[first][1]:
            problems.append(Problem(source, header_line, f"column {name}", f"unit must be one of {', '.join(sorted(_PSD_UNITS[first][1]))}, got {unit!r}"))
    if len(columns) < 2:
        problems.append(Problem(source, header_line, "PSD table", "needs a wavenumber column and at least one PSD column"))
    values = _table_values(source, rows[1:], len(columns), [c[0] for c in columns], problems)
    if len(values) < 2 and not problems:
        problems.append(Problem(source, None, "PSD table", f"needs at least two rows of numbers, got {len(values)}"))
    if problems:
        raise ModelError(problems)
    unit = "1/m" if first == "n" else "rad/m"
    wavenumbers = [row[1][0] for row in values]
    return {name: TabulatedSpectrum.from_table(f"{path.name} {name}", wavenumbers, [row[1][k] for row in values], unit, name)
            for k, (name, _) in enumerate(columns) if k > 0}


def _table_values(source: str, rows: list, width: int, names: list[str], problems: list[Problem]) -> list:
    """Numbers of the data rows, with a problem for each bad cell, negative PSD or
    wavenumber that does not increase."""
    values: list = []
    for number, cells in rows:
        if len(cells) != width:
            problems.append(Problem(source, number, "PSD table", f"expected {width} values, got {len(cells)}"))
            continue
        try:
            numbers = [float(cell) for cell in cells]
        except ValueError:
            problems.append(Problem(source, number, "PSD table", f"not a number in {','.join(cells)!r}"))
            continue
        if not all(math.isfinite(x) for x in numbers):
            problems.append(Problem(source, number, "PSD table", "values must be finite"))
            continue
        if not 0 <= numbers[0] <= WAVENUMBER_MAX:
            problems.append(Problem(source, number, f"column {names[0]}",
                                    f"wavenumber must be in 0 ... {WAVENUMBER_MAX:g}, got {numbers[0]:g}"))
        for k in range(1, width):
            if not 0 <= numbers[k] <= PSD_MAX:
                problems.append(Problem(source, number, f"column {names[k]}",
                                        f"PSD must be in 0 ... {PSD_MAX:g} m^3 (an irregularity of metres), got {numbers[k]:g}"))
        if values and numbers[0] <= values[-1][1][0]:
            problems.append(Problem(source, number, f"column {names[0]}", f"wavenumbers must increase: {numbers[0]:g} "
                                    f"after {values[-1][1][0]:g} (line {values[-1][0]})"))
        values.append((number, numbers))
    return values


# --- outputs -----------------------------------------------------------------------------


def _summary(model: Path, track: str, response: Any, comfort: dict, wheels: dict) -> dict:
    f = response.frequencies
    return {
        "model": str(model), "track": track, "speed": response.speed, "speed_kmh": response.speed / common.KMH,
        "frequency_band_hz": [float(f[0]), float(f[-1])], "points": int(f.size),
        "components": list(response.components), "notes": [*response.notes, *(line for w in wheels.values() for line in w.notes())],
        "output_points": {name: c.as_dict() for name, c in comfort.items()},
        "wheelsets": {name: w.as_dict() for name, w in wheels.items()},
        "units": {"rms": "m/s^2", "weighted_rms": "m/s^2", "a_p95": "m/s^2", "wheel_load": "N", "y_rms": "N",
                  "dq_rms": "N", "y_rel_rms": "m", "flange_clearance": "m", "speed": "m/s"},
    }


def _print_table(name: str, summary: dict, stream) -> None:
    band = summary["frequency_band_hz"]
    print(f"{name}: track {summary['track']} at {summary['speed_kmh']:.1f} km/h, {band[0]:g}-{band[1]:g} Hz "
          f"({summary['points']} points); components: {', '.join(summary['components']) or 'none'}", file=stream)
    print(f"  {'point':<14} {'a_x rms':>9} {'a_y rms':>9} {'a_z rms':>9} {'Wz_y':>6} {'Wz_z':>6} {'N_MV':>6}   (m/s^2)",
          file=stream)
    for point, c in summary["output_points"].items():
        rms = "".join(f" {c['rms'][a]:9.4f}" if a in c["rms"] else f" {'-':>9}" for a in "xyz")
        wz = "".join(f" {c['wz'][a]:6.2f}" if a in c["wz"] else f" {'-':>6}" for a in "yz")
        print(f"  {point:<14}{rms}{wz} {c['n_mv']:6.2f}", file=stream)
    print(f"  {'wheelset':<10} {'Y rms':>7} {'dQ rms L/R':>15} {'Y/Q0 rms':>9} {'Y/Q 3-sigma L/R':>17} {'y-yR rms':>9}",
          file=stream)
    print(f"  {'':<10} {'[kN]':>7} {'[kN]':>15} {'':>9} {'(dynamic Q)':>17} {'[mm]':>9}", file=stream)
    for wheelset, w in summary["wheelsets"].items():
        dq = f"{w['dq_rms']['L'] / 1e3:.2f}/{w['dq_rms']['R'] / 1e3:.2f}" if w["dynamic_q"] else "-"
        levels = "/".join("unloads" if w["unloads"][side] else f"{w['yq_level'][side]:.3f}" for side in "LR")
        print(f"  {wheelset:<10} {w['y_rms'] / 1e3:7.2f} {dq:>15} {w['yq_rms']:9.4f} {levels:>17} "
              f"{w['y_rel_rms'] * 1e3:9.2f}", file=stream)


def _psd_unit(unit: str) -> str:
    return {"m/s^2": "m^2/s^4/Hz", "N": "N^2/Hz", "m": "m^2/Hz"}.get(unit, f"({unit})^2/Hz")


def _write_csv(output: str, response: Any) -> None:
    from express.io.output import write_csv

    columns: dict[str, Any] = {"frequency": response.frequencies}
    units = {"frequency": "Hz"}
    for component in response.components:
        columns[f"track_{component}_psd"] = response.input_psd[component]
        units[f"track_{component}_psd"] = "m^2/Hz"
    for name, unit in zip(response.names, response.units, strict=True):
        columns[f"{name}_psd"] = response.psd_of(name)
        units[f"{name}_psd"] = _psd_unit(unit)
    write_csv(output, columns, units)


def _figure(vehicle: Any, response: Any, track: str, plot: Path) -> None:
    from express.analysis.plots import save_figure
    from express.analysis.ride.figures import figure_ride_spectra

    spectra = {}
    for point, axes in response.directions.items():
        kept = {a: response.psd_of(f"{point}.a{a}") for a in axes if response.rms(f"{point}.a{a}") > _NEGLIGIBLE}
        if kept:
            spectra[point] = kept
    if not spectra:
        raise UsageError(f"--plot: {vehicle.equations.name} has no excited output point ([rail.outputs]) to draw")
    title = f"{vehicle.equations.name}: track {track}, {response.speed / common.KMH:.0f} km/h"
    caption = "solid: PSD; dashed: EN 12299 weighted (Wd lateral/longitudinal, Wb vertical); dotted: Sperling B²·PSD"
    save_figure(figure_ride_spectra(response.frequencies, spectra, title=title, caption=caption), plot)


def main(argv: Sequence[str] | None = None) -> int:
    """``express ride`` with ``argv`` (default ``sys.argv[1:]``) alone: its exit status
    (:func:`express.cli.runner.run_command`, the parsing and errors of :func:`express.cli.main`)."""
    return run_command(sys.modules[__name__], argv)
