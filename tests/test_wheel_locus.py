"""The yawed wheelset's contact (express.rail.wheel_locus, contact_geometry with ``yaw``).

Checks: the lead of a yawed cone in closed form; the contact found through the contact
locus is the minimum of the gap between the 3-D wheel surface (the wheelset turned by
the full rotation matrix) and the rail, found independently by scipy's minimiser; no
yaw gives the unyawed table exactly, a tiny yaw the same to rounding away from the
contact jumps; the geometry is even in the yaw and the lead odd.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import minimize

from express.base.diagnostics import ArgumentError
from express.rail.contact_geometry import ContactSetup, contact_geometry
from express.rail.profiles import standard_profile
from express.rail.wheel_locus import contact_locus
from test_contact_geometry import R0, circle_rail, cone_wheel, rail_centre

CONICITY, RAIL_RADIUS = 0.05, 0.3
SETUP = ContactSetup(inclination=0.025)
Y = np.arange(-600, 601) * 1e-5


@pytest.mark.parametrize("yaw", [0.005, 0.015, -0.024])
def test_yawed_cone_lead_in_closed_form(yaw):
    """A cone of slope tan(gamma): sin(beta) = tan(psi) tan(gamma) on every circle, the
    lead ``cos(psi) R sin(beta) - sin(psi) Y`` (R = r0 - tan(gamma) s, Y = h + s at the
    contact), to first order ``psi (R tan(gamma) - Y)``."""
    table = contact_geometry(cone_wheel(CONICITY), circle_rail(RAIL_RADIUS), Y, SETUP, yaw=yaw)
    half = SETUP.tapeline_half_distance
    for row, sigma in enumerate((1.0, -1.0)):
        s = table.wheel_position[row]
        radius, axial = R0 - CONICITY * s, half + s
        exact = sigma * (math.cos(yaw) * radius * math.tan(yaw) * CONICITY - math.sin(yaw) * axial)
        assert np.abs(table.lead[row] - exact).max() < 1e-9
        first_order = sigma * yaw * (radius * CONICITY - axial)
        assert np.abs(table.lead[row] - first_order).max() < 0.2 * abs(yaw) ** 3 + 1e-9
        # the contact's depth below the axle is R cos(beta)
        depth = radius * math.sqrt(1.0 - (math.tan(yaw) * CONICITY) ** 2)
        assert np.abs(table.radius[row] - depth).max() < 1e-8


def _wheel_point(s, beta, y, height, roll, yaw, sigma, half):
    """A point of the 3-D conical wheel in the track frame: wheel frame (x forward, Y
    along the axle, z up), yawed about z, then rolled about x, then placed."""
    radius = R0 - CONICITY * s
    local = np.array([radius * math.sin(beta), sigma * (half + s), -radius * math.cos(beta)])
    cz, sz, cx, sx = math.cos(yaw), math.sin(yaw), math.cos(roll), math.sin(roll)
    yawing = np.array([[cz, -sz, 0.0], [sz, cz, 0.0], [0.0, 0.0, 1.0]])
    rolling = np.array([[1.0, 0.0, 0.0], [0.0, cx, -sx], [0.0, sx, cx]])
    return rolling @ yawing @ local + np.array([0.0, y, R0 + height])


@pytest.mark.parametrize("y, yaw", [(2e-3, 0.015), (-4e-3, 0.024), (0.0, -0.01)])
def test_contact_is_the_3d_gap_minimum(y, yaw):
    """The distance of the 3-D wheel surface from the circular rail head, minimised over
    the wheel's points (s, beta) by scipy from the circle's bottom: zero on both sides,
    at the table's contact point (lateral position and lead)."""
    table = contact_geometry(cone_wheel(CONICITY), circle_rail(RAIL_RADIUS), np.array([y]), SETUP, yaw=yaw)
    centre = rail_centre(SETUP, RAIL_RADIUS)
    half = SETUP.tapeline_half_distance
    for row, sigma in enumerate((1.0, -1.0)):
        head = np.array([sigma * centre[0], centre[1]])

        def gap(p, sigma=sigma, head=head):
            point = _wheel_point(p[0], p[1], y, table.height[0], table.roll[0], yaw, sigma, half)
            return math.hypot(point[1] - head[0], point[2] - head[1]) - RAIL_RADIUS

        best = minimize(gap, [table.wheel_position[row, 0], 0.0], method="Nelder-Mead",
                        options={"xatol": 1e-10, "fatol": 1e-14, "maxiter": 4000})
        point = _wheel_point(best.x[0], best.x[1], y, table.height[0], table.roll[0], yaw, sigma, half)
        assert abs(best.fun) < 1e-9  # touching
        assert best.x[0] == pytest.approx(table.wheel_position[row, 0], abs=2e-6)
        assert point[0] == pytest.approx(table.lead[row, 0], abs=1e-8)
        assert sigma * point[1] == pytest.approx(table.track_position[row, 0], abs=2e-6)


@pytest.fixture(scope="module")
def s1002():
    return standard_profile("S1002"), standard_profile("60E1")


def test_no_yaw_is_the_unyawed_table_and_a_tiny_yaw_its_limit(s1002):
    plain = contact_geometry(*s1002, Y)
    zero = contact_geometry(*s1002, Y, yaw=0.0)
    for name in ("roll", "radius", "track_position", "wheel_position", "contact_angle", "wheel_curvature_lateral"):
        assert np.array_equal(getattr(plain, name), getattr(zero, name)), name
    assert not zero.lead.any()
    tiny = contact_geometry(*s1002, Y, yaw=1e-7)
    away = np.ones(len(Y), bool)
    for jump in plain.jumps:
        away &= np.abs(Y - jump.y_before) > 0.05e-3
    # the effective profile is the profile re-splined on its own grid: rounding-level changes
    for name, tolerance in (("roll", 1e-9), ("radius", 1e-9), ("track_position", 1e-8), ("contact_angle", 1e-6)):
        assert np.abs(getattr(plain, name) - getattr(tiny, name))[..., away].max() < tolerance, name
    assert np.abs(tiny.lead_rate - plain.lead_rate)[:, away].max() < 1.5e-5  # 1.1e-5 m/rad of ~0.7


def test_even_in_yaw_lead_odd(s1002):
    ahead = contact_geometry(*s1002, Y, yaw=0.02)
    back = contact_geometry(*s1002, Y, yaw=-0.02)
    for name in ("roll", "radius", "track_position", "contact_angle"):
        assert np.array_equal(getattr(ahead, name), getattr(back, name)), name
    assert np.array_equal(ahead.lead, -back.lead)
    # the wheelset's mirror image: the right wheel at -y is the left wheel at y
    assert np.allclose(ahead.radius[0], ahead.radius[1, ::-1], atol=1e-12)
    assert np.allclose(ahead.lead[0], -ahead.lead[1, ::-1], atol=1e-12)


def test_locus_of_a_flat_wheel_lies_under_the_axle():
    s = np.linspace(-0.03, 0.03, 61)
    lateral, height, lead, kept = contact_locus(s, np.zeros_like(s), np.zeros_like(s), R0, 0.75, 0.02)
    assert kept.all()
    assert np.allclose(height, 0.0) and np.allclose(lead, -math.sin(0.02) * (0.75 + s))
    assert np.allclose(lateral, math.cos(0.02) * (0.75 + s) - 0.75)


def test_bad_yaw(s1002):
    with pytest.raises(ArgumentError, match="yaw"):
        contact_geometry(*s1002, Y, yaw=0.5)
