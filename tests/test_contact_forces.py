"""The forces of a yawed wheelset (express.rail.contact_forces): the wheel's rotation
balances the pitch moment about the axle, checked with 3-D vectors from the exact yawed
geometry (contact point, contact plane, every force including the normal one); the yaw
moment uses the contact's lead."""

from __future__ import annotations

import math

import numpy as np
import pytest

from express.rail.contact_forces import quasi_static_forces, wheelset_contact
from express.rail.contact_geometry import ContactSetup, contact_geometry
from express.rail.contact_tables import YAW_NODES, YAW_STEP, contact_tables
from express.rail.profiles import standard_profile

LOAD, MU = 10e3, 0.3


@pytest.fixture(scope="module")
def profiles():
    return standard_profile("S1002"), standard_profile("60E1")


@pytest.fixture(scope="module")
def contact(profiles):
    return wheelset_contact(contact_tables(*profiles, ContactSetup(), youngs_modulus=2 * 82e9 * 1.28, poisson=0.28,
                                           yaw_nodes=YAW_NODES),
                            LOAD, MU)


def _moments(forces, geometry, y, psi):
    """Moments about the axle and about the vertical of the rails' forces on the wheels,
    from 3-D vectors: the axle (-sin psi, cos psi, 0) turned by the roll about x, each
    contact at (lead, y_contact, z_contact) from the wheelset centre, its force
    Fx e_x + T t + N n with t, n in the cross-section at the contact angle."""
    roll = float(geometry["roll"])
    axle = np.array([-math.sin(psi), math.cos(psi) * math.cos(roll), math.cos(psi) * math.sin(roll)])
    pitch = yaw = roll_moment = 0.0
    for row, (side, sigma) in enumerate((("left", 1.0), ("right", -1.0))):
        delta = forces[f"angle_{side}"]
        normal, fx, lateral = forces[f"N_{side}"], forces[f"Fx_{side}"], forces[f"Y_{side}"]
        creep = (lateral + sigma * normal * math.sin(delta)) / math.cos(delta)
        force = (np.array([fx, 0.0, 0.0]) + creep * np.array([0.0, math.cos(delta), sigma * math.sin(delta)])
                 + normal * np.array([0.0, -sigma * math.sin(delta), math.cos(delta)]))
        # the contact from the centre: lateral from the track position, vertical its depth
        # below the axle turned by the roll
        arm = sigma * float(geometry["track_position"][row]) - y
        depth = float(geometry["radius"][row])
        point = np.array([float(geometry["lead"][row]), arm, arm * math.tan(roll) - depth / math.cos(roll)])
        moment = np.cross(point, force)
        pitch += axle @ moment
        yaw += moment[2]
        roll_moment += moment[0]
    return pitch, yaw, roll_moment


@pytest.mark.parametrize("y, psi", [(8e-3, 2 * YAW_STEP), (3e-3, 2 * YAW_STEP), (6.5e-3, 3 * YAW_STEP)])
def test_rotation_balances_the_pitch_moment(profiles, contact, y, psi):
    """On a yaw node (the tables exact there), Polach's law: the pitch moment of all
    forces, normal ones included, is zero to 1.5e-4 of one wheel's r Fx (achieved
    4.9e-5: the balance neglects the roll's share of the axle); the 3-D yaw moment
    equals the kernel's to 1.5e-14 relative (achieved 4.5e-15, rounding)."""
    forces = quasi_static_forces(contact, y, psi, speed=2.0, law="polach")
    geometry = contact_geometry(*profiles, np.array([y]), ContactSetup(), yaw=psi).at(y)
    pitch, yaw, _ = _moments(forces, geometry, y, psi)
    scale = 0.46 * max(abs(forces["Fx_left"]), abs(forces["Fx_right"]))
    assert abs(pitch) < 1.5e-4 * scale, (pitch, scale)
    assert forces["M"] == pytest.approx(yaw, rel=1.5e-14)


@pytest.mark.parametrize("law", ["polach", "fastsim"])
@pytest.mark.parametrize("y, psi", [(8e-3, 2 * YAW_STEP), (6.5e-3, 3 * YAW_STEP), (3e-3, 0.0), (-5e-3, 0.0)])
def test_the_roll_moment_is_the_rails_forces_about_the_centre(profiles, contact, y, psi, law):
    """The kernel's ``Mx = sum(sigma l Q + (r - sigma l phi_g) Y_wheel)`` (the contact's
    depth to first order in the roll) against the roll moment of the 3-D forces at the
    3-D contact points (:func:`_moments`), with unequal loads (12 and 9 kN): within
    1e-4 relative (achieved 5.9e-5 on the flange at 8 mm, 1e-9 on the tread: the depth's
    second order in the roll).  The depth ``r`` alone, without the roll's term, is
    2.4e-2 off on the flange at 8 mm."""
    forces = quasi_static_forces(contact, y, psi, speed=2.0, law=law, loads=(12e3, 9e3))
    geometry = contact_geometry(*profiles, np.array([y]), ContactSetup(), yaw=psi).at(y)
    _, _, roll_moment = _moments(forces, geometry, y, psi)
    assert forces["Mx"] == pytest.approx(roll_moment, rel=1e-4)


# ------------------------------------------------------------------ the wheels' rise on their rails


def _rise_case():
    from express.rail.contact_forces import contact_set

    tables = contact_tables(standard_profile("S1002"), standard_profile("60E1"), ContactSetup(), reach=12e-3)
    contact = wheelset_contact(tables, 55e3, 0.3)
    return tables, contact_set([contact])


def test_the_wheelset_centre_rises_as_the_contact_geometry_says():
    """The centre's rise the tables integrate from ``dz = sigma (tan(delta) du - (l - d
    tan(delta)) dphi)`` (:func:`express.rail.wheel_rise.rise_tables`, whose side rise
    is ``z_g + sigma lever phi_g``) against the geometry solver's own wheelset height, an
    independent solution of the rigid contact (the minimum gap zero on both sides), over
    +-12 mm with the flange and its contact jump: within 0.01 um of a 9.86 mm climb
    (achieved 0.0014 um).  With the depth ``r`` for ``d`` it was 49 um off; with both
    sides' mean, 7 um at the jump."""
    tables, arrays = _rise_case()
    y = tables.y
    geometry = contact_geometry(standard_profile("S1002"), standard_profile("60E1"), y, ContactSetup())
    sigma = np.array([1.0, -1.0])[:, None]
    rows = y.size
    centre = arrays.rise[0, 0, :, :rows] - sigma * arrays.lever[0, 0, :, :rows] * tables.data[9][None, 0]
    height = geometry.height - np.interp(0.0, y, geometry.height)
    assert np.ptp(height) > 9e-3  # the flange climb is in the range
    for side in range(2):
        assert np.max(np.abs(centre[side] - height)) < 1e-8


def test_the_rise_presses_each_wheel_by_the_slope_of_its_contact():
    """At the geometric roll the press ``h - sigma lever phi`` of
    :func:`~express.rail.wheel_rise.contact_rise` moves by ``sigma tan(delta) du``: the
    lateral force ``-sigma Q tan(delta)`` is the gradient of the contact springs' energy
    (by differences inside a cell of the 0.01 mm tables, on the tread and the flange;
    within 0.5 % of the slope, the cell's own change of ``tan(delta)``: achieved 0.33 %
    on the flange, 0.02 % on the tread)."""
    from express.rail.wheel_rise import contact_rise
    from express.rail.contact_tables import ANGLE, ROLL

    tables, arrays = _rise_case()
    out, moved = np.zeros((2, 2)), np.zeros((2, 2))
    h = 1e-9
    for u in (-4.0033e-3, 1.2345e-3, 4.5003e-3, 8.0005e-3, 10.3004e-3):
        contact_rise(arrays, 0, u, 0.0, out)
        contact_rise(arrays, 0, u + h, 0.0, moved)
        roll = np.interp(u, tables.y, tables.data[ROLL, 0])
        for side, sigma in ((0, 1.0), (1, -1.0)):
            slope = ((moved[side, 0] - sigma * moved[side, 1] * roll) - (out[side, 0] - sigma * out[side, 1] * roll)) / h
            expected = sigma * math.tan(np.interp(u, tables.y, tables.data[ANGLE, side]))
            assert slope == pytest.approx(expected, rel=5e-3), (u, side)
