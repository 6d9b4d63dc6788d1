"""Sensitivities of the time-run outputs of a study: derivatives of EN 14363's largest
``(Y/Q)2m``, ``(ΣY)2m`` and ``ΔQ/Q0`` of a track run with respect to every parameter,
by central differences of the whole deterministic run, each checked at half the step.

The outputs (``max_YQ2m``, ``max_SY2m``, ``max_dQQ0``: :mod:`express.analysis.study.outputs`,
``express simulate --assess``) are maxima over the wheels (wheelsets) and over the
instants (the 2 m sliding windows) of a run whose wheel/rail forces are piecewise (the
flange contact, creep saturation, the contact tables' two-point contact, the bump
stops).  There is no implicit-function shortcut as for a steady state
(:mod:`express.analysis.study.curving_sensitivity`): each derivative is a **central
difference of the whole run** -- the same track, the same start (the state at rest at
the track's start), the same step ``dt`` (the nominal point's, chosen by the study's step
check), the same assessment -- at ``p (1 ± s)``, ``s`` the relative step :data:`STEP`
(absolute for a parameter of value 0).

**Why 1e-3.** The runs are deterministic (fixed step, exact linear part), so the
differences carry no noise beyond rounding; on the bundled forced-steering car along a
80 m curve entry, the derivatives at steps of 1e-3 and 5e-4 agree to 1e-8 .. 1e-6 of their
size where the output is smooth, and a step of 1e-5 gives the same to 1e-6 (rounding
shows only for elasticities under 1e-4).  A larger step would reach across more of the
kinks of the maxima; a much smaller one gains nothing.

**The check.** Each derivative is also taken at half the step (``p (1 ± s/2)``); both
are reported and their difference is the derivative's stated error.  Where the output is
smooth, the two agree to the truncation error ``~ h^2 f'''/8``; where the maximum has a
kink inside the step (it jumps to another wheel or another instant, a wheel enters flange
contact) they generally do not.  A derivative is **flagged as not differentiable at this
point** (:attr:`TimeRunSensitivity.differentiable` false, with its reason, and no clean
number) when

- the two estimates disagree by more than ``tolerance`` (:data:`TOLERANCE`, 5 %) of the
  larger, and by more than the floor ``floor |y| / |p|`` (:data:`FLOOR`: a disagreement of
  1e-4 in the elasticity, below which a derivative is nil for design; ``|p|`` 1 for a
  parameter of value 0), or
- the wheel (wheelset) holding the maximum is not the same in the runs at ``p - h`` and
  ``p + h`` (or at ``p ± h/2``): the output is then the larger of two smooth functions
  that cross between them, a kink, whatever the estimates say.

Where the maximum moves to another **instant** (window) of the same wheel between the
``-h`` and ``+h`` runs, that is said (:attr:`TimeRunSensitivity.switches`); it is flagged
only if the estimates disagree (a peak that moves smoothly along the track shifts its
window of 0.5 m spacing without a visible kink).  The nominal point's maxima are located
(:class:`MaximumAt`: the wheel or wheelset, the window's middle as distance and time).
"""

from __future__ import annotations

import math
import re
from collections.abc import Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np

from express.base.data import DataRecord, variable, xarray
from express.base.diagnostics import AnalysisError, ArgumentError

__all__ = ["FLOOR", "OUTPUTS", "STEP", "TOLERANCE", "MaximumAt", "TimeRunPoint", "TimeRunSensitivity",
           "checked_difference", "time_run_point", "time_run_sensitivity"]

#: The outputs differentiated, with their SI units (the study outputs of the same names).
OUTPUTS = {"max_YQ2m": "", "max_SY2m": "N", "max_dQQ0": ""}
#: Relative step of a parameter (absolute for a parameter of value 0; module docstring).
STEP = 1e-3
#: Largest disagreement of the estimates at the step and at half of it, relative to the larger.
TOLERANCE = 0.05
#: Disagreement in the elasticity ``(p / y) dy/dp`` always accepted (module docstring).
FLOOR = 1e-4


@dataclass(frozen=True)
class MaximumAt:
    """Where a time-run output has its maximum.

    Attributes
    ----------
    output : str
        ``max_YQ2m``, ``max_SY2m`` or ``max_dQQ0``.
    holder : str
        The wheel (``"1R"``: wheelset 1, right) of ``max_YQ2m`` and ``max_dQQ0``, the
        wheelset (``"2"``) of ``max_SY2m``.
    index : int
        The 2 m window (``max_YQ2m``, ``max_SY2m``; windows every 0.5 m) or the instant
        (``max_dQQ0``) of the maximum.
    distance : float
        The leading wheelset's distance along the track at the window's middle (or at
        the instant) [m].
    time : float
        The time there [s].
    value : float
        The maximum [the output's unit].
    """

    output: str
    holder: str
    index: int
    distance: float
    time: float
    value: float

    def as_dict(self) -> dict:
        return {"holder": self.holder, "index": self.index, "distance": self.distance, "time": self.time,
                "value": self.value}

    def text(self) -> str:
        what = "wheelset" if self.output == "max_SY2m" else "wheel"
        return f"{what} {self.holder} at {self.distance:.1f} m ({self.time:.3f} s)"


@dataclass(frozen=True)
class TimeRunPoint:
    """The time-run outputs of one run and where their maxima are.

    Attributes
    ----------
    values : dict of str to float
        ``max_YQ2m`` [-], ``max_SY2m`` [N], ``max_dQQ0`` [-].
    maxima : dict of str to MaximumAt
    """

    values: dict[str, float]
    maxima: dict[str, MaximumAt]


def _largest(criteria: dict[str, float], pattern: str) -> float:
    found = [value for name, value in criteria.items() if re.fullmatch(pattern, name)]
    return max(found) if found else math.nan


def _maxima(outputs, result, speed: float) -> dict[str, MaximumAt]:
    """Where the assessment's maxima are (the same filtering and sliding means as
    :func:`express.analysis.curving.assessment.assess`)."""
    from express.analysis.curving.assessment import SAMPLING, WINDOW, sliding_mean
    from express.analysis.curving.outputs import SIDES
    from express.analysis.curving.processing import filtered

    d, t = np.asarray(result.distance, float), np.asarray(result.time, float)
    if d.size > 1:
        outputs = filtered(outputs, d, speed)[0]

    def window(k: int) -> tuple[float, float]:
        middle = d[0] + SAMPLING * k + WINDOW / 2 if d.size > 1 and d[-1] - d[0] >= WINDOW else 0.5 * (d[0] + d[-1])
        return float(middle), float(np.interp(middle, d, t))

    yq = sliding_mean(d, outputs.y_over_q)
    k, j, s = np.unravel_index(int(np.argmax(yq)), yq.shape)
    sy = np.abs(sliding_mean(d, outputs.track_shift_force))
    m, w = np.unravel_index(int(np.argmax(sy)), sy.shape)
    unloading = outputs.wheel_unloading
    n, u, v = np.unravel_index(int(np.argmax(unloading)), unloading.shape)
    return {"max_YQ2m": MaximumAt("max_YQ2m", f"{j + 1}{SIDES[s]}", int(k), *window(int(k)), float(yq[k, j, s])),
            "max_SY2m": MaximumAt("max_SY2m", f"{w + 1}", int(m), *window(int(m)), float(sy[m, w])),
            "max_dQQ0": MaximumAt("max_dQQ0", f"{u + 1}{SIDES[v]}", int(n), float(d[n]), float(t[n]),
                                  float(unloading[n, u, v]))}


def time_run_point(vehicle, track, speed: float, dt: float) -> TimeRunPoint:
    """The time-run outputs of ``vehicle`` along ``track`` at ``speed`` [m/s] with step
    ``dt`` [s]: the study's run (:func:`express.analysis.time.simulate.simulate`) and
    assessment (:func:`express.analysis.curving.assessment.assess_run`), the values as
    the study takes them, and where their maxima are.

    Parameters
    ----------
    vehicle : VehicleModel
    track : Track
    speed : float
        [m/s].
    dt : float
        [s].

    Returns
    -------
    TimeRunPoint

    Raises
    ------
    AnalysisError
        When the run diverges.
    """
    from express.analysis.curving.assessment import assess_run
    from express.analysis.time.divergence import find_divergence
    from express.analysis.time.simulate import simulate

    result = simulate(vehicle, track, speed=speed, dt=dt, progress=False)
    divergence = find_divergence(result, vehicle)
    if divergence is not None:
        raise AnalysisError(f"the run diverges at t = {float(result.time[divergence.index]):.3f} s: "
                            f"{divergence.reason}")
    outputs, assessment = assess_run(vehicle, track, result)
    criteria = {c.name: c.value for c in assessment.criteria}
    values = {"max_YQ2m": _largest(criteria, r"YQ\d+[LR]"), "max_SY2m": _largest(criteria, r"SY\d+"),
              "max_dQQ0": criteria["dQQ0"]}
    return TimeRunPoint(values, _maxima(outputs, result, float(result.speed)))


def checked_difference(minus: float, plus: float, minus_half: float, plus_half: float, h: float, *,
                       output: float, scale: float, tolerance: float = TOLERANCE,
                       floor: float = FLOOR) -> tuple[float, float, str]:
    """The central differences at ``h`` and ``h/2`` and why they are not a derivative.

    Parameters
    ----------
    minus, plus : float
        The output at ``p - h`` and ``p + h``.
    minus_half, plus_half : float
        The output at ``p - h/2`` and ``p + h/2``.
    h : float
        The step [the parameter's unit], > 0.
    output : float
        The output at ``p`` (for the floor).
    scale : float
        ``|p|`` (1 for a parameter of value 0), for the floor.
    tolerance, floor : float
        As :func:`time_run_sensitivity`.

    Returns
    -------
    derivative, half_step : float
        ``(plus - minus) / (2 h)`` and ``(plus_half - minus_half) / h``.
    reason : str
        ``""`` when the two agree (module docstring), else why they do not.
    """
    first = (plus - minus) / (2.0 * h) + 0.0
    second = (plus_half - minus_half) / h + 0.0
    error = abs(first - second)
    allowed = max(tolerance * max(abs(first), abs(second)), floor * abs(output) / scale)
    if not (math.isfinite(first) and math.isfinite(second)):
        return first, second, "not finite"
    if error > allowed:
        return first, second, (f"the estimates at h and h/2 disagree by {error:.3g} (more than {allowed:.3g}): a kink "
                               "within the step (the maximum jumps between wheels or instants, or a contact regime "
                               "changes)")
    return first, second, ""


@dataclass(frozen=True, repr=False)
class TimeRunSensitivity(DataRecord):
    """Result of :func:`time_run_sensitivity`.

    Attributes
    ----------
    track : str
        The track run.
    speed, dt : float
        The running speed [m/s] and the time step of every run [s].
    step, tolerance, floor : float
        The relative step, the agreement tolerance and the floor (module docstring).
    values : dict of str to float
        ``max_YQ2m`` [-], ``max_SY2m`` [N], ``max_dQQ0`` [-] at the point.
    maxima : dict of str to MaximumAt
        Where they are at the point.
    parameters : tuple of str
    parameter_values : numpy.ndarray, shape (P,)
        [SI].
    steps : numpy.ndarray, shape (P,)
        The absolute step ``h`` of each parameter [SI].
    derivatives : numpy.ndarray, shape (P, 3)
        Central differences at ``h``, the outputs in the order of :data:`OUTPUTS` [output's
        SI unit per parameter's SI unit], flagged or not.
    half_step : numpy.ndarray, shape (P, 3)
        The same at ``h/2``.
    reasons : tuple of tuple of str
        Per parameter and output, ``""`` for a derivative that passed the check, else why
        it is not differentiable at this point.
    switches : tuple of tuple of str
        Per parameter and output, ``""`` when the maximum is at the same wheel (wheelset)
        and instant in the runs at ``p - h`` and ``p + h``, else where it moved.
    shifted : tuple of tuple of tuple of MaximumAt
        Per parameter and output, the maxima of the runs at ``p - h`` and ``p + h``.
    notes : tuple of str
        The step check of the nominal run.
    """

    track: str
    speed: float
    dt: float
    step: float
    tolerance: float
    floor: float
    values: dict[str, float]
    maxima: dict[str, MaximumAt]
    parameters: tuple[str, ...]
    parameter_values: np.ndarray
    steps: np.ndarray
    derivatives: np.ndarray
    half_step: np.ndarray
    reasons: tuple[tuple[str, ...], ...]
    switches: tuple[tuple[str, ...], ...]
    shifted: tuple[tuple[tuple[MaximumAt, MaximumAt], ...], ...]
    notes: tuple[str, ...]

    @property
    def errors(self) -> np.ndarray:
        """The stated error of each derivative, ``|d(h) - d(h/2)|``, shape (P, 3)."""
        return np.abs(self.derivatives - self.half_step)

    @property
    def differentiable(self) -> np.ndarray:
        """Whether each derivative passed the check (bool, shape (P, 3))."""
        return np.array([[not reason for reason in row] for row in self.reasons], dtype=bool).reshape(-1, len(OUTPUTS))

    @property
    def clean(self) -> np.ndarray:
        """:attr:`derivatives` where differentiable, nan where flagged, shape (P, 3)."""
        return np.where(self.differentiable, self.derivatives, np.nan)

    @property
    def elasticities(self) -> np.ndarray:
        """``(p / output) d output / dp`` [-] of :attr:`clean`, shape (P, 3) (0 where the
        parameter or the output is 0, nan where flagged)."""
        outputs = np.array([self.values[name] for name in OUTPUTS])
        with np.errstate(divide="ignore", invalid="ignore"):
            result = self.parameter_values[:, None] / outputs[None, :] * self.derivatives
        result = np.where(np.isfinite(result) & (self.parameter_values[:, None] != 0), result, 0.0) + 0.0
        return np.where(self.differentiable, result, np.nan)

    def derivative(self, output: str, parameter: str) -> float:
        """d ``output`` / d ``parameter`` (SI); nan where flagged."""
        return float(self.clean[self.parameters.index(parameter), list(OUTPUTS).index(output)])

    def as_dict(self) -> dict:
        """``{"values", "units", "maxima", "sensitivities": {parameter: {output: d or None}},
        "elasticities", "estimates": {parameter: {output: {"h", "half_step", "error",
        "differentiable", "reason", "switched", "minus_h", "plus_h"}}}, "not_differentiable",
        ...}`` (SI; None for a flagged derivative)."""
        names = list(OUTPUTS)
        elasticities, errors, ok = self.elasticities, self.errors, self.differentiable

        def number(array: np.ndarray, i: int, k: int) -> float | None:
            return float(array[i, k]) if ok[i, k] else None

        return {
            "track": self.track, "speed": self.speed, "dt": self.dt, "step": self.step, "tolerance": self.tolerance,
            "floor": self.floor, "values": dict(self.values), "units": dict(OUTPUTS),
            "maxima": {o: self.maxima[o].as_dict() for o in names},
            "steps": {p: float(self.steps[i]) for i, p in enumerate(self.parameters)},
            "sensitivities": {p: {o: number(self.derivatives, i, k) for k, o in enumerate(names)}
                              for i, p in enumerate(self.parameters)},
            "elasticities": {p: {o: number(elasticities, i, k) for k, o in enumerate(names)}
                             for i, p in enumerate(self.parameters)},
            "estimates": {p: {o: {"h": float(self.derivatives[i, k]), "half_step": float(self.half_step[i, k]),
                                  "error": float(errors[i, k]), "differentiable": bool(ok[i, k]),
                                  "reason": self.reasons[i][k], "switched": self.switches[i][k],
                                  "minus_h": self.shifted[i][k][0].as_dict(), "plus_h": self.shifted[i][k][1].as_dict()}
                              for k, o in enumerate(names)} for i, p in enumerate(self.parameters)},
            "not_differentiable": [f"{p}: {o}: {self.reasons[i][k]}" for i, p in enumerate(self.parameters)
                                   for k, o in enumerate(names) if not ok[i, k]],
            "notes": list(self.notes),
        }

    def to_xarray(self):
        """The derivatives as an :class:`xarray.Dataset` over ``parameter``: ``value`` and
        ``step`` (SI); for each output ``d_<output>`` (nan where flagged), ``d_<output>_h``,
        ``d_<output>_half``, ``error_<output>``, ``differentiable_<output>``,
        ``reason_<output>``, ``elasticity_<output>``; the outputs as scalars."""
        xr = xarray()
        data = {"value": variable(self.parameter_values, "parameter", "SI", "parameter value"),
                "step": variable(self.steps, "parameter", "SI", "absolute step h of the central differences")}
        clean, errors, ok, elasticities = self.clean, self.errors, self.differentiable, self.elasticities
        for k, (name, unit) in enumerate(OUTPUTS.items()):
            per = f"{unit or '1'} per SI unit of the parameter"
            data[f"d_{name}"] = variable(clean[:, k], "parameter", per, f"derivative of {name} (nan: not differentiable)")
            data[f"d_{name}_h"] = variable(self.derivatives[:, k], "parameter", per, f"central difference of {name} at h")
            data[f"d_{name}_half"] = variable(self.half_step[:, k], "parameter", per,
                                              f"central difference of {name} at h/2")
            data[f"error_{name}"] = variable(errors[:, k], "parameter", per, f"stated error of d {name}: |d(h) - d(h/2)|")
            data[f"differentiable_{name}"] = variable(ok[:, k], "parameter", "1", f"d {name} passed the check")
            data[f"reason_{name}"] = variable(np.array([row[k] for row in self.reasons], dtype=object), "parameter", "",
                                              f"why d {name} is not a derivative ('' for none)")
            data[f"elasticity_{name}"] = variable(elasticities[:, k], "parameter", "1", f"elasticity of {name}")
            data[name] = variable(self.values[name], (), unit or "1", name)
        dataset = xr.Dataset(data, coords={"parameter": list(self.parameters)})
        dataset.attrs.update({"track": self.track, "speed_m_s": self.speed, "dt_s": self.dt, "step": self.step,
                              "tolerance": self.tolerance, "floor": self.floor, "notes": "; ".join(self.notes),
                              **{f"{o}_at": m.text() for o, m in self.maxima.items()}})
        return dataset

    def _summary(self) -> list[str]:
        flagged = int((~self.differentiable).sum())
        return [f"{self.track}, {self.speed:.3f} m/s, dt {self.dt:g} s: (Y/Q)2m {self.values['max_YQ2m']:.4g}, "
                f"(SY)2m {self.values['max_SY2m'] / 1e3:.4g} kN, dQ/Q0 {self.values['max_dQQ0']:.4g}",
                f"{len(self.parameters)} parameters, step {self.step:g} checked at half; {flagged} derivatives "
                "not differentiable"]


def _track(track) -> tuple[Any, str, bool]:
    """The track, its name and whether its own speed counts (not for the default paper's
    curve, run at the model's speed as the study and ``express simulate`` do)."""
    from express.rail.track import Track, load_track, paper_curve

    if track is None:
        return paper_curve(), "the paper's curve (R = 400 m)", False
    if isinstance(track, Track):
        return track, f"a track of {track.length:g} m", True
    if isinstance(track, (str, Path)):
        return load_track(track), str(track), True
    raise ArgumentError(f"track must be a Track, a bundled track's name (\"R400\") or a track file, got "
                        f"{type(track).__name__}")


def _parameters(vehicle, parameters: Sequence[str] | None) -> list[str]:
    from express.analysis.study.sensitivity import chosen_parameters

    if getattr(vehicle, "tangent_vehicle", None) is not None:
        raise ArgumentError("a time run runs the nonlinear elements themselves: give the tangent vehicle, not one "
                            "linearised for the linear analyses")
    return chosen_parameters(vehicle, parameters)


def _step_checked(vehicle, track, speed: float, dt: float) -> tuple[float, list[str]]:
    """The nominal run's step: ``dt`` halved until the EN 14363 criteria agree with the
    run at twice the step (the study's check,
    :func:`express.analysis.time.step_check.checked_simulation`)."""
    from express.analysis.curving.assessment import assess_run
    from express.analysis.time.simulate import simulate
    from express.analysis.time.step_check import checked_simulation

    _result, _assessment, check = checked_simulation(
        vehicle, lambda step: simulate(vehicle, track, speed=speed, dt=step, progress=False),
        lambda run: (run, assess_run(vehicle, track, run)[1]), dt)
    return float(check.dt), [check.sentence()]


def _switch(output: str, low: MaximumAt, high: MaximumAt) -> str:
    if low.holder == high.holder and low.index == high.index:
        return ""
    if low.holder != high.holder:
        return f"the maximum switched from {low.text()} at p - h to {high.text()} at p + h"
    what = "wheelset" if output == "max_SY2m" else "wheel"
    unit = "window" if output != "max_dQQ0" else "instant"
    return (f"the maximum moved from {unit} {low.index} ({low.distance:.2f} m, {low.time:.4f} s) at p - h to {unit} "
            f"{high.index} ({high.distance:.2f} m, {high.time:.4f} s) at p + h, the same {what} {high.holder}")


def time_run_sensitivity(
    vehicle, track=None, *, speed: float | str | None = None, dt: float | str = 0.005,
    parameters: Sequence[str] | None = None, step: float = STEP, tolerance: float = TOLERANCE,
    floor: float = FLOOR, step_check: bool = True,
) -> TimeRunSensitivity:
    """The time-run outputs of ``vehicle`` along ``track`` and their derivatives with respect
    to every parameter, each checked at half the step (module docstring).

    Parameters
    ----------
    vehicle : VehicleModel
        With rail data (the tangent vehicle, not one linearised).
    track : Track, str or path, optional
        A track, a bundled track's name (``"R400"``) or a track file; by default the
        paper's R = 400 m curve (:func:`express.rail.track.paper_curve`) at the model's speed.
    speed : float or quantity, optional
        [m/s] (a number is SI, ``"95 km/h"`` a quantity); by default the track's own
        speed, else the model's (as :func:`express.simulate`).
    dt : float or quantity
        Time step [s]; with ``step_check`` the nominal run's step is halved from it until
        the criteria converge (the study's check), and every run uses that step.
    parameters : sequence of str, optional
        Default every given parameter but the speed
        (:func:`express.analysis.study.sensitivity.sensitivity_parameters`).
    step : float
        Relative step of a parameter (absolute for one of value 0), > 0.
    tolerance : float
        Largest disagreement of the estimates at the step and at half of it, relative to
        the larger [-].
    floor : float
        Disagreement in the elasticity always accepted [-].
    step_check : bool
        Check the nominal run's step (default, as a study does).

    Returns
    -------
    TimeRunSensitivity

    Raises
    ------
    ArgumentError
        An unknown parameter, a linearised vehicle, a bad step or tolerance.
    CurveError
        A track the vehicle cannot run at that speed (too much cant deficiency).
    AnalysisError
        A run that diverges.
    """
    from express.analysis.curving.curves import CurveError, track_problems
    from express.analysis.time.simulate import running_speed
    from express.base.arguments import si_argument

    names = _parameters(vehicle, parameters)
    for label, number in (("step", step), ("tolerance", tolerance), ("floor", floor)):
        if isinstance(number, bool) or not isinstance(number, (int, float)) or not (math.isfinite(number) and number > 0):
            raise ArgumentError(f"{label} must be a positive number, got {number!r}")
    if step >= 0.5:
        raise ArgumentError(f"step {step:g}: a relative step must be small (below 0.5; {STEP:g} by default)")
    road, where, own = _track(track)
    given = None if speed is None else si_argument(speed, "speed", "speed")
    v = running_speed(vehicle, road if own else replace(road, speed=None), given)[0]
    step_dt = float(si_argument(dt, "time", "dt"))
    problems = track_problems(vehicle, road, v)
    if problems:
        raise CurveError("\n".join(problems))
    notes: list[str] = []
    if step_check:
        step_dt, notes = _step_checked(vehicle, road, v, step_dt)
    nominal = time_run_point(vehicle, road, v, step_dt)
    outputs = list(OUTPUTS)
    shape = (len(names), len(outputs))
    first, second = np.zeros(shape), np.zeros(shape)
    reasons: list[tuple[str, ...]] = []
    switches: list[tuple[str, ...]] = []
    shifted: list[tuple[tuple[MaximumAt, MaximumAt], ...]] = []
    values = np.array([float(vehicle.values[name]) for name in names])
    steps = np.array([step * abs(value) or step for value in values])
    for i, name in enumerate(names):
        h = float(steps[i])
        runs = []
        for delta in (-h, h, -h / 2, h / 2):
            try:
                runs.append(time_run_point(vehicle.with_values({name: values[i] + delta}), road, v, step_dt))
            except AnalysisError as error:
                raise AnalysisError(f"{name} = {values[i] + delta:.6g}: {error}") from None
        row_reasons, row_switches, row_shifted = [], [], []
        for k, output in enumerate(outputs):
            minus, plus, minus_half, plus_half = (run.values[output] for run in runs)
            first[i, k], second[i, k], reason = checked_difference(
                minus, plus, minus_half, plus_half, h, output=nominal.values[output],
                scale=abs(values[i]) or 1.0, tolerance=tolerance, floor=floor)
            low, high = runs[0].maxima[output], runs[1].maxima[output]
            holders = {run.maxima[output].holder for run in runs}
            if len(holders) > 1 and not reason:
                reason = (f"the maximum is at different {'wheelsets' if output == 'max_SY2m' else 'wheels'} "
                          f"({', '.join(sorted(holders))}) within the step: the larger of two, a kink")
            row_reasons.append(reason)
            row_switches.append(_switch(output, low, high))
            row_shifted.append((low, high))
        reasons.append(tuple(row_reasons))
        switches.append(tuple(row_switches))
        shifted.append(tuple(row_shifted))
    return TimeRunSensitivity(where, v, step_dt, float(step), float(tolerance), float(floor), dict(nominal.values),
                              dict(nominal.maxima), tuple(names), values, steps, first, second, tuple(reasons),
                              tuple(switches), tuple(shifted), tuple(notes))
