"""The sections of ``express report``: model, parameters, equations, modes, stability,
curving and frequency response, built from one numerical vehicle.

Rail sections (stability, curving, frequency response) appear only for a model with
rail data; a model without rail data reports its drawing, parameters, equations and
modes.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace
from pathlib import Path

import numpy as np
import sympy as sp

from express.analysis.stability.critical_options import CriticalOptions
from express.assembly.equations import EquationsOfMotion
from express.base.units import KMH
from express.drawing.geometry import model_geometry
from express.drawing.views import figure_model
from express.model.parameters import expression_value
from express.model.records import Model
from express.model.topology import classify_bodies
from express.numeric.statespace import VehicleModel
from express.report.page import Figure, Math, Section, Table, render_page, svg_of

__all__ = ["MAX_EQUATION_ENTRIES", "report_html"]

#: Matrix entries shown in the equations section (the rest is counted, not shown).
MAX_EQUATION_ENTRIES = 300


def _value_of(vehicle: VehicleModel) -> Callable[[object], float]:
    values = vehicle.values

    def value(expression) -> float:
        return expression_value(expression, values)  # KeyError naming a name without value

    return value


def _model_of(vehicle: VehicleModel) -> Model:
    if vehicle.model is None:
        raise ValueError("the vehicle has no model to report on")
    return vehicle.model


def _source_comment(source: str, line: int | None) -> str:
    """The comment at the end of a parameter's line in its file (its documented source)."""
    if line is None:
        return ""
    try:
        text = Path(source).read_text(encoding="utf-8").splitlines()[line - 1]
    except (OSError, IndexError, UnicodeDecodeError):
        return ""
    quote = None
    for i, character in enumerate(text):
        if character in "\"'" and quote in (None, character):
            quote = None if quote == character else character
        elif character == "#" and quote is None:
            return text[i + 1:].strip()[:300]
    return ""


def _plural(count: int, one: str, many: str) -> str:
    return f"{count} {one if count == 1 else many}"


def _model_section(vehicle: VehicleModel) -> Section:
    model = _model_of(vehicle)
    equations = vehicle.equations
    topology = classify_bodies(model)
    geometry = model_geometry(model, _value_of(vehicle), topology.role)
    counts = {role: sum(1 for r in topology.role.values() if r == role) for role in ("wheelset", "bogie", "lever", "body")}
    summary = (
        f"{len(model.bodies)} bodies ({counts['wheelset']} wheelsets, {counts['bogie']} bogies, "
        f"{counts['lever']} levers, {_plural(counts['body'], 'car body', 'car bodies')}), {len(model.points)} connection points, "
        f"{len(model.elements)} elements, {len(model.pins)} pinned joints; {len(equations.dofs)} DOFs after "
        f"eliminating {len(equations.eliminated)} virtual DOFs; {len(equations.inputs)} inputs."
    )
    figure = figure_model(geometry)
    return Section("Model", (summary, Figure(svg_of(figure), "Plan, side and end views of the model.")))


def _parameters_section(vehicle: VehicleModel) -> Section:
    model = _model_of(vehicle)
    rows = []
    for name, parameter in sorted(model.parameters.items(), key=lambda item: item[0].lower()):
        shown = f"{parameter.value:.6g} SI" if not parameter.unit else f"{parameter.value:.6g} (SI) [{parameter.unit}]"
        try:
            from express.base.units import format_quantity

            shown = format_quantity(parameter.value, parameter.unit) if parameter.unit else f"{parameter.value:.6g}"
        except (ImportError, ValueError):
            pass
        rows.append((name, shown, float(parameter.value), _source_comment(model.source, parameter.line)))
    return Section("Parameters", (Table(("name", "value", "SI value", "source"), rows),))


def _equations_section(vehicle: VehicleModel, readable: EquationsOfMotion | None) -> Section:
    equations = readable if readable is not None else vehicle.equations
    entries: list[tuple[str, str]] = []
    total = 0
    for key in ("M", "C", "K"):
        matrix = equations.matrices.get(key)
        if matrix is None:
            continue
        for (i, j), value in sorted(matrix.todok().items()):
            total += 1
            if len(entries) < MAX_EQUATION_ENTRIES:
                label = f"{key}[{equations.dofs[i]}, {equations.dofs[j]}]"
                entries.append((label, sp.mathml(value, printer="presentation")))
    parts: list = [
        "M q'' + C q' + K q = P u + Pd u' with q the DOFs below; the non-zero entries of M, C and K "
        "(exact, virtual DOFs eliminated):",
        Math(entries),
    ]
    if total > len(entries):
        parts.append(f"{total - len(entries)} more non-zero entries are in `express generate` outputs.")
    parts.append("DOFs: " + ", ".join(equations.dofs))
    return Section("Equations", tuple(parts))


def _modes_section(vehicle: VehicleModel, speed: float) -> Section:
    from express.analysis.stability.stability import eigen_analysis
    from express.report.figures import mode_figures

    result = eigen_analysis(vehicle, speed)
    rows = [(k + 1, m.real, m.imag, m.frequency_hz, m.damping_ratio, m.describe()) for k, m in enumerate(result.modes)]
    at = f" at {speed / KMH:.1f} km/h" if vehicle.layout is not None else ""
    model = _model_of(vehicle)
    geometry = model_geometry(model, _value_of(vehicle), classify_bodies(model).role)
    shapes = [Figure(svg_of(figure), caption) for figure, caption in mode_figures(vehicle, geometry, speed, result.modes)]
    return Section("Modes", (
        f"{len(rows)} modes{at}, least stable first; {'stable' if result.stable else 'UNSTABLE'}. Names from the "
        "distribution of each mode's kinetic energy (docs/analyses.md).",
        Table(("mode", "Re [1/s]", "Im [rad/s]", "f [Hz]", "damping ratio", "description"), rows),
        *shapes,
    ))


def _stability_section(vehicle: VehicleModel) -> Section:
    from express.analysis.plots import figure_eigen_locus
    from express.analysis.stability.stability import critical_speed, root_locus

    options = CriticalOptions()
    v_min, v_max = options.v_min, options.v_max
    result = critical_speed(vehicle, options)
    text = result.describe() if result.found else f"stable up to {v_max / KMH:.0f} km/h"
    speeds = np.linspace(v_min, v_max, 200)
    figure = figure_eigen_locus(speeds / KMH, root_locus(vehicle, speeds), title="real parts of the eigenvalues",
                                critical_kmh=result.speed_kmh if result.found and not result.unstable_at_min else None)
    return Section("Stability", (f"Hunting: {text}.", Figure(svg_of(figure), "Real parts of the eigenvalues against speed.")))


def curving_speed(vehicle: VehicleModel, track, speed: float | None) -> tuple[float, str]:
    """The speed of the curving run and how it was chosen: the report's ``speed`` when
    given (as ``simulate --speed``), else the track's, else the model's."""
    if speed is not None:
        return speed, "the report's speed"
    if track is not None and track.speed is not None:
        return track.speed, "the track's speed"
    return vehicle.speed, "the model's speed"


def _curving_section(vehicle: VehicleModel, track=None, track_name: str = "", speed: float | None = None) -> Section:
    """A run along ``track`` (default: the paper's curve) at :func:`curving_speed`, with
    its EN 14363 running-safety assessment; a run that diverges (a vehicle unstable at
    that speed) is told, not raised."""
    from express.analysis.curving.assessment import assess_run
    from express.analysis.curving.steady import track_problems
    from express.analysis.time.divergence import divergence_message, find_divergence
    from express.analysis.time.simulate import simulate
    from express.rail.track.named import named_track

    if track is None:  # the paper's layout at the model's speed
        track, _ = named_track("paper")
        track = replace(track, speed=None)
        track_name = "no track given: the paper's Fig. 9 curve (R = 400 m, 95 mm cant, 95 m sine transitions)"
    speed, said = curving_speed(vehicle, track, speed)
    problems = track_problems(vehicle, track, speed)
    if problems:
        return Section("Curving", (f"Track: {track_name}. Not run at {speed / KMH:.0f} km/h ({said}): "
                                   + "; ".join(problems) + ". Give a track that suits the vehicle (--track).",))
    run = simulate(vehicle, track, speed=speed, progress=False)
    divergence = find_divergence(run, vehicle)
    if divergence is not None:
        return Section("Curving", (f"Track: {track_name}. Run at {speed / KMH:.0f} km/h ({said}): no result, "
                                   f"{divergence_message(run, vehicle, divergence)}.",))
    from express.analysis.time.step_check import checked_simulation

    def assessed(result):  # ((run, wheel/rail outputs), assessment)
        wheel_rail, assessment = assess_run(vehicle, track, result)
        return (result, wheel_rail), assessment

    (run, wheel_rail), assessment, check = checked_simulation(
        vehicle, lambda dt: simulate(vehicle, track, speed=speed, dt=dt, progress=False), assessed,
        float(run.options["dt"]), first=assessed(run))
    run.outputs.update({k: v for k, v in wheel_rail.columns().items() if k not in run.outputs})
    units = run.units()
    rows = [(name, f"{value:.6g}", units.get(name, "")) for name, value in run.max_abs().items()]
    checks = [(c.name, c.quantity, f"{c.value:.4g}", "-" if c.limit is None else f"{c.limit:.4g}",
               "n/a" if c.passed is None else ("pass" if c.passed else "FAIL")) for c in assessment.criteria]
    verdict = (f"The vehicle derails: {assessment.derailment}." if assessment.derailment is not None
               else f"Running safety: {'every limit met' if assessment.passed else 'a limit is exceeded'}.")
    from express.analysis.plots import figure_simulation
    from express.report.figures import figure_assessment

    run_figure = figure_simulation(run.distance, run.outputs, title=f"{vehicle.equations.name}: {track_name[:60]}")
    safety = figure_assessment(assessment.criteria)
    return Section("Curving", (
        f"Track: {track_name}. Run of {track.length:.0f} m at {speed / KMH:.0f} km/h ({said}) with the wheel/rail "
        f"contact; wheel loads: {wheel_rail.loads} (docs/curving.md).",
        Figure(svg_of(run_figure), "Curvature, wheelset yaw relative to the bogie and lateral wheel/rail forces "
                                   "against the distance of the leading wheelset."),
        "Largest absolute values:",
        Table(("output", "max |value|", "unit"), rows),
        f"EN 14363 running-safety quantities (2 m sliding means; docs/curving.md). {verdict} The time "
        f"{check.sentence()} (docs/curving.md, \"The step is checked\").",
        *([Figure(svg_of(safety), "Each EN 14363 quantity against its limit (1 = the limit).")] if safety else []),
        Table(("criterion", "quantity", "value (SI)", "limit", "verdict"), checks),
    ))


def _frequency_section(vehicle: VehicleModel, speed: float) -> Section | None:
    """The response at the output points at ``speed``; for a vehicle unstable there, the
    instability (the steady response does not exist) instead of an error."""
    from express.analysis.frequency.frequency import frequency_response
    from express.analysis.plots import figure_frequency_response
    from express.base.diagnostics import AnalysisError

    rail = _model_of(vehicle).rail
    points = [p.name for p in rail.outputs] if rail is not None else []
    if not points:
        return None
    frequencies = np.geomspace(0.1, 20.0, 200)
    try:
        response = frequency_response(vehicle, frequencies, speed=speed)
    except AnalysisError as error:
        return Section("Frequency response", (f"Not given at {speed / KMH:.1f} km/h: {error}.",))
    curves, rows = [], []
    for name in points:
        amplitude = np.abs(np.asarray(response.acceleration_of(name)))
        k = int(np.argmax(amplitude))
        rows.append((name, float(amplitude[k]), float(frequencies[k])))
        curves.append({"label": name, "values": amplitude})
    figure = figure_frequency_response(frequencies, curves, title="response to a 1 mm lateral irregularity")
    return Section("Frequency response", (
        Table(("output point", "peak acceleration [m/s²]", "at f [Hz]"), rows),
        Figure(svg_of(figure), "Acceleration amplitude against frequency (1 mm sinusoidal alignment)."),
    ))


def report_html(
    vehicle: VehicleModel, *, speed: float | None = None, track=None, track_name: str = "",
    equations: EquationsOfMotion | None = None,
) -> str:
    """The whole report of ``vehicle`` as an HTML document (see the module docstring).

    Parameters
    ----------
    vehicle : VehicleModel
        Numerical vehicle with its model (``express.numeric.statespace.load_vehicle``).
    speed : float, optional
        Speed of the report [m/s]: of the modes table, the curving run and the frequency
        response (as ``--speed`` of the other commands); by default the model's speed (1 m/s
        for a model without rail data, whose matrices do not depend on it) and, for the
        curving run, the track's own speed when it has one.  A section that has no result
        at that speed (an unstable vehicle's frequency response, a diverged run) says so,
        and the other sections are given.
    track : Track, optional
        The track of the curving section (default: the paper's curve, said so).
    track_name : str
        How the report names the track.
    equations : EquationsOfMotion, optional
        The readable (factored) equations to show
        (:func:`express.numeric.generation.load_generation`, which ``express report``
        passes from its cache); by default generated readable from the vehicle's model,
        so that the library's report is the command's.
    """
    if vehicle.model is None:
        raise ValueError("the vehicle has no model to report on")
    rail = vehicle.layout is not None and bool(vehicle.wheelsets)
    given = speed
    if speed is None:
        speed = vehicle.speed if rail and np.isfinite(vehicle.speed) else 1.0
    if equations is None:
        from express.rail.build import generate_vehicle

        equations = generate_vehicle(vehicle.model).equations  # factored for people, as the command shows
    sections = [_model_section(vehicle), _parameters_section(vehicle), _equations_section(vehicle, equations),
                _modes_section(vehicle, speed)]
    if rail:
        sections += [_stability_section(vehicle), _curving_section(vehicle, track, track_name, given)]
        frequency = _frequency_section(vehicle, speed)
        if frequency is not None:
            sections.append(frequency)
    title = f"EXPRESS report: {vehicle.equations.name}"
    return render_page(title, sections, note=f"Model file {vehicle.model.source}.")
