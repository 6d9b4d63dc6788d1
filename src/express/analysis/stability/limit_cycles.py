"""Runs at one fixed speed on straight track that tell whether a hunting limit cycle lives
there: :func:`limit_cycle` (one run of given length) and :func:`settle_cycle` (run on
until the cycle has settled or died), the two tests of
:mod:`express.analysis.stability.nonlinear_stability`.

Why two.  Near the speed where the cycle ends (a fold: the stable cycle meets an
unstable one) the motion is slow in both directions: just above it the amplitude creeps
onto the cycle for 10-40 s (on the Manchester car the two bogies' hunting drifts in
phase before it locks), just below it lingers near the vanished cycle before it
collapses.  A run of a few seconds that only asks "did the amplitude fall by less than
5 %?" then calls a collapsing motion alive and a creeping one dead (``docs/contact.md``,
"Nonlinear critical speed").  :func:`settle_cycle` asks whether the motion survives a
fixed time, ``longest``: dead when it collapses within it, alive otherwise; a cycle whose
amplitude has stopped changing is alive at once (a settled cycle survives any time).
Just below the fold the collapse comes later the nearer the fold is (as ``1 /
sqrt(v_fold - v)``): a speed that close to it counts as alive.  On the Manchester car a
collapse about 0.01 km/h below the end took 14 s, so 40 s leaves an error well below
that, far inside the search's 0.078 km/h grid.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from express.analysis.time.simulate import SimulationResult, simulate
from express.base.diagnostics import ArgumentError
from express.numeric.statespace import VehicleModel
from express.rail.options import DEFAULT_CREEP_LAW, ContactModel, CreepLaw
from express.rail.track import Straight, Track

__all__ = ["SETTLED_WINDOWS", "CycleCheck", "flange_touched", "instability_ratio", "limit_cycle", "settle_cycle",
           "settled"]

#: Windows over which a settled cycle's amplitude stays within ``spread`` (:func:`settle_cycle`).
SETTLED_WINDOWS = 4


def _run(vehicle: VehicleModel, speed: float, state: np.ndarray, duration: float, dt: float,
         creep_law: CreepLaw, contact: ContactModel | None) -> SimulationResult:
    """``duration`` [s] at ``speed`` [m/s] from ``state`` on straight track."""
    track = Track((Straight(speed * duration + 100.0),))
    return simulate(vehicle, track, speed=speed, dt=dt, end=speed * duration, initial_state=state,
                    progress=False, creep_law=creep_law, contact=contact)


def _final_state(vehicle: VehicleModel, result: SimulationResult) -> np.ndarray:
    """The last state ``[q; q_D']`` of a run."""
    return np.concatenate([result.q[-1], result.q_dot[-1][vehicle.form.massive]])


def _lateral_force(vehicle: VehicleModel, result: SimulationResult, wheelset: int, last: int) -> float:
    """Largest lateral force of a flanging wheel of ``wheelset`` over the ``last`` samples [N]
    (``nan`` without a record of it)."""
    if result.wheel_rail is not None:  # the contact tables: the larger lateral force of the two wheels
        return float(np.max(np.abs(result.wheel_rail.lateral_force[-last:, wheelset])))
    name = f"Y{wheelset + 1}"
    return float(np.max(np.abs(result.outputs[name][-last:]))) if name in result.outputs else math.nan


def flange_touched(result: SimulationResult, last: int) -> bool:
    """Whether a flange touched its rail in the ``last`` samples of a run: the contact
    tables' flag (contact angle above
    :data:`~express.analysis.curving.outputs.FLANGE_CONTACT_ANGLE`, 30 degrees), else a
    dead-band flange force ``Y<n>`` not zero."""
    if result.wheel_rail is not None:
        return bool(np.any(result.wheel_rail.flange_contact[-last:]))
    return any(np.any(values[-last:] != 0) for name, values in result.outputs.items()
               if name[:1] == "Y" and name[1:].isdigit())


def instability_ratio(result: SimulationResult) -> float:
    """EN 14363's instability criterion of a run: the largest ``ΣY`` rms over 100 m
    (:func:`express.analysis.curving.instability.instability_rms`) of any wheelset over
    half its Prud'homme limit (``> 1``: unstable); ``nan`` without the contact tables'
    forces or for a run shorter than one window."""
    from express.analysis.curving.assessment import prudhomme_limit
    from express.analysis.curving.instability import instability_rms

    outputs = result.wheel_rail
    if outputs is None:
        return math.nan
    ratios = []
    for j in range(outputs.wheelsets):
        found = instability_rms(result.distance, float(result.speed), outputs.track_shift_force[:, j])
        if found is not None:
            ratios.append(found.largest / (0.5 * prudhomme_limit(float(outputs.static_load[j]))))
    return max(ratios, default=math.nan)


def limit_cycle(vehicle: VehicleModel, speed: float, state: np.ndarray, *, duration: float, dt: float,
                wheelset: int = 0, creep_law: CreepLaw = DEFAULT_CREEP_LAW, contact: ContactModel | None = None):
    """Run ``duration`` [s] at ``speed`` from ``state`` on straight track; returns the
    amplitudes of the wheelset's lateral motion over the last and the middle third [m],
    the largest flange force of the last third [N], the final state, the simulation's
    contact option, whether a flange touched its rail in the last third
    (:func:`flange_touched`) and the run's EN 14363 instability ratio
    (:func:`instability_ratio`)."""
    result = _run(vehicle, speed, state, duration, dt, creep_law, contact)
    y = result.q[:, vehicle.wheelsets[wheelset].y]
    third = max(1, len(y) // 3)
    return (float(np.max(np.abs(y[-third:]))), float(np.max(np.abs(y[-2 * third: -third]))),
            _lateral_force(vehicle, result, wheelset, third), _final_state(vehicle, result),
            result.options.get("contact", "deadband"), flange_touched(result, third), instability_ratio(result))


@dataclass(frozen=True)
class CycleCheck:
    """Result of :func:`settle_cycle`.

    Attributes
    ----------
    speed : float
        [m/s].
    alive : bool
        The motion survived ``longest`` or settled: a limit cycle lives at this speed.
    settled : bool
        Its amplitude stopped changing (within ``spread``) before ``longest``.
    amplitudes : tuple of float
        Largest ``|y|`` of any wheelset in each window, in order [m].
    watched : tuple of float
        Largest ``|y|`` of the watched wheelset in each window [m].
    flange_force : float
        Largest lateral force of a flanging wheel of that wheelset in the last window [N].
    state : numpy.ndarray
        The final state ``[q; q_D']`` (on the cycle when ``alive``).
    duration : float
        Time simulated [s].
    contact : str
        The simulation's contact option.
    flange_contact : bool
        A flange touched its rail in the last window (:func:`flange_touched`).
    """

    speed: float
    alive: bool
    settled: bool
    amplitudes: tuple[float, ...]
    watched: tuple[float, ...]
    flange_force: float
    state: np.ndarray = field(repr=False, compare=False)
    duration: float
    contact: str
    flange_contact: bool = False


def settled(amplitudes: list[float] | tuple[float, ...], spread: float) -> bool:
    """The last :data:`SETTLED_WINDOWS` amplitudes differ by no more than ``spread`` times the last."""
    last = amplitudes[-SETTLED_WINDOWS:]
    return len(last) == SETTLED_WINDOWS and max(last) - min(last) <= spread * last[-1]


def settle_cycle(vehicle: VehicleModel, speed: float, state: np.ndarray, *, dt: float, window: float = 2.0,
                 longest: float = 40.0, spread: float = 2e-3, threshold: float = 0.1e-3, wheelset: int = 0,
                 creep_law: CreepLaw = DEFAULT_CREEP_LAW, contact: ContactModel | None = None) -> CycleCheck:
    """Run at ``speed`` from ``state`` window after window: does the motion survive
    ``longest`` seconds?

    Dead: the amplitude (largest ``|y|`` of any wheelset in a window: one bogie may hunt
    alone) falls to ``threshold`` or below within ``longest``.  Alive: it does not; the run stops early
    when the amplitude has settled, i.e. in each of the last :data:`SETTLED_WINDOWS`
    windows it stays within ``spread`` (relative).

    Parameters
    ----------
    vehicle : VehicleModel
        With rail data.
    speed : float
        [m/s].
    state : numpy.ndarray, shape (vehicle.form.size,)
        Start ``[q; q_D']``; to follow a cycle, a state on the cycle at a nearby higher speed.
    dt : float
        Time step [s].
    window : float
        Length of a window [s]; a few periods of the hunting.
    longest : float
        The time the motion must survive [s] (the most simulated).
    spread : float
        Largest relative change of the amplitude over the last windows of a settled cycle [-].
    threshold : float
        Amplitude [m] at or below which the motion has died.
    wheelset : int
        The watched wheelset (:attr:`CycleCheck.watched`, :attr:`CycleCheck.flange_force`).
    creep_law, contact :
        As :func:`express.analysis.time.simulate.simulate`.

    Returns
    -------
    CycleCheck
    """
    for name, value in (("window", window), ("longest", longest), ("spread", spread), ("threshold", threshold)):
        if not (math.isfinite(value) and value > 0):
            raise ArgumentError(f"{name} must be positive, got {value!r}")
    lateral = [w.y for w in vehicle.wheelsets]
    amplitudes: list[float] = []
    watched: list[float] = []
    alive = steady = False
    while not steady:
        result = _run(vehicle, speed, state, window, dt, creep_law, contact)
        state = _final_state(vehicle, result)
        peaks = np.max(np.abs(result.q[1:, lateral]), axis=0)
        amplitudes.append(float(np.max(peaks)))
        watched.append(float(peaks[wheelset]))
        if amplitudes[-1] <= threshold:
            break
        steady = settled(amplitudes, spread)
        alive = steady or len(amplitudes) * window >= longest - 1e-9
        if alive:
            break
    last = len(result.q) - 1
    return CycleCheck(speed, alive, steady, tuple(amplitudes), tuple(watched), _lateral_force(vehicle, result, wheelset, last),
                      state, len(amplitudes) * window, result.options.get("contact", "deadband"),
                      flange_touched(result, last))
