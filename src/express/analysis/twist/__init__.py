"""Twisted track: the twist as track geometry, the quasi-static wheel loads on it, and
EN 14363's derailment-on-twist assessment (``docs/track.md``, "Twisted track").

:mod:`.loads` the cross-level ramp and the loads, :mod:`.standard` the limit twists and
the combined twist shape, :mod:`.assessment` the unloading and flange-climb criteria.
"""

from express.analysis.twist.assessment import FlangeClimb, TwistAssessment, assess_twist, flange_climb
from express.analysis.twist.loads import (
    TwistLoads,
    cross_level_heights,
    quasi_static_loads,
    rail_height_loads,
    takes_cross_level,
    twist_passage,
    twist_ramp,
    twisted_track,
)
from express.analysis.twist.standard import StandardTwist, standard_twist, twist_limit

__all__ = ["FlangeClimb", "StandardTwist", "TwistAssessment", "TwistLoads", "assess_twist", "cross_level_heights",
           "flange_climb", "quasi_static_loads", "rail_height_loads", "standard_twist", "takes_cross_level",
           "twist_limit", "twist_passage", "twist_ramp", "twisted_track"]
