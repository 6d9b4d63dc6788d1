"""The settled time run into a curve: what ``express curving`` reports where the steady
state has no stable equilibrium (issue 32, item 5; ``docs/curving.md``, "When there is no
stable equilibrium").

An unstable equilibrium is not where a vehicle runs, and an absent one (the solver finds
none) says nothing; in both cases the vehicle is run through the curve as a track would
take it — :data:`LEAD` of straight track, a linear transition of curvature and cant, then
the circular curve long enough to settle (:func:`settled_length`) — and the wheel/rail
quantities are read over the last :data:`WINDOW` of the circular curve, where every
wheelset has been in it for at least half its length: their **mean** (the state the
vehicle settles to) and their **half range** (the amplitude of the limit cycle it keeps, 0
for a settled run). The run's step is the given one (``simulate``'s default 5 ms; from
:func:`curving_or_settled` the step that resolves the force elements,
:meth:`~express.analysis.curving.steady.SteadyCurvingSolver.resolved_dt`).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from express.analysis.curving.outputs import WheelRailOutputs
from express.analysis.curving.steady import NoSteadyStateError, SteadyCurve, SteadyCurving, SteadyCurvingSolver
from express.analysis.curving.transition import LEAD, transition_length
from express.base.data import DataRecord, variable, xarray
from express.base.diagnostics import AnalysisError

__all__ = ["LEAD", "SETTLED", "WINDOW", "SettledCurving", "curving_or_settled", "settled_curving", "settled_length"]

#: Length of the circular curve's end over which the run is read [m].
WINDOW = 100.0
#: A run whose every quantity's half range is below this share of its size (or of 1 N,
#: 1e-6 rad) counts as settled [-].
SETTLED = 1e-3


def settled_length(speed: float) -> float:
    """The circular curve's length [m]: 20 s of running, at least 300 m."""
    return max(300.0, 20.0 * speed)


@dataclass(frozen=True, repr=False)
class SettledCurving(DataRecord):
    """The settled time run through one curve (module docstring).

    As data (:meth:`to_xarray`): every wheel/rail column a variable over ``statistic``
    (``mean``, ``amplitude``) with its SI unit; ``to_pandas()`` two rows, one column per
    quantity (``"Y1L [N]"``).

    Attributes
    ----------
    curve : SteadyCurve
    speed : float
        [m/s].
    reason : str
        Why the run was made (the equilibrium's absence or instability).
    mean, amplitude : dict of str to float
        Each wheel/rail column's mean and half range over the window
        (:meth:`~express.analysis.curving.outputs.WheelRailOutputs.columns`; SI).
    window : tuple of float
        The leading wheelset's distance at its start and end [m].
    dt : float
        The run's step [s].
    wheel_rail : WheelRailOutputs, optional
        The wheel/rail outputs of the window's instants (for the wear of a route's case,
        :mod:`express.analysis.wear.cases`).
    """

    curve: SteadyCurve
    speed: float
    reason: str
    mean: dict[str, float]
    amplitude: dict[str, float]
    window: tuple[float, float]
    dt: float
    wheel_rail: WheelRailOutputs | None = field(default=None, repr=False, compare=False)

    @property
    def settled(self) -> bool:
        """Every quantity's half range within :data:`SETTLED` of its size (else a limit cycle)."""
        return all(self.amplitude[name] <= SETTLED * max(abs(self.mean[name]), _floor(name)) for name in self.mean)

    def describe(self) -> str:
        """One line: settled, or the limit cycle's largest amplitudes."""
        if self.settled:
            return "settles (every quantity's half range within 0.1 % of its size)"
        shift = {k: v for k, v in self.amplitude.items() if k.startswith("SY")}
        angle = {k: v for k, v in self.amplitude.items() if k.startswith("aoa")}
        worst_shift = max(shift, key=lambda k: shift[k]) if shift else None
        worst_angle = max(angle, key=lambda k: angle[k]) if angle else None
        parts = []
        if worst_shift:
            parts.append(f"{worst_shift} +- {shift[worst_shift] / 1e3:.3g} kN")
        if worst_angle:
            parts.append(f"{worst_angle} +- {angle[worst_angle] * 1e3:.3g} mrad")
        return "keeps a limit cycle: " + ", ".join(parts)

    def to_xarray(self) -> Any:
        """The means and half ranges over ``statistic``, the curve's and the run's scalars
        (:class:`xarray.Dataset`; CF-style ``units`` and ``long_name``; ``"1"`` for ratios)."""
        from express.analysis.curving.outputs import column_unit

        data = {name: variable(np.array([self.mean[name], self.amplitude[name]], float), "statistic",
                               column_unit(name) or "1", f"{name}, mean and half range over the window")
                for name in self.mean}
        data["radius"] = variable(float(self.curve.radius), (), "m", "curve radius")
        data["cant"] = variable(float(self.curve.cant), (), "m", "cant")
        data["speed"] = variable(float(self.speed), (), "m/s", "speed")
        data["window_start"] = variable(float(self.window[0]), (), "m", "leading wheelset's distance, window start")
        data["window_end"] = variable(float(self.window[1]), (), "m", "leading wheelset's distance, window end")
        data["dt"] = variable(float(self.dt), (), "s", "time step of the run")
        return xarray().Dataset(data, coords={"statistic": ["mean", "amplitude"]},
                                attrs={"reason": self.reason, "settled": int(self.settled),
                                       "direction": self.curve.direction})

    def _summary(self) -> list[str]:
        return [f"R {self.curve.radius:g} m, cant {self.curve.cant * 1e3:g} mm at {self.speed * 3.6:.1f} km/h: "
                f"{self.reason}", self.describe()[:200]]

    def as_dict(self) -> dict:
        return {"radius": float(self.curve.radius), "cant": float(self.curve.cant),
                "speed": self.speed, "reason": self.reason, "settled": self.settled, "window": list(self.window),
                "dt": self.dt, "mean": dict(self.mean), "amplitude": dict(self.amplitude)}


def _floor(name: str) -> float:
    """The size below which a quantity counts as zero: 1 N for forces, 1e-6 otherwise."""
    return 1.0 if name[:1] in ("Q", "Y", "S", "F") and not name.startswith("YQ") else 1e-6


def settled_curving(vehicle, curve: SteadyCurve, speed: float, reason: str, *, dt: float = 0.005, **options) -> SettledCurving:
    """Run ``vehicle`` into ``curve`` (a :class:`~express.analysis.curving.steady.SteadyCurve`)
    at ``speed`` [m/s] and read where it settles (module docstring).

    Parameters
    ----------
    vehicle : VehicleModel
    curve : SteadyCurve
    speed : float
        [m/s].
    reason : str
        Said with the result.
    dt : float
        The run's step [s].
    **options
        ``contact``, ``creep_law``, ``flange``, ``saturation`` of
        :func:`~express.analysis.time.simulate.simulate`.

    Raises
    ------
    AnalysisError
        When the run leaves the model's range (it diverges).
    """
    from express.analysis.curving.assessment import assess_run
    from express.analysis.time.divergence import divergence_message, find_divergence
    from express.analysis.time.simulate import simulate
    from express.rail.track import Curve, Straight, Track, Transition

    transition = transition_length(curve.radius)
    length = settled_length(speed)
    track = Track((Straight(LEAD), Transition(transition), Curve(length, curve.radius, curve.direction, curve.cant)))
    run = simulate(vehicle, track, speed=speed, dt=dt, progress=False, **options)
    divergence = find_divergence(run, vehicle)
    if divergence is not None:
        raise AnalysisError(f"the run into R = {curve.radius:g} m diverged: {divergence_message(run, vehicle, divergence)}")
    outputs, _ = assess_run(vehicle, track, run)
    end = LEAD + transition + length
    inside = (run.distance >= end - WINDOW) & (run.distance <= end)
    columns = outputs.columns()
    mean = {name: float(np.mean(values[inside])) for name, values in columns.items() if not name.startswith("flanging")}
    amplitude = {name: float(np.ptp(columns[name][inside]) / 2) for name in mean}
    return SettledCurving(curve, float(speed), reason, mean, amplitude, (end - WINDOW, end), float(run.options["dt"]),
                          outputs.at(inside))


def curving_or_settled(vehicle, curves, speeds,
                       **options) -> list[tuple[SteadyCurving | None, SettledCurving | None]]:
    """Each curve's steady state and, where it is unstable or absent, the settled time run
    (module docstring): a list of ``(steady or None, settled or None)``, one per curve.

    Parameters
    ----------
    vehicle : VehicleModel
    curves : list of SteadyCurve
    speeds : list of float
        [m/s], one per curve.
    **options
        ``contact``, ``creep_law``, ``flange``, ``saturation`` of the solver and the run.
    """
    solvers: dict[float, SteadyCurvingSolver] = {}
    found: list[tuple[SteadyCurving | None, SettledCurving | None]] = []
    previous: SteadyCurving | None = None
    for curve, speed in zip(curves, speeds, strict=True):
        solver = solvers.get(float(speed))
        if solver is None:
            solver = solvers[float(speed)] = SteadyCurvingSolver(vehicle, speed, **options)
        start = previous.state if previous is not None and previous.curve.direction == curve.direction else None
        try:
            steady = solver.solve(curve, start)
        except NoSteadyStateError as error:
            found.append((None, settled_curving(vehicle, curve, speed, f"no equilibrium found ({error})",
                                                dt=solver.resolved_dt(), **options)))
            continue
        previous = steady
        settled = None
        if steady.stable is False:
            settled = settled_curving(vehicle, curve, speed, f"the equilibrium is unstable (growth rate "
                                      f"{steady.growth:.3g} 1/s)", dt=solver.resolved_dt(), **options)
        found.append((steady, settled))
    return found
