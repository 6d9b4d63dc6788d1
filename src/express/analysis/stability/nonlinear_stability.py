"""Nonlinear critical speed by the ramp-down method, with the limit-cycle amplitude
against speed (a bifurcation diagram) (issue 12, item 6).

The linear critical speed (:func:`express.analysis.stability.stability.critical_speed`) is where
the centred running loses its stability for infinitesimal disturbances.  With the
nonlinear contact the hunting bifurcation is usually subcritical: a limit cycle exists
well below it, and a large enough disturbance (a track fault) starts hunting there.  The
**nonlinear critical speed** is the lowest speed at which a limit cycle persists.

Method, in two stages.  **Ramp** (the "ramp-down" of the literature, in speed steps):
start above the linear critical speed with every wheelset displaced by ``disturbance``,
run on straight track, then lower the speed by ``step``, each run starting from the last
state of the previous one (the limit cycle is followed down its branch).  At each speed
the amplitude of the watched wheelset (the leading one) is the largest ``|y|`` over the
last third of the run; the cycle is *alive* when that amplitude is above ``threshold``
and not smaller than ``persistence`` times the middle third's.  A motion that still
decays is run on (``extensions`` times at most): leaving a large cycle it may settle on a
smaller one of another branch (S1002 on 60E1 has a flange-contact branch and a tread
branch), which then is followed.  The ramp stops at the first speed where the cycle dies.

**End of the cycle.**  The ramp's few-second test is too coarse near the end of the
cycle, where the motion creeps and collapses slowly (:mod:`express.analysis.stability.limit_cycles`).
So the interval between the last live speed of the ramp (the *anchor*) and the dead one
is halved until narrower than ``tolerance`` with runs that must *survive*: started from
the state of the anchor's run, alive when the lateral motion of some wheelset stays above
``threshold`` for ``longest`` seconds (or settles earlier), dead when it collapses
(:func:`express.analysis.stability.limit_cycles.settle_cycle`).  Every try starts from the same
state, so whether a speed counts as alive does not depend on the tries before it; the
speeds tried lie on one grid, ``anchor - k step / 2**n``.  Every run is a
:func:`express.analysis.time.simulate.simulate` with the contact from the profiles' tables when
the model has them (else the dead-band flange and creep saturation).

**Step-size check.**  The runs use a fixed step ``dt``, and the end of the cycle moves
with it (the Manchester car: 174.1 km/h at 5 ms, 175.4 km/h at 0.625 ms).  So the end of
the cycle is searched again with ``dt`` halved, from the same anchor and on the same grid,
until halving ``dt`` moves the result by no more than ``tolerance`` (or ``refinements``
halvings were made).  The result keeps every step's speed
(:attr:`NonlinearCriticalSpeed.step_checks`), the ``dt`` it used and its uncertainty: the
final bracket's width plus the change of the last halving.

A vehicle may have several limit cycles near the end (the Manchester car's two bogies
hunt phase-locked in more than one way, or one bogie alone; ``docs/contact.md``); the
result is the end of the one reached from the anchor.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from express.analysis.stability.attractors import Attractor, attractors
from express.analysis.stability.limit_cycles import CycleCheck, limit_cycle, settle_cycle
from express.analysis.stability.stability import CriticalSpeed, critical_speed
from express.base.arguments import si_argument
from express.base.data import DataRecord, variable, xarray
from express.base.diagnostics import ArgumentError
from express.base.threads import limited_blas
from express.base.units import KMH
from express.numeric.statespace import VehicleModel
from express.rail.options import DEFAULT_CREEP_LAW, ContactModel, CreepLaw

__all__ = ["Attractor", "BifurcationPoint", "NonlinearCriticalSpeed", "StepCheck", "limit_cycle",
           "nonlinear_critical_speed"]


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
    flange_contact : bool
        A flange touched its rail in the last third
        (:func:`express.analysis.stability.limit_cycles.flange_touched`).
    instability : float
        EN 14363's instability criterion over the run, the largest ``ΣY`` rms over 100 m
        against half Prud'homme's limit (``> 1`` fails; ``nan`` without the contact
        tables or for a run under 100 m:
        :func:`express.analysis.stability.limit_cycles.instability_ratio`).
    """

    speed: float
    amplitude: float
    previous: float
    alive: bool
    flange_force: float = math.nan
    flange_contact: bool = False
    instability: float = math.nan

    @property
    def speed_kmh(self) -> float:
        """[km/h]."""
        return self.speed / KMH


@dataclass(frozen=True)
class StepCheck:
    """The search at one time step.

    Attributes
    ----------
    dt : float
        Time step [s].
    speed : float or None
        Lowest speed with a limit cycle at this step [m/s].
    bracket : tuple of float
        ``(dead, alive)`` [m/s] at this step.
    runs : int
        Speeds run at this step (ramp points and settled runs).
    simulated : float
        Time simulated at this step [s].
    """

    dt: float
    speed: float | None
    bracket: tuple[float, float]
    runs: int
    simulated: float = 0.0


@dataclass(frozen=True, repr=False)
class NonlinearCriticalSpeed(DataRecord):
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
        Every run of the ramp at the first step (the bifurcation diagram), in the order run.
    linear : CriticalSpeed or None
        The linear critical speed of the same model.
    wheelset : str
        The watched wheelset.
    contact : str
        The contact model of the runs.
    options : dict
        ``v_start``, ``v_min``, ``step``, ``tolerance``, ``duration``, ``dt``,
        ``disturbance``, ``threshold``, ``persistence``, ``extensions``, ``refinements``.
    state : numpy.ndarray or None
        The state ``[q; q_D']`` at the end of the run at :attr:`speed` (on the limit
        cycle), for restarting there.
    step_checks : tuple of StepCheck
        The search at each time step, the first ``options["dt"]``, each next one half the
        previous; :attr:`speed` and :attr:`bracket` are the last one's.
    anchor : tuple or None
        ``(speed, state)``: the live point of the ramp every try of the last step started
        from [m/s] and the ramp's state there; ``nonlinear_critical_speed(v_start=speed,
        initial_state=state, dt=..., refinements=0)`` repeats the search at another step.
    attractors : tuple of Attractor
        Every limit cycle the ramp followed down, highest first, with its speeds,
        amplitudes and flange contact (:mod:`express.analysis.stability.attractors`).
    """

    speed: float | None
    bracket: tuple[float, float]
    points: tuple[BifurcationPoint, ...]
    linear: CriticalSpeed | None
    wheelset: str
    contact: str
    options: dict = field(default_factory=dict)
    state: np.ndarray | None = field(default=None, repr=False, compare=False)
    step_checks: tuple[StepCheck, ...] = ()
    anchor: tuple[float, np.ndarray] | None = field(default=None, repr=False, compare=False)
    attractors: tuple[Attractor, ...] = ()

    @property
    def flange_speed(self) -> float | None:
        """The lowest ramp speed at which a limit cycle runs in flange contact [m/s] (None:
        none did), to the ramp's ``step`` (:attr:`Attractor.flange_lowest`)."""
        speeds = [a.flange_lowest for a in self.attractors if a.flange_contact]
        return min(speeds) if speeds else None

    @property
    def speed_kmh(self) -> float | None:
        """[km/h]."""
        return None if self.speed is None else self.speed / KMH

    @property
    def found(self) -> bool:
        """True when a limit cycle was sustained at some speed (:attr:`speed` is not None)."""
        return self.speed is not None

    @property
    def reason(self) -> str:
        """``"limit cycle"`` (:attr:`speed` found), ``"no limit cycle at v_start"``."""
        return "limit cycle" if self.found else "no limit cycle at v_start"

    def to_xarray(self):
        """The bifurcation diagram as an :class:`xarray.Dataset` over ``run`` (the ramp's
        runs in order: ``speed`` [m/s], ``amplitude`` [m], ``limit_cycle``, ``flange_force``
        [N]) and the result's scalars (``critical_speed`` [m/s], nan when not
        :attr:`found`, the bracket, ``dt`` [s], ``uncertainty`` [m/s]); ``found``,
        ``reason``, ``contact`` and ``wheelset`` as attributes."""
        xr = xarray()
        points = self.points
        nan = math.nan
        data = {
            "run_speed": variable(np.array([p.speed for p in points], float), "run", "m/s", "speed of the ramp's run"),
            "amplitude": variable(np.array([p.amplitude for p in points], float), "run", "m",
                                  "largest lateral displacement of the watched wheelset, last third of the run"),
            "limit_cycle": variable(np.array([bool(p.alive) for p in points], bool), "run", "1", "a limit cycle lives"),
            "flange_force": variable(np.array([p.flange_force for p in points], float), "run", "N",
                                     "largest lateral force on a flanging wheel"),
            "flange_contact": variable(np.array([bool(p.flange_contact) for p in points], bool), "run", "1",
                                       "a flange touched its rail"),
            "instability": variable(np.array([p.instability for p in points], float), "run", "1",
                                    "largest SY rms over 100 m against half the Prud'homme limit (EN 14363)"),
            "flange_speed": variable(self.flange_speed if self.flange_speed is not None else nan, (), "m/s",
                                     "lowest ramp speed of a flange-contact limit cycle"),
            "critical_speed": variable(self.speed if self.speed is not None else nan, (), "m/s",
                                       "nonlinear critical speed"),
            "bracket_dead": variable(float(self.bracket[0]), (), "m/s", "speed where the cycle died"),
            "bracket_alive": variable(float(self.bracket[1]), (), "m/s", "speed where the cycle lived"),
            "dt": variable(self.dt, (), "s", "time step"),
            "uncertainty": variable(self.uncertainty, (), "m/s", "bracket width plus the change of the last dt halving"),
            "linear_critical_speed": variable(self.linear.speed if self.linear is not None else nan, (), "m/s",
                                              "linear critical speed"),
        }
        return xr.Dataset(data, coords={"run": np.arange(len(points))},
                          attrs={"found": int(self.found), "reason": self.reason, "contact": self.contact,
                                 "wheelset": self.wheelset})

    def _summary(self) -> list[str]:
        return [self.describe(), f"found={self.found}, reason={self.reason!r}, {len(self.points)} ramp runs"]

    @property
    def dt(self) -> float:
        """The time step of :attr:`speed` [s]."""
        return self.step_checks[-1].dt if self.step_checks else float(self.options["dt"])

    @property
    def step_change(self) -> float:
        """How far the last halving of ``dt`` moved :attr:`speed` [m/s] (``nan``: not
        checked, or no cycle at one of the steps)."""
        if len(self.step_checks) < 2 or self.step_checks[-1].speed is None or self.step_checks[-2].speed is None:
            return math.nan
        return abs(self.step_checks[-1].speed - self.step_checks[-2].speed)

    @property
    def converged(self) -> bool:
        """Halving ``dt`` moved the result by no more than the bracket's tolerance."""
        return bool(self.step_change <= self.options["tolerance"])

    @property
    def uncertainty(self) -> float:
        """Width of the final bracket plus :attr:`step_change` [m/s] (``nan`` when either
        is unknown): the true critical speed of the model lies within
        ``speed - uncertainty .. speed + step_change``."""
        return (self.bracket[1] - self.bracket[0]) + self.step_change

    def describe(self) -> str:
        """One line: the nonlinear and the linear critical speeds."""
        linear = (f"linear {self.linear.speed_kmh:.1f} km/h" if self.linear is not None and self.linear.found
                  and not self.linear.unstable_at_min else "no linear critical speed in the range")
        if self.speed is None:
            return (f"no limit cycle at the start speed {self.options['v_start'] / KMH:.1f} km/h ({linear})")
        low = "" if math.isfinite(self.bracket[0]) else " (still cycling at the lowest speed)"
        if math.isfinite(self.step_change):
            bound = f"uncertainty {self.uncertainty / KMH:.2f} km/h " if math.isfinite(self.uncertainty) else ""
            step = (f"dt {self.dt * 1e3:g} ms, {bound}(halving dt moved it {self.step_change / KMH:.2f} km/h"
                    f"{'' if self.converged else ', NOT converged in dt'})")
        else:
            step = f"dt {self.dt * 1e3:g} ms, not checked by halving dt"
        return (f"nonlinear critical speed {self.speed_kmh:.1f} km/h{low}, {step}, {linear}; "
                f"contact: {self.contact}")

    def as_dict(self) -> dict:
        """The result as plain data (SI, speeds also in km/h): the speed, bracket, contact,
        wheelset, time step and its check, and the bifurcation diagram's points; a value
        not known (nan here: a bracket's end below ``v_min``, no step check) is None."""
        return _known({"critical_speed": self.speed, "critical_speed_kmh": self.speed_kmh,
                "bracket": list(self.bracket), "contact": self.contact, "wheelset": self.wheelset,
                "threshold": self.options.get("threshold"), "disturbance": self.options.get("disturbance"),
                "dt": self.dt, "uncertainty": self.uncertainty, "step_change": self.step_change,
                "converged_in_dt": self.converged,
                "step_checks": [{"dt": c.dt, "critical_speed": c.speed, "bracket": list(c.bracket), "runs": c.runs,
                                 "simulated": c.simulated} for c in self.step_checks],
                "speeds": [p.speed for p in self.points], "amplitudes": [p.amplitude for p in self.points],
                "limit_cycle": [bool(p.alive) for p in self.points],
                "flange_contact": [bool(p.flange_contact) for p in self.points],
                "instability": [p.instability for p in self.points],
                "flange_speed": self.flange_speed,
                "flange_speed_kmh": None if self.flange_speed is None else self.flange_speed / KMH,
                "attractors": [a.as_dict() for a in self.attractors]})


def _known(value: Any) -> Any:
    """``value`` with every nan float (in dicts and lists) replaced by None."""
    if isinstance(value, dict):
        return {key: _known(item) for key, item in value.items()}
    if isinstance(value, list):
        return [_known(item) for item in value]
    return None if isinstance(value, float) and math.isnan(value) else value


@dataclass(frozen=True)
class _Settings:
    """The search's fixed options (see :func:`nonlinear_critical_speed`)."""

    v_min: float
    step: float
    tolerance: float
    duration: float
    threshold: float
    persistence: float
    extensions: int
    window: float
    longest: float
    spread: float
    creep_law: CreepLaw
    contact: ContactModel | None


@dataclass
class _Search:
    """The runs at one ``dt``: the ramp's (first step only) and the fold search's."""

    alive: float | None = None
    dead: float = math.nan
    state: np.ndarray | None = None
    points: list[BifurcationPoint] = field(default_factory=list)
    used: str = "deadband"
    runs: int = 0
    simulated: float = 0.0
    anchor: tuple[float, np.ndarray] | None = None


def _ramp_point(vehicle: VehicleModel, speed: float, start: np.ndarray, dt: float, settings: _Settings,
                search: _Search) -> tuple[BifurcationPoint, np.ndarray]:
    """One point of the ramp (continued while its motion still decays)."""
    final = start
    for _ in range(1 + settings.extensions):  # a motion still decaying may settle on another cycle
        amplitude, previous, force, final, search.used, flanging, instability = limit_cycle(
            vehicle, speed, final, duration=settings.duration, dt=dt, creep_law=settings.creep_law,
            contact=settings.contact)
        search.simulated += settings.duration
        search.runs += 1
        alive = amplitude > settings.threshold and amplitude >= settings.persistence * previous
        if alive or amplitude <= settings.threshold:
            break
    point = BifurcationPoint(speed, amplitude, previous, alive, force, flanging, instability)
    search.points.append(point)
    return point, final


def _ramp_down(vehicle: VehicleModel, v_start: float, state: np.ndarray, dt: float, settings: _Settings,
               search: _Search) -> tuple[list[tuple[float, np.ndarray]], float]:
    """From ``v_start`` down in ``step`` until the cycle dies: the live points ``(speed,
    state)``, lowest first, and the first dead speed (``nan``: alive down to ``v_min``)."""
    live: list[tuple[float, np.ndarray]] = []
    speed = v_start
    while speed >= settings.v_min:
        point, final = _ramp_point(vehicle, speed, live[-1][1] if live else state, dt, settings, search)
        if not point.alive:
            return live[::-1], speed
        live.append((speed, final))
        speed -= settings.step
    return live[::-1], math.nan


def _settle(vehicle: VehicleModel, speed: float, state: np.ndarray, dt: float, settings: _Settings,
            search: _Search, record: bool) -> CycleCheck:
    """:func:`express.analysis.stability.limit_cycles.settle_cycle` with the search's options."""
    check = settle_cycle(vehicle, speed, state, dt=dt, window=settings.window, longest=settings.longest,
                         spread=settings.spread, threshold=settings.threshold, creep_law=settings.creep_law,
                         contact=settings.contact)
    search.simulated += check.duration
    search.runs += 1
    search.used = check.contact
    if record:
        watched = check.watched
        search.points.append(BifurcationPoint(speed, watched[-1], watched[-2] if len(watched) > 1 else watched[-1],
                                              check.alive, check.flange_force, check.flange_contact))
    return check


def _fold(vehicle: VehicleModel, dt: float, anchors: list[tuple[float, np.ndarray]], dead: float,
          settings: _Settings, search: _Search, record: bool) -> _Search:
    """The end of the cycle at ``dt`` by runs that must survive ``longest``: the lowest
    anchor (a live point of the ramp) whose motion survives is the upper end, ``dead``
    (checked, and lowered by ``step`` while the motion survives there) the lower end, then
    the bracket is halved to ``tolerance``.  Every try starts from the state the anchor's
    run ended in.  The speeds tried lie on the grid ``anchor - k step / 2**n``, the same at
    every ``dt``."""
    upper = None
    for speed, state in anchors:
        check = _settle(vehicle, speed, state, dt, settings, search, record)
        if check.alive:
            upper, search.anchor = check, (speed, state)
            break
        dead = speed  # re-checked below from the state of a surviving run
    if upper is None:
        search.dead = dead
        return search
    start = upper.state  # every try starts here: whether it lives does not depend on the tries before
    while math.isfinite(dead):  # the lower end: no motion survives there
        check = _settle(vehicle, dead, start, dt, settings, search, record)
        if not check.alive:
            break
        upper = check
        dead = dead - settings.step if dead - settings.step >= settings.v_min else math.nan
    while math.isfinite(dead) and upper.speed - dead > settings.tolerance:
        check = _settle(vehicle, 0.5 * (upper.speed + dead), start, dt, settings, search, record)
        if check.alive:
            upper = check
        else:
            dead = check.speed
    search.alive, search.dead, search.state = upper.speed, dead, upper.state
    return search


def _refined(vehicle: VehicleModel, dt: float, anchors: list[tuple[float, np.ndarray]], dead: float,
             settings: _Settings, first: _Search, refinements: int) -> tuple[_Search, list[StepCheck]]:
    """The end of the cycle at ``dt``, then at ``dt`` halved until a halving moves it by no
    more than ``tolerance`` (``refinements`` halvings at most): the last search and every step's check."""
    search = _fold(vehicle, dt, anchors, dead, settings, first, record=True)
    checks = [_check(dt, search)]
    for _ in range(refinements):
        if search.alive is None:
            break
        finer = dt / 2 ** len(checks)
        again = _fold(vehicle, finer, anchors, dead, settings, _Search(), record=False)
        moved = abs(again.alive - search.alive) if again.alive is not None else math.inf
        search = again
        checks.append(_check(finer, search))
        if search.alive is None or moved <= settings.tolerance:
            break
    return search, checks


def _check(dt: float, search: _Search) -> StepCheck:
    return StepCheck(dt, search.alive, (search.dead, search.alive if search.alive is not None else math.nan),
                     search.runs, search.simulated)


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
    creep_law: CreepLaw = DEFAULT_CREEP_LAW,
    contact: ContactModel | None = None,
    linear: CriticalSpeed | None = None,
    v_max: float = 150.0,
    extensions: int = 4,
    refinements: int = 4,
    window: float = 2.0,
    longest: float = 40.0,
    spread: float = 2e-3,
    initial_state: np.ndarray | None = None,
) -> NonlinearCriticalSpeed:
    """The ramp-down, then the end of the cycle by runs that must survive, repeated with
    ``dt`` halved until converged (see the module docstring).

    Parameters
    ----------
    vehicle : VehicleModel
        With rail data; the contact from profiles when the model has them.
    v_start : float, optional
        First speed [m/s] (this and every speed, time and length below: a number is SI, a
        quantity carries its unit, ``"150 km/h"``, ``"4 s"``); by default 1.2 times the linear critical speed (which must
        then exist below ``v_max``).
    v_min : float
        Lowest speed tried [m/s].
    step : float
        Speed decrement of the ramp [m/s] (5 km/h).
    tolerance : float
        Largest width of the final bracket [m/s] (0.5 km/h), and the largest change a
        halving of ``dt`` may make for the result to count as converged.
    duration : float
        Length of each run of the ramp [s]; the amplitudes are read in its last two thirds.
    dt : float
        First time step [s].
    disturbance : float
        Initial lateral displacement of every wheelset [m] (without ``initial_state``).
    threshold, persistence : float
        A run of the ramp has a limit cycle when its last-third amplitude is above
        ``threshold`` [m] and at least ``persistence`` times the middle third's; a run of
        the end-of-cycle search is dead when its amplitude falls to ``threshold``.
    creep_law, contact :
        As :func:`express.analysis.time.simulate.simulate`.
    linear : CriticalSpeed, optional
        The linear critical speed, if already known.
    v_max : float
        Upper end of the linear critical speed's search [m/s].
    extensions : int
        A ramp run whose motion still decays (above ``threshold``) is continued up to this
        many times: it may settle on a smaller cycle of another branch.
    refinements : int
        Largest number of halvings of ``dt`` (0: no step-size check).
    window, longest, spread : float
        The runs of the end-of-cycle search (:func:`express.analysis.stability.limit_cycles.
        settle_cycle`): window length [s], the time a run must survive [s] (40 s), the
        largest relative change of a settled cycle's amplitude [-] (a settled run stops early).
    initial_state : numpy.ndarray, optional
        The state ``[q; q_D']`` the ramp starts from instead of the disturbance, e.g. that of
        :attr:`NonlinearCriticalSpeed.anchor` of an earlier search, with ``v_start`` its speed.

    Raises
    ------
    ArgumentError
        For a model without rail data, bad options, or no linear critical speed below
        ``v_max`` when ``v_start`` is not given.
    """
    if vehicle.layout is None or not vehicle.wheelsets:
        raise ArgumentError("the model has no rail data (wheelsets): no hunting to follow")
    v_start = None if v_start is None else si_argument(v_start, "speed", "v_start")
    v_min, v_max, step, tolerance = (si_argument(value, "speed", name) for name, value in (
        ("v_min", v_min), ("v_max", v_max), ("step", step), ("tolerance", tolerance)))
    duration, dt, window, longest = (si_argument(value, "time", name) for name, value in (
        ("duration", duration), ("dt", dt), ("window", window), ("longest", longest)))
    disturbance, threshold = si_argument(disturbance, "length", "disturbance"), si_argument(threshold, "length", "threshold")
    for name, value in (("step", step), ("tolerance", tolerance), ("duration", duration), ("dt", dt),
                        ("disturbance", disturbance), ("threshold", threshold), ("v_min", v_min),
                        ("window", window), ("longest", longest), ("spread", spread)):
        if not (math.isfinite(value) and value > 0):
            raise ArgumentError(f"{name} must be positive, got {value!r}")
    if refinements < 0:
        raise ArgumentError(f"refinements must be 0 or more, got {refinements!r}")
    if initial_state is not None and np.shape(initial_state) != (vehicle.form.size,):
        raise ArgumentError(f"initial_state must have shape ({vehicle.form.size},), got {np.shape(initial_state)}")
    if linear is None:
        linear = critical_speed(vehicle, v_max=v_max)
    if v_start is None:
        if not linear.found or linear.unstable_at_min:
            raise ArgumentError(f"no linear critical speed below {v_max / KMH:.0f} km/h to start above: give v_start")
        v_start = 1.2 * linear.speed
    if not v_start > v_min:
        raise ArgumentError(f"v_start ({v_start / KMH:.1f} km/h) must be above v_min ({v_min / KMH:.1f} km/h)")
    if initial_state is None:
        state = np.zeros(vehicle.form.size)
        for wheelset in vehicle.wheelsets:
            state[wheelset.y] = disturbance
    else:
        state = np.array(initial_state, dtype=float)
    options = {"v_start": v_start, "v_min": v_min, "step": step, "tolerance": tolerance, "duration": duration,
               "dt": dt, "disturbance": disturbance, "threshold": threshold, "persistence": persistence,
               "extensions": extensions, "refinements": refinements, "window": window, "longest": longest,
               "spread": spread}
    settings = _Settings(v_min, step, tolerance, duration, threshold, persistence, extensions, window, longest,
                         spread, creep_law, contact)
    first = _Search()
    anchors, ramp_dead = _ramp_down(vehicle, v_start, state, dt, settings, first)
    found = attractors(first.points)  # the ramp's points alone: the fold search's are appended next
    search, checks = _refined(vehicle, dt, anchors, ramp_dead, settings, first, refinements)
    name = vehicle.wheelsets[0].name
    if search.alive is None:
        return NonlinearCriticalSpeed(None, (search.dead, math.nan), tuple(first.points), linear, name,
                                      first.used, options, None, tuple(checks), attractors=found)
    return NonlinearCriticalSpeed(search.alive, (search.dead, search.alive), tuple(first.points), linear, name,
                                  search.used, options, search.state, tuple(checks), search.anchor, found)
