"""The quantities a study computes at every point, and their options.

=========================  ======  =================================================================
output                     unit    what
=========================  ======  =================================================================
``critical_speed``         m/s     as ``express critical-speed`` reports it (``critical`` module);
                                   ``v_min`` when already unstable there, nan when stable up to
                                   ``v_max`` (with a message)
``critical_frequency``     Hz      frequency of the mode that goes unstable (at the exact crossing;
                                   10 significant digits)
``least_damping_ratio``    --      smallest damping ratio ``-Re/|lambda|`` of the modes at ``speed``
``least_damping_frequency`` Hz     frequency of that mode
``max_Y``                  N       largest lateral wheel/rail force ``|Y|`` of any wheelset on the
                                   track (time-domain run, flange contact and creep saturation)
``max_YQ``                 --      largest derailment quotient ``|Y/Q0|`` on the track
``max_lever_angle``        rad     largest steering-lever rotation ``|theta|`` on the track
``frf_peak_acceleration``  m/s^2   peak acceleration amplitude of an output point (``frf_output``)
                                   in the response to a sinusoidal lateral irregularity (or to
                                   the track component ``frf_input``: its vertical acceleration
                                   for ``vertical``, its lateral one otherwise)
``frf_peak_frequency``     Hz      frequency of that peak
``max_YQ2m``               --      EN 14363's largest ``(Y/Q)2m`` of any wheel on the track run
                                   (``express simulate --assess``'s ``YQ{n}{s}``, filtered forces)
``max_SY2m``               N       largest ``(ΣY)2m`` of any wheelset on the track run
``max_dQQ0``               --      largest wheel unloading ``ΔQ/Q0`` on the track run
``max_aoa``                rad     largest angle of attack ``|aoa|`` of any wheelset on the track run
``max_Tgamma``             N       largest frictional power ``Tgamma`` of any wheel on the track run
                                   (contact from profiles; nan for the dead-band contact)
``step_dt``                s       the step of the assessed track run: ``dt``, halved until the
                                   EN 14363 outputs agree with the run at twice the step
                                   (``express simulate --assess``'s step check)
``step_error``             --      that check's largest change of a criterion over its limit
``steady_aoa``             rad     the leading wheelset's angle of attack in the steady curve
                                   (``curve_radius``, ``curve_cant``, ``speed``; ``express curving``)
``steady_YQ``              --      largest Y/Q of any wheel in that steady curve
``steady_SY``              N       largest ``|ΣY|`` of any wheelset in that steady curve
=========================  ======  =================================================================

The options (``[study.options]``) are those of the matching commands: ``v_min``,
``v_max``, ``tolerance``, ``points``, ``threshold``, ``check`` (critical speed);
``speed`` (eigenvalues, track and FRF; default the model's speed); ``track`` (a track
file or a bundled track's name, ``"R400"``, as ``--track`` takes it; default the paper's
R = 400 m curve), ``dt``; ``frf_output``, ``frf_input``, ``frf_fmin``, ``frf_fmax``,
``frf_points``, ``frf_amplitude``; ``curve_radius`` (default 600 m) and ``curve_cant``
(default 0) of the steady curve; ``step_check`` (default true: a track run with EN 14363
outputs is checked against the run at twice its step, the step halved until every
criterion moves by less than 1 % of its limit, :mod:`express.analysis.time.step_check`; a
point that does not converge says so). Quantities are numbers in SI or strings with a unit
(``"540 km/h"``).

Their sensitivities: ``steady_aoa``, ``steady_YQ``, ``steady_SY`` exactly (implicit
function theorem, :mod:`express.analysis.study.curving_sensitivity`); ``max_YQ2m``,
``max_SY2m``, ``max_dQQ0`` by central differences of the whole run, checked at half the
step and flagged where not differentiable (:mod:`express.analysis.study.time_run_sensitivity`;
``express sensitivity --output steady-curving`` and ``--output time-run``).

``max_Y`` and ``max_YQ`` were ``max_Q`` and ``max_QP`` before issue 35 (one meaning per
name: ``Q`` the vertical wheel load, ``Y`` the lateral force); a study that names the old
ones is refused with the new name (:data:`RENAMED_OUTPUTS`).
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from express.analysis.stability.critical_options import CriticalOptions, SearchCheck
from express.analysis.study.critical import CriticalSpeedSearch, StateBlocks
from express.base.diagnostics import ArgumentError

__all__ = ["OUTPUTS", "RENAMED_OUTPUTS", "OutputSettings", "PointOutputs", "renamed_message"]

from express.base.names import did_you_mean

#: Output name -> (SI unit, group). The group decides which analysis runs.
OUTPUTS: dict[str, tuple[str, str]] = {
    "critical_speed": ("m/s", "critical"),
    "critical_frequency": ("Hz", "critical"),
    "least_damping_ratio": ("", "eigen"),
    "least_damping_frequency": ("Hz", "eigen"),
    "max_Y": ("N", "track"),
    "max_YQ": ("", "track"),
    "max_lever_angle": ("rad", "track"),
    "frf_peak_acceleration": ("m/s^2", "frf"),
    "frf_peak_frequency": ("Hz", "frf"),
    "max_YQ2m": ("", "assess"),
    "max_SY2m": ("N", "assess"),
    "max_dQQ0": ("", "assess"),
    "max_aoa": ("rad", "assess"),
    "max_Tgamma": ("N", "assess"),
    "step_dt": ("s", "assess"),
    "step_error": ("", "assess"),
    "steady_aoa": ("rad", "steady"),
    "steady_YQ": ("", "steady"),
    "steady_SY": ("N", "steady"),
}

#: The critical-speed search's defaults (the one set: :class:`CriticalOptions`).
_SEARCH = CriticalOptions()
#: Option -> (dimension, default in SI, low, high); None dimension: not a quantity.
_QUANTITIES = {
    "v_min": ("speed", _SEARCH.v_min, 1e-6, 1000.0),
    "v_max": ("speed", _SEARCH.v_max, 1e-6, 1000.0),
    "tolerance": ("speed", _SEARCH.tolerance, 0.0, 100.0),
    "threshold": ("frequency", _SEARCH.threshold, 0.0, 1.0),
    "speed": ("speed", None, 1e-6, 1000.0),
    "dt": ("time", 0.005, 1e-5, 0.1),
    "frf_fmin": ("frequency", 0.1, 1e-4, 1000.0),
    "frf_fmax": ("frequency", 20.0, 1e-4, 1000.0),
    "frf_amplitude": ("length", 1e-3, 1e-9, 0.1),
    "curve_radius": ("length", 600.0, 1.0, 1e6),
    "curve_cant": ("length", 0.0, -0.3, 0.3),
    "element_amplitude": ("length", 1e-3, 1e-9, 1.0),
    "element_angle": ("angle", 1e-3, 1e-9, 1.0),
    "element_frequency": ("frequency", 2.0, 1e-4, 1000.0),
}
_OTHERS = ("points", "check", "track", "frf_output", "frf_input", "frf_points", "step_check", "linearisation")
#: The outputs of the linear analyses: the only ones ``linearisation = "equivalent"`` applies to.
LINEAR_OUTPUTS = tuple(name for name, (_unit, kind) in OUTPUTS.items() if kind in ("critical", "eigen", "frf"))
#: Track components of ``frf_input`` and the acceleration axis reported for each.
_FRF_INPUTS = {"alignment": "y", "vertical": "z", "cross_level": "y", "gauge": "y"}

#: Output names before issue 35 -> their names now.
RENAMED_OUTPUTS = {"max_Q": "max_Y", "max_QP": "max_YQ"}


def renamed_message(name: str) -> str | None:
    """What to say about an output named by its old name (None for any other name)."""
    new = RENAMED_OUTPUTS.get(name)
    if new is None:
        return None
    return (f"{name!r} is now called {new!r} (Q is the vertical wheel load, Y the lateral force, "
            "in every contact model)")


@dataclass(frozen=True)
class OutputSettings:
    """``[study.options]`` in SI (module docstring)."""

    v_min: float = _SEARCH.v_min
    v_max: float = _SEARCH.v_max
    tolerance: float = _SEARCH.tolerance
    threshold: float = _SEARCH.threshold
    points: int = _SEARCH.points
    check: SearchCheck = _SEARCH.check
    speed: float | None = None
    track: Path | str | None = None
    dt: float = 0.005
    frf_output: str | None = None
    frf_input: str = "alignment"
    frf_fmin: float = 0.1
    frf_fmax: float = 20.0
    frf_points: int = 200
    frf_amplitude: float = 1e-3
    curve_radius: float = 600.0
    curve_cant: float = 0.0
    step_check: bool = True
    linearisation: str = "tangent"
    element_amplitude: float = 1e-3
    element_angle: float = 1e-3
    element_frequency: float = 2.0

    @property
    def linearisation_spec(self) -> Any:
        """The :class:`express.forces.linearisation.Linearisation` of ``linearisation``."""
        from express.forces.linearisation import Linearisation

        return Linearisation(self.linearisation, self.element_amplitude, self.element_angle, self.element_frequency)

    @property
    def critical(self) -> CriticalOptions:
        return CriticalOptions(self.v_min, self.v_max, self.tolerance, self.threshold, self.points, self.check)

    @classmethod
    def from_table(cls, table: dict, base: Path, problems: list[tuple[str, str]]) -> OutputSettings:
        """Parse ``[study.options]``; ``problems`` receives ``(key, message)`` pairs."""
        from express.base.units import UnitError, parse_quantity

        values: dict[str, Any] = {}
        for key, raw in table.items():
            if key in _QUANTITIES:
                dimension, _default, low, high = _QUANTITIES[key]
                try:
                    if isinstance(raw, bool) or not isinstance(raw, (int, float, str)):
                        raise UnitError(f"expected a number (SI) or a quantity such as \"540 km/h\", got {raw!r}")
                    number = parse_quantity(raw, dimension)[0] if isinstance(raw, str) else float(raw)
                except UnitError as error:
                    problems.append((key, f"bad unit: {error}" if isinstance(raw, str) else str(error)))
                    continue
                if not (math.isfinite(number) and low <= number <= high):
                    problems.append((key, f"{raw!r} is outside {low:g} .. {high:g} (SI)"))
                    continue
                values[key] = float(number)
            elif key in ("points", "frf_points"):
                if isinstance(raw, bool) or not isinstance(raw, int) or not 2 <= raw <= 100_000:
                    problems.append((key, f"must be a whole number from 2 to 100000, got {raw!r}"))
                else:
                    values[key] = raw
            elif key == "check":
                if raw not in ("grid", "local"):
                    problems.append((key, f'must be "grid" or "local", got {raw!r}'))
                else:
                    values[key] = raw
            elif key == "track":
                from express.rail.track.named import NAMED_CURVES

                track = base / str(raw) if isinstance(raw, str) else None
                if track is not None and track.is_file():
                    values[key] = track
                elif isinstance(raw, str) and raw in (*NAMED_CURVES, "paper"):
                    values[key] = raw  # a bundled track, as --track takes it
                else:
                    problems.append((key, f"no such track file or bundled track: {raw!r} (the bundled ones: "
                                          f"{', '.join([*NAMED_CURVES, 'paper'])})"))
            elif key == "frf_input":
                if raw not in _FRF_INPUTS:
                    problems.append((key, f"must be one of {', '.join(_FRF_INPUTS)}, got {raw!r}"))
                else:
                    values[key] = raw
            elif key == "linearisation":
                if raw not in ("tangent", "equivalent"):
                    problems.append((key, f'must be "tangent" or "equivalent" (the statistical one is the ride\'s), '
                                          f"got {raw!r}"))
                else:
                    values[key] = raw
            elif key == "step_check":
                if not isinstance(raw, bool):
                    problems.append((key, f"must be true or false, got {raw!r}"))
                else:
                    values[key] = raw
            elif key == "frf_output":
                if not isinstance(raw, str):
                    problems.append((key, "must be the name of an output point"))
                else:
                    values[key] = raw
            else:
                problems.append((key, "unknown option" + did_you_mean(key, [*_QUANTITIES, *_OTHERS])))
        settings = cls(**values)
        if not settings.v_max > settings.v_min:
            problems.append(("v_max", "must be above v_min"))
        if not settings.frf_fmax > settings.frf_fmin:
            problems.append(("frf_fmax", "must be above frf_fmin"))
        return settings


def _rounded(value: float, digits: int) -> float:
    """``value`` to ``digits`` significant digits (so that a quantity found by Newton's
    method from different starting points is written the same)."""
    return float(f"{value:.{digits}g}") if math.isfinite(value) else value


class PointOutputs:
    """Computes the outputs of one point from a vehicle evaluated at its values.

    One instance per worker: it keeps the track (read once) and, for ``check =
    "local"``, the state of the critical-speed search (the last crossing as the starting
    guess, :class:`~express.analysis.study.critical.CriticalSpeedSearch`).

    Parameters
    ----------
    outputs : sequence of str
        Names of :data:`OUTPUTS`.
    settings : OutputSettings
    """

    def __init__(self, outputs, settings: OutputSettings):
        self.outputs = tuple(outputs)
        self.settings = settings
        self.groups = {OUTPUTS[name][1] for name in self.outputs}
        self.search = CriticalSpeedSearch(settings.critical)
        self._track: Any = None

    def restart(self) -> None:
        """Forget the critical-speed search's state (at the start of a chunk)."""
        self.search = CriticalSpeedSearch(self.settings.critical)

    def __call__(self, vehicle) -> tuple[dict[str, float], list[str]]:
        """Output values (SI; nan when not available) and messages for this point."""
        values: dict[str, float] = {}
        notes: list[str] = []
        if "critical" in self.groups:
            values.update(self._critical(vehicle, notes))
        if "eigen" in self.groups:
            values.update(self._eigen(vehicle))
        if self.groups & {"track", "assess"}:
            values.update(self._track_run(vehicle, notes))
        if "steady" in self.groups:
            values.update(self._steady(vehicle))
        if "frf" in self.groups:
            values.update(self._frf(vehicle))
        return {name: float(values[name]) for name in self.outputs}, notes

    def _speed(self, vehicle) -> float:
        speed = self.settings.speed if self.settings.speed is not None else float(vehicle.speed)
        if not (math.isfinite(speed) and speed > 0):
            raise ArgumentError("the model has no speed: give options.speed")
        return speed

    def _critical(self, vehicle, notes: list[str]) -> dict[str, float]:
        options = self.settings.critical
        result = self.search(StateBlocks(vehicle))
        if result.unstable_at_min:
            notes.append(f"already unstable at the lowest speed {options.v_min:.6g} m/s")
        elif not result.found:
            notes.append(f"no critical speed: stable up to {options.v_max:.6g} m/s")
        speed = result.speed
        if options.check == "local" and options.tolerance == 0:
            speed = _rounded(speed, 12)  # the exact crossing's last bits depend on the starting guess
        return {"critical_speed": speed, "critical_frequency": _rounded(result.frequency, 10)}

    def _eigen(self, vehicle) -> dict[str, float]:
        eigenvalues = np.linalg.eigvals(vehicle.state_matrix(self._speed(vehicle)))
        magnitude = np.abs(eigenvalues)
        keep = magnitude > 1e-9  # rigid-body (zero) eigenvalues have no damping ratio
        if not keep.any():
            return {"least_damping_ratio": math.nan, "least_damping_frequency": math.nan}
        ratios = -eigenvalues.real[keep] / magnitude[keep]
        k = int(np.argmin(ratios))
        return {"least_damping_ratio": float(ratios[k]),
                "least_damping_frequency": float(abs(eigenvalues[keep][k].imag) / (2 * np.pi))}

    def _track_run(self, vehicle, notes: list[str]) -> dict[str, float]:
        from express.analysis.time.simulate import simulate

        if self._track is None:
            from express.rail.track import load_track, paper_curve

            self._track = load_track(self.settings.track) if self.settings.track is not None else paper_curve()
        # the study's speed, else a track file's own (never silently ignored), else the model's (the
        # default paper's curve runs at the model's speed, as `express simulate` without --track)
        own = self._track.speed if self.settings.speed is None and self.settings.track is not None else None
        speed = own if own is not None else self._speed(vehicle)
        check = None
        if "assess" in self.groups and self.settings.step_check:
            result, check = self._checked_run(vehicle, speed)
        else:
            result = simulate(vehicle, self._track, speed=speed, dt=self.settings.dt, progress=False)
        maxima = result.max_abs()

        def largest(pattern: str) -> float:
            found = [value for name, value in maxima.items() if re.fullmatch(pattern, name)]
            return max(found) if found else math.nan

        found = {"max_Y": largest(r"Y\d+"), "max_YQ": largest(r"YQ\d+"), "max_lever_angle": largest(r"theta_.+")}
        if "assess" in self.groups:
            found.update(_assessed(vehicle, self._track, result))
            found["step_dt"] = check.dt if check is not None else self.settings.dt
            found["step_error"] = _step_error(check)
            if check is not None and not check.converged:
                notes.append(f"the track run's step did not converge: {check.dt:g} s against {check.compared_dt:g} s "
                                   f"moves a criterion by {found['step_error']:.1%} of its limit (tolerance "
                                   f"{check.tolerance:.0%})")
        return found

    def _checked_run(self, vehicle, speed: float):
        """The track run at ``dt``, checked against twice the step (the step halved until the
        EN 14363 criteria agree: :func:`express.analysis.time.step_check.checked_simulation`)."""
        from express.analysis.curving.assessment import assess_run
        from express.analysis.time.simulate import simulate
        from express.analysis.time.step_check import checked_simulation

        def simulate_at(step: float):
            return simulate(vehicle, self._track, speed=speed, dt=step, progress=False)

        def assess(run):
            return run, assess_run(vehicle, self._track, run)[1]

        result, _assessment, check = checked_simulation(vehicle, simulate_at, assess, self.settings.dt)
        return result, check

    def _steady(self, vehicle) -> dict[str, float]:
        from express.analysis.curving.steady import SteadyCurve, steady_curving

        s = self.settings
        state = steady_curving(vehicle, SteadyCurve(s.curve_radius, s.curve_cant), speeds=self._speed(vehicle))[0]
        outputs = state.wheel_rail
        return {"steady_aoa": float(outputs.angle_of_attack[0, 0]),
                "steady_YQ": float(np.max(outputs.y_over_q)),
                "steady_SY": float(np.max(np.abs(outputs.track_shift_force)))}

    def _frf(self, vehicle) -> dict[str, float]:
        from express.analysis.frequency.frequency import frequency_response

        s = self.settings
        model = vehicle.model
        points = [p.name for p in model.rail.outputs] if model is not None and model.rail is not None else []
        name = s.frf_output or (points[0] if points else None)
        if name is None or name not in points:
            raise ArgumentError(f"no output point {name!r} for the FRF; the model has: {', '.join(points) or 'none'}")
        frequencies = np.geomspace(s.frf_fmin, s.frf_fmax, s.frf_points)
        if s.frf_input == "alignment":
            response = frequency_response(vehicle, frequencies, amplitude=s.frf_amplitude, speed=self._speed(vehicle))
            amplitude = np.abs(np.asarray(response.acceleration_of(name)))
        else:
            from express.analysis.frequency.track_response import track_frequency_response

            track = track_frequency_response(vehicle, frequencies, components=[s.frf_input],
                                             amplitude=s.frf_amplitude, speed=self._speed(vehicle))
            amplitude = np.abs(track.of(f"{name}.a{_FRF_INPUTS[s.frf_input]}", s.frf_input))
        k = int(np.argmax(amplitude))
        return {"frf_peak_acceleration": float(amplitude[k]), "frf_peak_frequency": float(frequencies[k])}


def _step_error(check) -> float:
    """The step check's largest change of a criterion over its scale (0 without a check)."""
    if check is None:
        return 0.0
    return max((check.errors[name] / check.scales[name] for name in check.errors), default=0.0)


def _assessed(vehicle, track, result) -> dict[str, float]:
    """The EN 14363 outputs of a track run (``express simulate --assess``'s criteria)."""
    from express.analysis.curving.assessment import assess_run

    outputs, assessment = assess_run(vehicle, track, result)
    values = {c.name: c.value for c in assessment.criteria}

    def largest(pattern: str) -> float:
        found = [value for name, value in values.items() if re.fullmatch(pattern, name)]
        return max(found) if found else math.nan

    power = outputs.frictional_power
    return {"max_YQ2m": largest(r"YQ\d+[LR]"), "max_SY2m": largest(r"SY\d+"), "max_dQQ0": values["dQQ0"],
            "max_aoa": float(np.max(np.abs(outputs.angle_of_attack))),
            "max_Tgamma": float(np.max(power)) if power is not None else math.nan}
