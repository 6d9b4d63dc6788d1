"""EN 14363 running-safety quantities of a run or a steady state, each against its limit.

From the wheel/rail outputs (:class:`~express.analysis.curving.outputs.WheelRailOutputs`)
along the distance run (``docs/curving.md``, "Running safety"):

* ``(Y/Q)2m`` of every wheel: the 2 m sliding mean of its derailment quotient, taken in
  windows every 0.5 m, its largest value against the limit 0.8 (for curves of
  R >= 250 m; for a run through a smaller radius no limit is given here, the public
  material we could read gives none) and, while the wheel is in flange contact (its Y/Q
  counted as zero elsewhere: a tread contact cannot climb), against **Nadal's**
  flange-climb limit ``(tan(gamma) - mu) / (1 + mu tan(gamma))`` from the flange angle
  ``gamma`` and the friction coefficient ``mu``;
* ``(ΣY)2m`` of every wheelset: the largest 2 m sliding mean of the track shift force's
  size against Prud'homme's ``alpha (10 kN + 2 Q0 / 3)``, ``Q0`` the static wheel load
  and ``alpha = 1`` (the factor for other vehicle kinds is a parameter);
* of a time run of 100 m or more, EN 14363's instability criterion of every wheelset
  (``SY1_rms``: the sliding rms over 100 m of ``ΣY`` filtered at ``f0 ± 2 Hz`` against
  ``(ΣY)lim / 2``, :mod:`express.analysis.curving.instability`);
* ``ΔQ/Q0`` of the vehicle: the largest wheel unloading, against
  :data:`UNLOADING_LIMIT` (0.6; a value the public material we read does not state for
  running, see ``docs/curving.md``).

A steady state is one window: its sliding means are its values.  A run **derails**
(:attr:`Assessment.derailment`) when the 2 m sliding mean of a flanging wheel's Y/Q
exceeds Nadal's limit, or a wheel lifts (Q <= 0, unfiltered).  A time run's Y and Q are
low-pass filtered at 20 Hz first, and the assessment carries each quantity's 0.15 %, 50 %
and 99.85 % values (:mod:`express.analysis.curving.processing`); the limits are checked
against the largest values.

With the contact tables the assessment also carries each wheel's energy and damage
numbers (:class:`WheelDamage`: Tgamma, the USFD wear rate, Burstow's RCF index, largest
and mean; ``docs/wear.md``), without limits.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any, cast

import numpy as np

from express.analysis.curving.outputs import SIDES, WheelRailOutputs
from express.analysis.curving.processing import Filtering, Percentiles, filtered, percentiles
from express.rail.contact_forces import ContactSet
from express.rail.options import DEFAULT_CREEP_LAW, CreepLaw

__all__ = [
    "SAMPLING",
    "UNLOADING_LIMIT",
    "WINDOW",
    "YQ_LIMIT",
    "YQ_LIMIT_RADIUS",
    "Assessment",
    "Criterion",
    "WheelDamage",
    "assess",
    "assess_run",
    "assess_steady",
    "flange_angle_of",
    "nadal_limit",
    "prudhomme_limit",
    "sliding_mean",
    "smallest_radius",
    "wheel_damage",
]

#: Length of the sliding mean [m] and the spacing of its windows [m].
WINDOW, SAMPLING = 2.0, 0.5
#: Limit of (Y/Q)2m for curves of R >= :data:`YQ_LIMIT_RADIUS` [m].
YQ_LIMIT, YQ_LIMIT_RADIUS = 0.8, 250.0
#: Limit of the wheel unloading ΔQ/Q0 (see the module docstring).
UNLOADING_LIMIT = 0.6


def nadal_limit(flange_angle: float, friction: float) -> float:
    """Nadal's flange-climb limit of Y/Q.

    Examples
    --------
    >>> round(nadal_limit(math.radians(70.0), 0.36), 3)
    1.2
    """
    t = math.tan(flange_angle)
    return (t - friction) / (1.0 + friction * t)


def prudhomme_limit(static_load: float, alpha: float = 1.0) -> float:
    """Prud'homme's limit of the track shift force, ``alpha (10 kN + 2 Q0 / 3)`` [N] for a
    static wheel load ``Q0`` [N] (an axle load of ``2 Q0``)."""
    return alpha * (10e3 + 2.0 * static_load / 3.0)


def sliding_mean(distance: np.ndarray, values: np.ndarray, window: float = WINDOW,
                 sampling: float = SAMPLING) -> np.ndarray:
    """Means of ``values`` (shape (N, ...)) over windows ``[s, s + window]`` of the
    distance, one every ``sampling`` metres (trapezoidal integration, linear between
    samples); one value, the value itself, for a run shorter than a window."""
    distance = np.asarray(distance, dtype=float)
    values = np.asarray(values, dtype=float)
    if distance.size < 2 or distance[-1] - distance[0] < window:
        return values.mean(axis=0, keepdims=True)
    steps = np.diff(distance)[(...,) + (None,) * (values.ndim - 1)]
    integral = np.concatenate([np.zeros((1,) + values.shape[1:]),
                               np.cumsum(0.5 * steps * (values[1:] + values[:-1]), axis=0)])
    starts = np.arange(distance[0], distance[-1] - window + 1e-9, sampling)
    flat = integral.reshape(distance.size, -1)
    low = np.stack([np.interp(starts, distance, column) for column in flat.T], axis=1)
    high = np.stack([np.interp(starts + window, distance, column) for column in flat.T], axis=1)
    return ((high - low) / window).reshape((starts.size,) + values.shape[1:])


@dataclass(frozen=True)
class Criterion:
    """One assessed quantity.

    Attributes
    ----------
    name : str
        ``YQ1L``, ``YQ1L_nadal``, ``SY1``, ``SY1_rms``, ``dQQ0``.
    quantity : str
        What it is, in words.
    value : float
        Its largest value (SI: N for forces, ratios dimensionless).
    limit : float or None
        The limit (None: none applies).
    passed : bool or None
        ``value <= limit`` (None without a limit).
    unit : str
    """

    name: str
    quantity: str
    value: float
    limit: float | None
    passed: bool | None
    unit: str = ""

    def as_dict(self) -> dict:
        return {"name": self.name, "quantity": self.quantity, "value": self.value, "limit": self.limit,
                "passed": self.passed, "unit": self.unit}


@dataclass(frozen=True)
class WheelDamage:
    """The energy and damage numbers of one wheel over a run (``docs/wear.md``): the
    largest and the mean (over the instants, equally spaced in distance) of its
    frictional power Tgamma [N], USFD wear rate [ug/(m mm^2)] and Burstow RCF damage
    index per passage [-].  No limits: they are not running-safety criteria."""

    wheel: str
    tgamma_max: float
    tgamma_mean: float
    wear_max: float
    wear_mean: float
    rcf_max: float
    rcf_mean: float

    def as_dict(self) -> dict:
        return dict(self.__dict__)


@dataclass(frozen=True)
class Assessment:
    """Every :class:`Criterion` of a run, and whether (and why) it derailed; with the
    contact tables also each wheel's :class:`WheelDamage` (not a criterion); of a time
    run, how its forces were filtered and their percentiles
    (:mod:`express.analysis.curving.processing`)."""

    criteria: tuple[Criterion, ...]
    derailment: str | None = None
    wear: tuple[WheelDamage, ...] = ()
    filtering: Filtering | None = None
    percentiles: Percentiles | None = None

    @property
    def passed(self) -> bool:
        """No criterion failed (those without a limit do not count)."""
        return all(c.passed is not False for c in self.criteria)

    def as_dict(self) -> dict:
        found: dict[str, Any] = {"passed": self.passed, "derailment": self.derailment,
                                 "criteria": [c.as_dict() for c in self.criteria]}
        if self.wear:
            found["wear"] = [w.as_dict() for w in self.wear]
        if self.filtering is not None:
            found["filtering"] = self.filtering.as_dict()
        if self.percentiles is not None:
            found["percentiles"] = self.percentiles.as_dict()
        return found


def wheel_damage(outputs: WheelRailOutputs) -> tuple[WheelDamage, ...]:
    """Each wheel's :class:`WheelDamage` (none without the frictional power: the
    dead-band contact)."""
    if outputs.frictional_power is None:
        return ()
    tgamma, wear, rcf = outputs.frictional_power, outputs.wear_rate, outputs.rcf_damage
    assert wear is not None and rcf is not None
    return tuple(WheelDamage(f"{j + 1}{side}", *(float(f(values[:, j, k])) for values in (tgamma, wear, rcf)
                                                 for f in (np.max, np.mean)))
                 for j in range(outputs.wheelsets) for k, side in enumerate(SIDES))


def _check(name: str, quantity: str, value: float, limit: float | None, unit: str = "") -> Criterion:
    return Criterion(name, quantity, float(value), limit, None if limit is None else bool(value <= limit), unit)


def assess(outputs: WheelRailOutputs, distance, *, radius: float, friction: float, flange_angle: float,
           alpha: float = 1.0, speed: float | None = None) -> Assessment:
    """The running-safety criteria of ``outputs`` (module docstring).

    Parameters
    ----------
    outputs : WheelRailOutputs
        N instants.
    distance : array_like, shape (N,)
        Distance run at each instant [m] (a steady state: any one value).
    radius : float
        The smallest curve radius of the run [m] (``inf`` on straight track).
    friction : float
        mu for Nadal's limit.
    flange_angle : float
        The wheel's flange angle [rad] for Nadal's limit.
    alpha : float
        Factor of Prud'homme's limit.
    speed : float, optional
        The running speed of a time run [m/s]: its Y and Q are filtered and their
        percentiles taken (:mod:`express.analysis.curving.processing`), and the
        instability criterion of every wheelset is added
        (:mod:`express.analysis.curving.instability`) when the run is at least 100 m long.
    """
    d = np.atleast_1d(np.asarray(distance, dtype=float))
    raw, filtering, statistics = outputs, None, None
    if speed is not None and d.size > 1:
        outputs, filtering = filtered(raw, d, speed)
        statistics = percentiles(outputs)
    y_over_q = sliding_mean(d, outputs.y_over_q)  # (windows, n, 2)
    climbing = sliding_mean(d, np.where(outputs.flange_contact, outputs.y_over_q, 0.0))
    shift = sliding_mean(d, outputs.track_shift_force)  # (windows, n)
    nadal = nadal_limit(flange_angle, friction)
    limit_08 = YQ_LIMIT if radius >= YQ_LIMIT_RADIUS else None
    criteria = []
    for j in range(outputs.wheelsets):
        for k, side in enumerate(SIDES):
            criteria.append(_check(f"YQ{j + 1}{side}", f"(Y/Q)2m of wheel {j + 1}{side} against 0.8",
                                   float(y_over_q[:, j, k].max()), limit_08))
            criteria.append(_check(f"YQ{j + 1}{side}_nadal", f"(Y/Q)2m in flange contact of wheel {j + 1}{side} "
                                   f"against Nadal (flange {math.degrees(flange_angle):.0f} deg, mu {friction:g})",
                                   float(climbing[:, j, k].max()), nadal))
    for j in range(outputs.wheelsets):
        criteria.append(_check(f"SY{j + 1}", f"(ΣY)2m of wheelset {j + 1} against Prud'homme",
                               float(np.abs(shift[:, j]).max()), prudhomme_limit(float(outputs.static_load[j]), alpha),
                               "N"))
    if speed is not None:
        criteria += _instability(raw, d, speed, alpha)
    criteria.append(_check("dQQ0", "wheel unloading ΔQ/Q0 of the vehicle", float(outputs.vehicle_unloading.max()),
                           UNLOADING_LIMIT))
    return Assessment(tuple(criteria), _derailment(raw, d, climbing, nadal), wheel_damage(raw), filtering,
                      statistics)


def _instability(outputs: WheelRailOutputs, distance: np.ndarray, speed: float, alpha: float) -> list[Criterion]:
    """EN 14363's instability criterion of every wheelset: the filtered sliding rms of
    ``ΣY`` over 100 m against half Prud'homme's limit (none for a run under 100 m)."""
    from express.analysis.curving.instability import HALF_WIDTH, WINDOW, instability_rms

    criteria = []
    for j in range(outputs.wheelsets):
        found = instability_rms(distance, speed, outputs.track_shift_force[:, j])
        if found is not None:
            limit = 0.5 * prudhomme_limit(float(outputs.static_load[j]), alpha)
            criteria.append(_check(f"SY{j + 1}_rms", f"ΣY rms over {WINDOW:g} m ({found.frequency:.2f} ± {HALF_WIDTH:g} Hz) "
                                   f"of wheelset {j + 1} against (ΣY)lim / 2 (instability)", found.largest, limit, "N"))
    return criteria


def _derailment(outputs: WheelRailOutputs, distance: np.ndarray, y_over_q: np.ndarray, nadal: float) -> str | None:
    lifted = np.argwhere(outputs.vertical_load <= 0.0)
    if lifted.size:
        k, j, side = lifted[0]
        return f"wheel {j + 1}{SIDES[side]} lifts (Q <= 0) at d = {distance[min(k, distance.size - 1)]:.1f} m"
    climbing = np.argwhere(y_over_q > nadal)
    if climbing.size:
        k, j, side = climbing[0]
        start = distance[0] + SAMPLING * k if distance.size > 1 else distance[0]
        return (f"wheel {j + 1}{SIDES[side]}: (Y/Q)2m = {y_over_q[k, j, side]:.3f} beyond Nadal's limit "
                f"{nadal:.3f} over the 2 m from d = {start:.1f} m (flange climb)")
    return None


def flange_angle_of(contact: ContactSet | None, default: float) -> float:
    """The flange angle [rad] for Nadal's limit: the largest contact angle of the contact
    tables (stacked, :func:`express.forces.contact.contact_arrays`), else ``default``."""
    if contact is None:
        return default
    from express.rail.contact_tables import ANGLE

    return float(np.max(contact.tables[..., ANGLE]))


def smallest_radius(track) -> float:
    """The smallest radius of a track's circular curves [m] (``inf`` for none)."""
    radii = [float(segment.radius) for segment in track.segments if hasattr(segment, "radius")]
    return min(radii, default=math.inf)


def assess_run(vehicle, track, result) -> tuple[WheelRailOutputs, Assessment]:
    """The wheel/rail outputs and the assessment of a time simulation
    (:class:`~express.analysis.time.simulate.SimulationResult`) along ``track``."""
    from express.analysis.curving.measure import DEFAULT_FLANGE_ANGLE, wheel_rail_outputs
    from express.analysis.time.force_elements import contact_tables_of
    from express.analysis.time.track_inputs import track_inputs

    contact = None
    label = str(result.options.get("contact", ""))
    if label.startswith("tables"):
        law = cast("CreepLaw", label.partition("(")[2].rstrip(")") or DEFAULT_CREEP_LAW)  # the run's own label
        contact = contact_tables_of(vehicle, "tables", law)
    outputs = getattr(result, "wheel_rail", None)  # the march's own contact forces (contact tables)
    if outputs is None:
        inputs = track_inputs(vehicle, track, result.distance, result.speed)
        outputs = wheel_rail_outputs(vehicle, result.q, result.q_dot, inputs, result.speed, contact=contact)
    from express.analysis.curving.bogie_frames import bogie_frame_criteria

    friction = min(w.friction for w in vehicle.wheelsets)
    angle = flange_angle_of(contact, DEFAULT_FLANGE_ANGLE)
    assessment = assess(outputs, result.distance, radius=smallest_radius(track), friction=friction,
                        flange_angle=angle, speed=float(result.speed))
    frames = tuple(_check(name, quantity, value, limit, "m/s^2")
                   for name, quantity, value, limit in bogie_frame_criteria(vehicle, result))
    return outputs, replace(assessment, criteria=assessment.criteria + frames)


def assess_steady(vehicle, steady) -> Assessment:
    """The assessment of a steady state (:class:`~express.analysis.curving.steady.SteadyCurving`)."""
    from express.analysis.curving.measure import DEFAULT_FLANGE_ANGLE
    from express.analysis.time.force_elements import contact_tables_of

    contact = None
    if steady.contact.startswith("tables"):
        contact = contact_tables_of(vehicle, "tables", steady.contact.partition("(")[2].rstrip(")") or DEFAULT_CREEP_LAW)
    friction = min(w.friction for w in vehicle.wheelsets)
    return assess(steady.wheel_rail, [0.0], radius=steady.curve.radius, friction=friction,
                  flange_angle=flange_angle_of(contact, DEFAULT_FLANGE_ANGLE))
