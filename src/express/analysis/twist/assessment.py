"""EN 14363's safety against derailment on twisted track, as we take it (``docs/track.md``,
"Twist assessment").

Two criteria (:class:`~express.analysis.curving.assessment.Criterion`):

* ``dQQ0_twist``: the largest quasi-static unloading ``-dQ/Q0`` of any wheel with the
  vehicle standing on the standard twist (:func:`~express.analysis.twist.standard.standard_twist`),
  against :data:`~express.analysis.curving.assessment.UNLOADING_LIMIT` (0.6; the value a
  public summary of UIC 530-2 gives for twisted track). The loads are the linear static
  solution (:func:`~express.analysis.twist.loads.rail_height_loads`), or, for a vehicle
  with friction elements or characteristics (which that solution sees stuck or at their
  tangents), the end of a slow time run onto the twist
  (:func:`~express.analysis.twist.passage.twist_run_loads`);
* ``YQ_twist_nadal``: flange climb of the leading outer wheel in a tight curve on the
  twist. The curve's ``Y`` and ``Q`` come from the steady curving (or, where it has no
  steady state, the settled time run: :func:`~express.analysis.curving.settled.curving_or_settled`)
  in a right curve of :data:`RADIUS` (150 m, the radius of the standard's test in a tight
  curve) without cant at :data:`SPEED` (10 km/h, quasi-static); the twist's ``dQ`` of that
  wheel is added to its ``Q`` and its ``Y`` kept::

      (Y/Q)_twist = Y / (Q + dQ_twist)

  against Nadal's ``(tan g - mu) / (1 + mu tan g)``
  (:func:`~express.analysis.curving.assessment.nadal_limit`) with ``mu`` = :data:`FRICTION`
  (0.36) and the flange angle ``g`` from the contact tables (else 70 degrees). Keeping
  ``Y`` is conservative: a smaller ``Q`` lowers the creep forces' saturation ``mu Q``.
  The superposition is ours: the standard's own procedure (a test on a twisted curve, a
  twist rig with measured ``Y/Q`` in a curve, or a calculation) is not public to us.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from express.analysis.curving.assessment import UNLOADING_LIMIT, Assessment, Criterion, nadal_limit
from express.analysis.twist.loads import rail_height_loads
from express.analysis.twist.passage import slips, twist_run_loads
from express.analysis.twist.standard import StandardTwist, standard_twist
from express.numeric.statespace import VehicleModel
from express.rail.options import DEFAULT_CREEP_LAW

__all__ = ["FRICTION", "RADIUS", "SPEED", "STATIC_METHOD", "FlangeClimb", "TwistAssessment", "assess_twist", "flange_climb"]

#: Radius of the tight curve [m], speed in it [m/s] and the friction of Nadal's limit.
RADIUS, SPEED, FRICTION = 150.0, 10.0 / 3.6, 0.36
#: How the loads of a vehicle without friction elements or characteristics are found.
STATIC_METHOD = "quasi-static, K q = P u"


@dataclass(frozen=True)
class FlangeClimb:
    """The leading outer wheel in the tight curve on the twist.

    Attributes
    ----------
    wheel : str
        ``W1 left`` etc.
    y_over_q_curve, q_curve : float
        Its ``Y/Q`` and ``Q`` [N] in the curve without the twist.
    delta_q : float
        The twist's load change of that wheel [N].
    y_over_q : float
        ``Y/Q`` on the twist (``inf`` if the wheel lifts).
    limit : float
        Nadal's limit.
    source : str
        ``steady state`` or why the settled time run was taken.
    """

    wheel: str
    y_over_q_curve: float
    q_curve: float
    delta_q: float
    y_over_q: float
    limit: float
    source: str


@dataclass(frozen=True)
class TwistAssessment:
    """The twist, each wheel's quasi-static ``dQ`` on it, the flange climb (or None) and
    the criteria."""

    twist: StandardTwist
    delta_q: np.ndarray  # (n_wheelsets, 2) [N]
    wheel_load: np.ndarray  # (n_wheelsets,) [N]
    climb: FlangeClimb | None
    assessment: Assessment
    method: str = STATIC_METHOD

    @property
    def passed(self) -> bool:
        return self.assessment.passed

    def as_dict(self) -> dict:
        found = {"twist": {"body_base": self.twist.body_base, "bogie_base": self.twist.bogie_base,
                           "body_twist": self.twist.body_twist, "bogie_twist": self.twist.bogie_twist,
                           "cross_level": self.twist.cross_level.tolist()},
                 "delta_q": self.delta_q.tolist(), "wheel_load": self.wheel_load.tolist(),
                 "flange_climb": None if self.climb is None else dict(self.climb.__dict__), "method": self.method}
        return _finite(found | self.assessment.as_dict())


def _finite(value):
    """``value`` with every non-finite float (a lifted wheel's ``Y/Q``) as None, for JSON."""
    if isinstance(value, dict):
        return {key: _finite(item) for key, item in value.items()}
    if isinstance(value, list):
        return [_finite(item) for item in value]
    return None if isinstance(value, float) and not math.isfinite(value) else value


def flange_climb(vehicle: VehicleModel, delta_q: np.ndarray, *, radius: float = RADIUS, speed: float = SPEED,
                 friction: float = FRICTION) -> FlangeClimb:
    """The flange-climb check of the leading outer wheel (module docstring); ``delta_q``
    (n_wheelsets, 2) [N] the twist's load changes."""
    from express.analysis.curving.assessment import flange_angle_of
    from express.analysis.curving.measure import DEFAULT_FLANGE_ANGLE
    from express.analysis.curving.settled import curving_or_settled
    from express.analysis.curving.steady import SteadyCurve
    from express.analysis.time.force_elements import contact_tables_of

    lead = int(np.argmax([w.station for w in vehicle.wheelsets]))
    steady, settled = curving_or_settled(vehicle, [SteadyCurve(radius, 0.0, "right")], [speed])[0]
    if steady is not None:
        y_over_q, q = float(steady.wheel_rail.y_over_q[0, lead, 0]), float(steady.wheel_rail.vertical_load[0, lead, 0])
        source = "steady state"
    else:
        assert settled is not None
        y_over_q, q = float(settled.mean[f"YQ{lead + 1}L"]), float(settled.mean[f"Q{lead + 1}L"])
        source = f"settled time run: {settled.reason.split(' (')[0]}"
    loaded = q + float(delta_q[lead, 0])
    climb = y_over_q * q / loaded if loaded > 0 else math.inf
    angle = flange_angle_of(contact_tables_of(vehicle, None, DEFAULT_CREEP_LAW), DEFAULT_FLANGE_ANGLE)
    return FlangeClimb(f"{vehicle.wheelsets[lead].name} left", y_over_q, q, float(delta_q[lead, 0]), climb,
                       nadal_limit(angle, friction), source)


def assess_twist(vehicle: VehicleModel, twist: StandardTwist | None = None, *, climb: bool = True,
                 radius: float = RADIUS, speed: float = SPEED, friction: float = FRICTION) -> TwistAssessment:
    """The twist assessment of ``vehicle`` (module docstring).

    Parameters
    ----------
    vehicle : VehicleModel
        Wheels on vertical springs to rail grounds.
    twist : StandardTwist, optional
        Default :func:`~express.analysis.twist.standard.standard_twist` of the vehicle.
    climb : bool
        Add the flange-climb check (a steady curving solution, or a time run).
    radius, speed, friction : float
        Of the flange-climb check [m, m/s, -].
    """
    twist = standard_twist(vehicle) if twist is None else twist
    method = STATIC_METHOD
    if slips(vehicle):
        run = twist_run_loads(vehicle, twist)
        delta, method = run.delta_q, run.method
    else:
        delta = rail_height_loads(vehicle, twist.heights)[0]
    loads = np.array([w.wheel_load for w in vehicle.wheelsets], dtype=float)
    unloading = float(max(0.0, np.nanmax(-delta / loads[:, None])))
    criteria = [Criterion("dQQ0_twist", f"quasi-static wheel unloading -ΔQ/Q0 on the twist ({twist.describe()})",
                          unloading, UNLOADING_LIMIT, unloading <= UNLOADING_LIMIT)]
    found = None
    if climb:
        found = flange_climb(vehicle, delta, radius=radius, speed=speed, friction=friction)
        criteria.append(Criterion("YQ_twist_nadal", f"Y/Q of {found.wheel} in R {radius:g} m on the twist against "
                                  f"Nadal (mu {friction:g})", found.y_over_q, found.limit,
                                  bool(found.y_over_q <= found.limit)))
    derailment = None
    if found is not None and not math.isfinite(found.y_over_q):
        derailment = f"{found.wheel} lifts on the twist in R {radius:g} m (Q + ΔQ <= 0)"
    return TwistAssessment(twist, delta, loads, found, Assessment(tuple(criteria), derailment), method)
