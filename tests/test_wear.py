"""Energy and damage numbers of a contact (issue 37, item 1): the frictional power Tgamma
of the contact kernel against the creep forces and creepages computed by hand from the
same state's outputs and geometry, the USFD wear function's regimes and boundaries
(express.rail.wear), Burstow's RCF damage function's corners."""

from __future__ import annotations

import math

import numpy as np
import pytest

from express.rail.contact_forces import patch_area, quasi_static_forces, wheelset_contact
from express.rail.contact_geometry import ContactSetup, contact_geometry
from express.rail.contact_tables import contact_tables
from express.rail.profiles import standard_profile
from express.rail.wear import BURSTOW, USFD_R8T, burstow_damage, usfd_wear_rate, wear_rate_of_contact

LOAD, MU, SPEED = 10e3, 0.3, 20.0
#: Just either side of a boundary [N/mm^2].
EPS = 1e-9


# -- the USFD wear function (R8T, Braghin et al. 2006 / Lewis & Dwyer-Joyce 2004) --------

@pytest.mark.parametrize(("specific", "rate"), [
    (-1.0, 0.0),  # no negative power
    (0.0, 0.0),
    (5.0, 5.3 * 5.0),  # mild: K1 = 5.3 Tgamma/A
    (10.4 - EPS, 5.3 * (10.4 - EPS)),  # below the first boundary: 55.12
    (10.4, 55.0),  # on it: severe, the plateau K2 = 55.0
    (40.0, 55.0),
    (77.2, 55.0),  # the second boundary belongs to the plateau
    (77.2 + EPS, 0.0),  # just beyond: 61.9 x - 4778.7 = -0.02 as published, clamped
    (78.0, 61.9 * 78.0 - 4778.7),  # catastrophic: 49.5
    (100.0, 61.9 * 100.0 - 4778.7),  # 1411.3
])
def test_usfd_regimes_and_boundaries(specific, rate):
    """Each regime and both sides of each boundary, to 1e-12 relative (achieved: rounding,
    the same expressions)."""
    assert float(usfd_wear_rate(specific)) == pytest.approx(rate, rel=1e-12, abs=1e-12)


def test_usfd_coefficients_are_the_published_ones():
    assert tuple(USFD_R8T) == (5.3, 10.4, 55.0, 77.2, 61.9, 4778.7)


def test_wear_rate_of_a_contact_divides_by_the_area_in_square_millimetres():
    """100 N on 20 mm^2 (2e-5 m^2) is 5 N/mm^2: mild, 26.5; no area (a lifted wheel), none;
    shapes broadcast."""
    rates = wear_rate_of_contact([[100.0, 100.0, 3.0]], [[2e-5, 1e-6, 0.0]])
    assert rates.shape == (1, 3)
    assert rates[0].tolist() == pytest.approx([26.5, 61.9 * 100.0 - 4778.7, 0.0], rel=1e-12)


# -- Burstow's RCF damage function ---------------------------------------------------------

@pytest.mark.parametrize(("tgamma", "damage"), [
    (0.0, 0.0), (15.0, 0.0),  # no damage up to the threshold
    (15.0 + 1e-3, 1e-5 * 1e-3 / 50.0),  # then rising
    (40.0, 0.5e-5), (65.0, 1e-5),  # linearly to the peak
    (120.0, 0.5e-5),  # falling as wear takes over
    (175.0 - 1e-3, 1e-5 * 1e-3 / 110.0), (175.0, 0.0), (300.0, 0.0),  # none beyond
])
def test_burstow_corners(tgamma, damage):
    """The corners of the function and points between them, to 1e-10 relative (achieved:
    equal, and 1.6e-11 at the 1e-3 N steps beside the corners, cancellation)."""
    assert float(burstow_damage(tgamma)) == pytest.approx(damage, rel=1e-10, abs=1e-22)


def test_burstow_coefficients():
    assert tuple(BURSTOW) == (15.0, 65.0, 175.0, 1e-5)


# -- Tgamma of the contact kernel ----------------------------------------------------------

@pytest.fixture(scope="module")
def contact():
    tables = contact_tables(standard_profile("S1002"), standard_profile("60E1"), ContactSetup(),
                            youngs_modulus=2 * 82e9 * 1.28, poisson=0.28)
    return wheelset_contact(tables, LOAD, MU)


def _grid_node(contact, y):
    """The table node nearest ``y``: there the tables are the geometry itself."""
    tables = contact.tables
    return tables.start + round((y - tables.start) / tables.step) * tables.step


@pytest.mark.parametrize("law", ["polach", "fastsim"])
@pytest.mark.parametrize(("y", "psi"), [(1e-3, -5e-3), (3e-3, 10e-3), (6.5e-3, 0.0), (8e-3, 10e-3)])
def test_tgamma_is_creep_forces_times_creepages(contact, law, y, psi):
    """On a table node, no rates, no curvature (``q = 0``): by hand from the geometry and
    the kernel's outputs, the creepages ``eta = -psi / cos(delta)``, the right wheel's
    ``xi`` from the left one's through the common rotation ``(1 - xi) / r``, the lateral
    creep force ``T = (Y + sigma N sin(delta)) / cos(delta)`` from the track-plane forces;
    then ``Tgamma = |Fx xi + T eta|``.  Asserted: ``xi`` of the right wheel to 1e-11
    relative (achieved 2.1e-13), ``eta`` to 1e-12 (achieved: equal), ``T`` to 1e-12
    (achieved 1.0e-14), Tgamma to 1e-12 (achieved: equal); the power is dissipated
    (``Fx xi + T eta < 0``)."""
    y = _grid_node(contact, y)
    f = quasi_static_forces(contact, y, psi, speed=SPEED, law=law)
    geometry = contact_geometry(standard_profile("S1002"), standard_profile("60E1"), np.array([y]),
                                ContactSetup()).at(y)
    radius = np.asarray(geometry["radius"], dtype=float)
    rate = (1.0 - f["xi_left"]) / radius[0]
    assert f["xi_right"] == pytest.approx(1.0 - rate * radius[1], rel=1e-11, abs=1e-15)
    for side, sigma in (("left", 1.0), ("right", -1.0)):
        delta = f[f"angle_{side}"]
        eta = -psi / math.cos(delta)
        assert f[f"eta_{side}"] == pytest.approx(eta, rel=1e-12, abs=1e-18)
        creep = (f[f"Y_{side}"] + sigma * f[f"N_{side}"] * math.sin(delta)) / math.cos(delta)
        assert f[f"T_{side}"] == pytest.approx(creep, rel=1e-12, abs=1e-9)
        power = f[f"Fx_{side}"] * f[f"xi_{side}"] + creep * eta
        assert power < 0.0
        assert f[f"Tgamma_{side}"] == pytest.approx(abs(power), rel=1e-12)


def test_patch_area_is_the_hertz_ellipse(contact):
    """``pi a b`` with the semi-axes of 1 N scaled by ``N^(1/3)`` each, at the final normal
    force: 1e-12 relative (achieved: equal); a lifted wheel (N <= 0) has none."""
    from express.rail.contact_tables import SEMI_A, SEMI_B

    tables = contact.tables
    for y in (2e-3, 8e-3):
        y = _grid_node(contact, y)
        f = quasi_static_forces(contact, y, law="fastsim")
        k = round((y - tables.start) / tables.step)
        for row, side in enumerate(("left", "right")):
            a, b = tables.data[SEMI_A, row, k], tables.data[SEMI_B, row, k]
            area = patch_area(f[f"unit_area_{side}"], f[f"N_{side}"])
            assert area == pytest.approx(math.pi * a * b * f[f"N_{side}"] ** (2 / 3), rel=1e-12)
    assert patch_area(1e-6, -5.0) == 0.0


@pytest.mark.parametrize(("positions", "tolerance"), [
    ((-3e-3, 1e-3, 2e-3, 4e-3, 5.5e-3), 2.2e-7),  # tread: achieved 1.7e-7 m
    ((6.5e-3, 8e-3, 9.5e-3), 1.2e-4),  # flange: achieved 8.9e-5 m (0.09 mm)
])
def test_contact_position_on_the_wheel(contact, positions, tolerance):
    """The kernel's ``wheel_u`` (the track-plane arm turned back by the roll, less the
    centred contact's) against the contact geometry's position on the wheel profile, both
    from the centred wheelset's contact point; positive toward the field side."""
    wheel, rail = standard_profile("S1002"), standard_profile("60E1")
    centred = np.asarray(contact_geometry(wheel, rail, np.array([0.0]), ContactSetup()).at(0.0)["wheel_position"])
    for y in positions:
        y = _grid_node(contact, y)
        f = quasi_static_forces(contact, y, law="fastsim")
        geometry = contact_geometry(wheel, rail, np.array([y]), ContactSetup()).at(y)
        expected = np.asarray(geometry["wheel_position"], dtype=float) - centred
        assert abs(f["wheel_u_left"] - expected[0]) < tolerance and abs(f["wheel_u_right"] - expected[1]) < tolerance
