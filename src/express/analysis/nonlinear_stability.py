"""Nonlinear critical speed by the ramp-down method, with the limit-cycle amplitude
against speed (a bifurcation diagram) (issue 12, item 6).

The linear critical speed (:func:`express.analysis.stability.critical_speed`) is where
the centred running loses its stability for infinitesimal disturbances.  With the
nonlinear contact the hunting bifurcation is usually subcritical: a limit cycle exists
well below it, and a large enough disturbance (a track fault) starts hunting there.  The
**nonlinear critical speed** is the lowest speed at which a limit cycle persists.

Method (the "ramp-down" of the literature, in speed steps): start above the linear
critical speed with every wheelset displaced by ``disturbance``, run on straight track
until the motion has settled, then lower the speed step by step, each run starting from
the last state of the previous one (the limit cycle is followed down its branch).  At
each speed the amplitude of the watched wheelset (the leading one) is the largest
``|y|`` over the last third of the run; the cycle is *alive* when that amplitude is above
``threshold`` and not smaller than ``persistence`` times the middle third's.  A motion
that still decays is run on (``extensions`` times at most): leaving a large cycle it may
settle on a smaller one of another branch (S1002 on 60E1 has a flange-contact branch and
a tread branch), which then is followed.  When it dies, the interval between the last live speed and
the first dead one is halved, always restarting from the last live state, until it is
narrower than ``tolerance``.  Every run is a :func:`express.analysis.simulate.simulate`
with the contact from the profiles' tables when the model has them (else the dead-band
flange and creep saturation).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from express.analysis.simulate import simulate
from express.analysis.stability import CriticalSpeed, critical_speed
from express.base.threads import limited_blas
from express.base.units import KMH
from express.numeric.statespace import VehicleModel
from express.rail.track import Straight, Track

__all__ = ["BifurcationPoint", "NonlinearCriticalSpeed", "limit_cycle", "nonlinear_critical_speed"]


@dataclass(frozen=True)
class BifurcationPoint:
    """One run of the ramp-down.

    Attributes
    ----------
    speed : float
        [m/s].
    amplitude : float
        Largest ``|y|`` of the watched wheelset over the last third of the run [m].
    previous : float
        The same over the middle third [m].
    alive : bool
        A limit cycle: ``amplitude > threshold`` and ``amplitude >= persistence * previous``.
    flange_force : float
        Largest lateral force on a flanging wheel of the watched wheelset in the last third [N].
    """

    speed: float
    amplitude: float
    previous: float
    alive: bool
    flange_force: float = math.nan

    @property
    def speed_kmh(self) -> float:
        """[km/h]."""
        return self.speed / KMH


@dataclass(frozen=True)
class NonlinearCriticalSpeed:
    """Result of :func:`nonlinear_critical_speed`.

    Attributes
    ----------
    speed : float or None
        Lowest speed [m/s] at which a limit cycle was sustained (``None``: no cycle at
        the start speed).
    bracket : tuple of float
        ``(dead, alive)`` [m/s]: the cycle died at ``dead`` and lived at ``alive``
        (``dead`` is ``nan`` when it lived down to ``v_min``).
    points : tuple of BifurcationPoint
        Every run, in the order run.
    linear : CriticalSpeed or None
        The linear critical speed of the same model.
    wheelset : str
        The watched wheelset.
    contact : str
        The contact model of the runs.
    options : dict
        ``v_start``, ``v_min``, ``step``, ``tolerance``, ``duration``, ``dt``,
        ``disturbance``, ``threshold``, ``persistence``, ``extensions``.
    state : numpy.ndarray or None
        The state ``[q; q_D']`` at the end of the run at :attr:`speed` (on the limit
        cycle), for restarting there.
    """

    speed: float | None
    bracket: tuple[float, float]
    points: tuple[BifurcationPoint, ...]
    linear: CriticalSpeed | None
    wheelset: str
    contact: str
    options: dict = field(default_factory=dict)
    state: np.ndarray | None = field(default=None, repr=False, compare=False)

    @property
    def speed_kmh(self) -> float | None:
        """[km/h]."""
        return None if self.speed is None else self.speed / KMH

    def describe(self) -> str:
        """One line: the nonlinear and the linear critical speeds."""
        linear = (f"linear {self.linear.speed_kmh:.1f} km/h" if self.linear is not None and not
                  self.linear.unstable_at_min else "no linear critical speed in the range")
        if self.speed is None:
            return (f"no limit cycle at the start speed {self.options['v_start'] / KMH:.1f} km/h ({linear})")
        low = "" if math.isfinite(self.bracket[0]) else " (still cycling at the lowest speed)"
        return (f"nonlinear critical speed {self.speed_kmh:.1f} km/h{low}, {linear}; "
                f"contact: {self.contact}")


def _state(vehicle: VehicleModel, result) -> np.ndarray:
    """The last state ``[q; q_D']`` of a run."""
    massive = vehicle.form.massive
    return np.concatenate([result.q[-1], result.q_dot[-1][massive]])


def limit_cycle(vehicle: VehicleModel, speed: float, state: np.ndarray, *, duration: float, dt: float,
                wheelset: int = 0, creep_law: str = "fastsim", contact: str | None = None):
    """Run ``duration`` [s] at ``speed`` from ``state`` on straight track; returns the
    amplitudes of the wheelset's lateral motion over the last and the middle third [m],
    the largest flange force of the last third [N], the final state and the
    simulation's contact option."""
    track = Track((Straight(speed * duration + 100.0),))
    result = simulate(vehicle, track, speed=speed, dt=dt, end=speed * duration, initial_state=state,
                      progress=False, creep_law=creep_law, contact=contact)
    y = result.q[:, vehicle.wheelsets[wheelset].y]
    third = max(1, len(y) // 3)
    q_name = f"Q{wheelset + 1}"
    force = float(np.max(np.abs(result.outputs[q_name][-third:]))) if q_name in result.outputs else math.nan
    return (float(np.max(np.abs(y[-third:]))), float(np.max(np.abs(y[-2 * third: -third]))), force,
            _state(vehicle, result), result.options.get("contact", "deadband"))


@limited_blas
def nonlinear_critical_speed(
    vehicle: VehicleModel,
    *,
    v_start: float | None = None,
    v_min: float = 1.0,
    step: float = 5.0 * KMH,
    tolerance: float = 0.5 * KMH,
    duration: float = 6.0,
    dt: float = 0.005,
    disturbance: float = 5e-3,
    threshold: float = 0.1e-3,
    persistence: float = 0.95,
    creep_law: str = "fastsim",
    contact: str | None = None,
    linear: CriticalSpeed | None = None,
    v_max: float = 150.0,
    extensions: int = 4,
) -> NonlinearCriticalSpeed:
    """The ramp-down (see the module docstring).

    Parameters
    ----------
    vehicle : VehicleModel
        With rail data; the contact from profiles when the model has them.
    v_start : float, optional
        First speed [m/s]; by default 1.2 times the linear critical speed (which must
        then exist below ``v_max``).
    v_min : float
        Lowest speed tried [m/s].
    step : float
        Speed decrement of the ramp [m/s] (5 km/h).
    tolerance : float
        Width of the final bracket [m/s] (0.5 km/h).
    duration : float
        Length of each run [s]; the amplitudes are read in its last two thirds.
    dt : float
        Time step [s].
    disturbance : float
        Initial lateral displacement of every wheelset [m].
    threshold, persistence : float
        A run has a limit cycle when its last-third amplitude is above ``threshold`` [m]
        and at least ``persistence`` times the middle third's.
    creep_law, contact :
        As :func:`express.analysis.simulate.simulate`.
    linear : CriticalSpeed, optional
        The linear critical speed, if already known.
    v_max : float
        Upper end of the linear critical speed's search [m/s].
    extensions : int
        A run whose motion still decays (above ``threshold``) is continued up to this many
        times: it may settle on a smaller cycle of another branch.

    Raises
    ------
    ValueError
        For a model without rail data, bad options, or no linear critical speed below
        ``v_max`` when ``v_start`` is not given.
    """
    if vehicle.layout is None or not vehicle.wheelsets:
        raise ValueError("the model has no rail data (wheelsets): no hunting to follow")
    for name, value in (("step", step), ("tolerance", tolerance), ("duration", duration), ("dt", dt),
                        ("disturbance", disturbance), ("threshold", threshold), ("v_min", v_min)):
        if not (math.isfinite(value) and value > 0):
            raise ValueError(f"{name} must be positive, got {value!r}")
    if linear is None:
        linear = critical_speed(vehicle, v_max=v_max)
    if v_start is None:
        if linear is None or linear.unstable_at_min:
            raise ValueError(f"no linear critical speed below {v_max / KMH:.0f} km/h to start above: give v_start")
        v_start = 1.2 * linear.speed
    if not v_start > v_min:
        raise ValueError(f"v_start ({v_start / KMH:.1f} km/h) must be above v_min ({v_min / KMH:.1f} km/h)")
    state = np.zeros(vehicle.form.size)
    for wheelset in vehicle.wheelsets:
        state[wheelset.y] = disturbance
    options = {"v_start": v_start, "v_min": v_min, "step": step, "tolerance": tolerance, "duration": duration,
               "dt": dt, "disturbance": disturbance, "threshold": threshold, "persistence": persistence,
               "extensions": extensions}
    points: list[BifurcationPoint] = []
    used = "deadband"

    def run(speed: float, start: np.ndarray) -> tuple[BifurcationPoint, np.ndarray]:
        nonlocal used
        final = start
        for _ in range(1 + extensions):  # a motion still decaying may settle on another cycle
            amplitude, previous, force, final, used = limit_cycle(vehicle, speed, final, duration=duration, dt=dt,
                                                                  creep_law=creep_law, contact=contact)
            alive = amplitude > threshold and amplitude >= persistence * previous
            if alive or amplitude <= threshold:
                break
        point = BifurcationPoint(speed, amplitude, previous, alive, force)
        points.append(point)
        return point, final

    speed = v_start
    point, final = run(speed, state)
    if not point.alive:
        return NonlinearCriticalSpeed(None, (speed, math.nan), tuple(points), linear,
                                      vehicle.wheelsets[0].name, used, options)
    alive_speed, alive_state = speed, final
    dead = math.nan
    while True:  # ramp down until the cycle dies
        speed = alive_speed - step
        if speed < v_min:
            break
        point, final = run(speed, alive_state)
        if not point.alive:
            dead = speed
            break
        alive_speed, alive_state = speed, final
    while math.isfinite(dead) and alive_speed - dead > tolerance:  # halve the bracket
        speed = 0.5 * (alive_speed + dead)
        point, final = run(speed, alive_state)
        if point.alive:
            alive_speed, alive_state = speed, final
        else:
            dead = speed
    return NonlinearCriticalSpeed(alive_speed, (dead, alive_speed), tuple(points), linear,
                                  vehicle.wheelsets[0].name, used, options, alive_state)
