"""Contact tables, elastic rails, Wickens' linear contact parameters and the wheelset
force kernel (express.rail.contact_tables, express.rail.contact_forces).

Closed forms (docs/contact.md, derived there from the centre-distance condition
|C_w - C_r| = R_w - R_r and checked against the independently solved contact geometry):
for a hollow circular tread R_w on a circular rail head R_r, centred contact angle d0,
contact distance l0 and rolling radius r0 (t = tan d0, D = l0 - r0 t),

    sigma   = l0 t / D
    epsilon = l0 (l0 + R_w sin d0) / (D (R_w - R_r) cos d0)
    lambda  = R_w t (l0 + R_r sin d0) / (D (R_w - R_r))

and for cones (R_w -> inf) epsilon = sigma, lambda = t (l0 + R_r sin d0) / D; for small
angles these are Wickens' expressions.  The force kernel's slopes at the centred
position are the terms of the linear model (express.rail.wheelrail.wheelset_terms).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy as sp

from express.model.parameters import expression_value
from express.rail.contact import hertz_contact
from express.rail.contact_forces import quasi_static_forces, wheelset_contact
from express.rail.contact_geometry import ContactSetup, contact_geometry
from express.rail.contact_tables import (
    ANGLE,
    FIELDS,
    LEAD_RATE,
    RADIUS,
    YAW_NODES,
    YAW_STEP,
    contact_tables,
    describing_gain,
    linear_contact_parameters,
    rail_deflection_map,
)
from express.rail.kalker import kalker_coefficients
from express.rail.profile_contact import linear_wheelset_terms
from express.rail.profiles import standard_profile
from express.rail.wheelrail import wheelset_terms
from test_contact_geometry import arc_wheel, circle_rail, cone_wheel


def closed_forms(l0, r0, d0, rw, rr):
    t = math.tan(d0)
    d = l0 - r0 * t
    sigma = l0 * t / d
    if math.isinf(rw):
        return sigma, sigma, t * (l0 + rr * math.sin(d0)) / d
    epsilon = l0 * (l0 + rw * math.sin(d0)) / (d * (rw - rr) * math.cos(d0))
    return epsilon, sigma, rw * t * (l0 + rr * math.sin(d0)) / (d * (rw - rr))


CASES = [  # wheel, rail, R_w, R_r, inclination (rail contacts on the 60E1's R300 crown)
    (lambda: arc_wheel(0.5, math.atan(0.01)), lambda: standard_profile("60E1"), 0.5, 0.3, 0.0),
    (lambda: arc_wheel(0.8, math.atan(0.02)), lambda: standard_profile("60E1"), 0.8, 0.3, 0.0),
    (lambda: arc_wheel(0.5, math.atan(0.04)), lambda: standard_profile("60E1"), 0.5, 0.3, 1 / 40),
    (lambda: cone_wheel(0.05), lambda: circle_rail(0.3), math.inf, 0.3, 0.0),
    (lambda: cone_wheel(0.025), lambda: circle_rail(0.2), math.inf, 0.2, 1 / 20),
]


@pytest.mark.parametrize("wheel, rail, rw, rr, inclination", CASES)
def test_wickens_parameters_match_closed_forms(wheel, rail, rw, rr, inclination):
    tables = contact_tables(wheel(), rail(), ContactSetup(inclination=inclination), reach=3e-3)
    for amplitude in (0.05e-3, 0.5e-3):
        linear = linear_contact_parameters(tables, amplitude)
        epsilon, sigma, lam = closed_forms(linear.half_distance, linear.radius, linear.delta0, rw, rr)
        assert linear.epsilon == pytest.approx(epsilon, rel=2e-4)
        assert linear.sigma == pytest.approx(sigma, rel=2e-4)
        assert linear.lambda_ == pytest.approx(lam, rel=2e-4)


def test_describing_gain():
    assert describing_gain(lambda y: 3.0 * y, 1e-3) == pytest.approx(3.0, rel=1e-12)
    # a cubic: gain of y^3 at amplitude A is 3 A^2 / 4
    assert describing_gain(lambda y: y**3, 2.0) == pytest.approx(3.0, rel=1e-9)
    # a relay of height 1: 4 / (pi A)
    assert describing_gain(np.sign, 0.5, points=4000) == pytest.approx(8 / math.pi, rel=1e-3)


@pytest.fixture(scope="module")
def s1002():
    return contact_tables(standard_profile("S1002"), standard_profile("60E1"), ContactSetup())


@pytest.fixture(scope="module")
def s1002_yawed():
    return contact_tables(standard_profile("S1002"), standard_profile("60E1"), ContactSetup(), yaw_nodes=YAW_NODES)


def test_tables_follow_the_geometry_and_hertz(s1002):
    y = np.array([-7e-3, -2e-3, 0.0, 3e-3, 6.5e-3])
    geometry = contact_geometry(standard_profile("S1002"), standard_profile("60E1"), y, ContactSetup())
    for k, yk in enumerate(y):
        at = s1002.at(float(yk))
        assert at["radius"] == pytest.approx(geometry.radius[:, k], abs=1e-12)
        assert at["angle"] == pytest.approx(geometry.contact_angle[:, k], abs=1e-12)
        for side in (0, 1):
            a_rolling = 0.5 * geometry.wheel_curvature_rolling[side, k]
            b_lateral = 0.5 * (geometry.wheel_curvature_lateral[side, k] + geometry.rail_curvature_lateral[side, k])
            ellipse = hertz_contact(50e3, 0.5 / a_rolling, 0.5 / b_lateral)
            scale = 50e3 ** (1 / 3)
            # (the tables round the curvatures to 1e-6 1/m to share ellipses between nodes)
            assert at["semi_a"][side] * scale == pytest.approx(ellipse.a, rel=1e-6)
            assert at["semi_b"][side] * scale == pytest.approx(ellipse.b, rel=1e-6)
            assert at["c22"][side] == pytest.approx(kalker_coefficients(ellipse.a, ellipse.b, 0.3)[1], rel=1e-6)


def test_tables_symmetric(s1002):
    data = s1002.data
    assert len(FIELDS) == data.shape[0]
    assert np.allclose(data[RADIUS, 0], data[RADIUS, 1, ::-1], atol=1e-12)
    assert np.allclose(data[ANGLE, 0], data[ANGLE, 1, ::-1], atol=1e-9)


@pytest.mark.parametrize("psi, radius_um, angle_mrad", [(7.5e-3, 0.064, 0.011), (12.5e-3, 0.193, 0.032),
                                                     (24e-3, None, None)])
def test_yaw_nodes_interpolated_in_psi_squared(s1002_yawed, psi, radius_um, angle_mrad):
    """Between the yaw nodes (every 5 mrad, linear in psi^2) against the exact yawed
    geometry on |y| <= 10 mm: 95 % of the nodes within 0.25 um of radius and 0.04 mrad of
    contact angle (achieved at 7.5 / 12.5 mrad: 0.064 / 0.19 um, 0.011 / 0.032 mrad;
    medians 0.002 / 0.005 / 0.011 um at 7.5 / 12.5 / 24 mrad); the rest is the band where a contact jump moves between two
    nodes (0.03-0.07 mm of y per node), where the table mixes the two sides of it.  The
    lead within 1 % of the exact everywhere off the jumps (its odd part is exact)."""
    k = int(psi / YAW_STEP)
    low, high = (k * YAW_STEP) ** 2, ((k + 1) * YAW_STEP) ** 2
    data = s1002_yawed.yawed[k] + (psi * psi - low) / (high - low) * (s1002_yawed.yawed[k + 1] - s1002_yawed.yawed[k])
    exact = contact_geometry(standard_profile("S1002"), standard_profile("60E1"), s1002_yawed.y, ContactSetup(), yaw=psi)
    near = np.abs(s1002_yawed.y) <= 10e-3
    radius = np.abs(data[RADIUS] - exact.radius)[:, near]
    angle = np.abs(data[ANGLE] - exact.contact_angle)[:, near]
    if radius_um is not None:
        assert np.percentile(radius, 95) < 0.25e-6 and np.percentile(angle, 95) < 0.04e-3
    assert np.median(radius) < 0.015e-6 and np.median(angle) < 1e-6
    off = near & np.all(np.abs(exact.lead - psi * data[LEAD_RATE]) < 0.01 * np.abs(exact.lead) + 1e-6, axis=0)
    assert off.sum() > 0.9 * near.sum()


def test_rail_map(s1002):
    rigid = rail_deflection_map(s1002, 50e3, math.inf)
    assert np.allclose(rigid.contact, [s1002.y, s1002.y])
    elastic = rail_deflection_map(s1002, 50e3, 2e7)
    grid = elastic.start + elastic.step * np.arange(elastic.contact.shape[1])
    assert np.all(np.diff(elastic.contact, axis=1) >= -1e-15)  # the contact never goes back
    assert elastic.at(0.0) == pytest.approx([0.0, 0.0], abs=1e-15)
    # y = u + (Q / kR)(tan delta(u) - tan delta(0)) on the left, where u is not stuck at a jump
    tangent = np.tan(s1002.data[ANGLE, 0])
    t0 = np.interp(0.0, s1002.y, tangent)
    for y in (-4e-3, 2e-3, 4e-3, 8e-3):
        u = elastic.at(y)[0]
        assert u + 50e3 / 2e7 * (np.interp(u, s1002.y, tangent) - t0) == pytest.approx(y, abs=2e-7)
    # in flange contact (from 6.26 mm) the contact stays at the flange while the rail gives way
    stuck = elastic.contact[0, (grid > 8e-3) & (grid < 12e-3)]
    assert stuck.min() > 6.24e-3 and stuck.max() < 6.27e-3


def test_kernel_slopes_are_the_linear_model(tmp_path):
    """Numerical slopes of the force kernel at the centred position (rigid rails, no
    saturation) against the linear terms of wheelset_terms with the profiles node's
    coefficients: the linear model is the linearisation of the nonlinear one."""
    from express.rail.profile_contact import profile_derivation, profile_tables

    wheel = arc_wheel(0.5, math.atan(0.01))
    path = tmp_path / "arc.csv"
    path.write_text("y_mm,z_mm\n" + "".join(f"{a * 1e3:.9f},{b * 1e3:.9f}\n" for a, b in zip(wheel.y, wheel.z, strict=True)))
    load, speed, amplitude = 50e3, 30.0, 0.1e-3
    node = profile_derivation(wheel=str(path), rail="60E1", gauge=1.435, flange_back=1.36, inclination=0.0,
                              wheel_radius=0.46, amplitude=amplitude, wheel_load=load, youngs_modulus=206e9,
                              poisson=0.3)
    tables = profile_tables(str(path), "60E1", inclination=0.0)
    lam = linear_contact_parameters(tables, amplitude).lambda_
    contact = wheelset_contact(tables, load, 1e6)  # friction high enough to stay linear

    def forces(**state):
        f = quasi_static_forces(contact, **{"y": 0.0, **state}, speed=speed)
        return np.array([f["Y"], f["M"]])

    # the linear model's terms, evaluated
    from express.model.records import Wheelset

    symbols = {key: sp.Symbol(key) for key in ("f1", "f2", "conicity", "r0", "b", "kR")}
    wheelset = Wheelset("W", symbols["f1"], symbols["f2"], symbols["conicity"], symbols["r0"], symbols["b"],
                        sp.S.Zero, symbols["kR"], sp.S.One, sp.Float(load))
    contact_symbols = {key: sp.Symbol(key) for key in node}
    stiffness, damping, inputs = wheelset_terms(wheelset, sp.Symbol("v"), "rho", contact_symbols)
    values = {**node, "f1": node["f11"], "f2": node["f22"], "conicity": lam, "r0": node["radius"],
              "b": node["half_distance"], "kR": 0.0, "v": speed}
    rows = {"W.y": 0, "W.rz": 1}

    def matrix(terms, column):
        out = np.zeros(2)
        for row, col, value in terms:
            if col == column:
                out[rows[row]] += expression_value(value, values)
        return out

    steps = {"y": ("W.y", 1e-6, stiffness), "psi": ("W.rz", 1e-7, stiffness),
             "y_dot": ("W.y", 1e-6, damping), "psi_dot": ("W.rz", 1e-6, damping)}
    for name, (column, h, terms) in steps.items():
        slope = (forces(**{name: h}) - forces(**{name: -h})) / (2 * h)
        assert slope == pytest.approx(-matrix(terms, column), rel=3e-4, abs=1e-3)
    slope = (forces(rho=1e-7) - forces(rho=-1e-7)) / 2e-7
    assert slope == pytest.approx(matrix(inputs, "rho"), rel=3e-4)
    # irregularity: the geometric terms act on y - yR
    assert matrix(inputs, "W.yR") == pytest.approx(matrix(stiffness, "W.y") * [1, 1], rel=1e-12)
    # the coefficients themselves
    expected = linear_wheelset_terms(linear_contact_parameters(tables, amplitude), load, node["f23"])
    assert node["lateral_stiffness"] == pytest.approx(expected["lateral_stiffness"], rel=1e-12)


def test_saturated_flange_holds_against_the_rail_stiffness(s1002):
    contact = wheelset_contact(s1002, 50e3, 0.3, 2e7)
    quiet = quasi_static_forces(contact, 5e-3, speed=30.0)
    pushed = [quasi_static_forces(contact, y, speed=30.0) for y in (8e-3, 9e-3, 10e-3)]
    # in flange contact the rail gives way: the lateral force grows with the rail's
    # stiffness, less the friction at the flange (the rail moves under Q tan(delta))
    steps = np.diff([-f["Y"] for f in pushed])
    assert np.all((steps > 0.5 * 2e7 * 1e-3) & (steps < 2e7 * 1e-3))
    assert abs(quiet["Y"]) < 0.2 * abs(pushed[0]["Y"])
    # the contact sits between the last tread node and the first flange node (6.25 and
    # 6.26 mm): tread and flange contact share the load, a two-point contact
    assert all(35 < np.degrees(f["angle_left"]) < 70.1 for f in pushed)


def test_contact_off_the_profiles_is_an_error():
    with pytest.raises(ValueError, match="no contact inside the profiles"):
        contact_tables(arc_wheel(0.4, math.atan(0.02)), circle_rail(0.25), ContactSetup(inclination=1 / 20),
                       reach=3e-3)
