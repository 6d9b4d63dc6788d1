"""Wear across the wheel profile by Archard's law (express.rail.wear_profile): the closed
form on a constant slip and a constant pressure, the volume on the profile equal to the
patch's (mass conservation), the Hertz distribution's shape."""

from __future__ import annotations

import math

import numpy as np
import pytest

from express.rail.wear_profile import archard_volume, profile_wear_depth

K, H, R = 1e-4, 3e9, 0.46  # wear coefficient [-], hardness [Pa], rolling radius [m]
N, GAMMA, D, B = 50e3, 0.01, 1000.0, 6e-3  # normal force, slip, distance rolled, semi-axis


def test_archard_closed_form():
    """k N s / H: 1e-4 x 50 kN x 10 m / 3 GPa = 1.667e-8 m^3 (16.7 mm^3)."""
    assert float(archard_volume(K, N, GAMMA * D, H)) == pytest.approx(K * N * GAMMA * D / H, rel=1e-15)
    assert float(archard_volume(K, N, GAMMA * D, H)) == pytest.approx(1.6667e-8, rel=1e-4)


def test_constant_pressure_and_slip_against_the_closed_form():
    """Uniform pressure ``p = N / (pi a b)`` and constant slip: a point on the centre line
    passes ``2a`` of pressure ``p``, so loses ``k p gamma 2a / H`` per passage, and
    ``D / (2 pi R)`` passages: depth ``k N gamma D / (H pi b) / (pi R)`` (``a`` drops out).
    A narrow cell at the centre gives it to 1e-7 (the cell's mean of the sqrt profile,
    achieved 4.6e-9)."""
    half = 1e-6
    depth = profile_wear_depth([-half, half], 0.0, B, N, GAMMA, D, coefficient=K, hardness=H, radius=R,
                               pressure="uniform")
    closed = K * (N / (math.pi * B)) * 2.0 * GAMMA * D / H / (2.0 * math.pi * R)
    assert float(depth[0]) == pytest.approx(closed, rel=1e-7)


@pytest.mark.parametrize("pressure", ["hertz", "uniform"])
@pytest.mark.parametrize("cells", [3, 40, 1001])
def test_the_profile_holds_the_patch_volume(pressure, cells):
    """Mass conservation: the depth over the profile times the circumference is the
    Archard volume of the patch, for any grid covering it (coarse or fine), to 1e-13
    (achieved 1.1e-16: the cells' loads are the exact integrals); several contacts add."""
    edges = np.linspace(-0.02, 0.03, cells + 1)
    centres, normals, slips = np.array([0.0, 0.012]), np.array([N, 0.5 * N]), np.array([GAMMA, 3 * GAMMA])
    depth = profile_wear_depth(edges, centres, B, normals, slips, D, coefficient=K, hardness=H, radius=R,
                               pressure=pressure)
    volume = float(np.sum(depth * np.diff(edges)) * 2 * math.pi * R)
    assert volume == pytest.approx(float(np.sum(archard_volume(K, normals, slips * D, H))), rel=1e-13)


def test_hertz_distribution_is_parabolic_across_the_patch():
    """Under Hertz pressure the line load is ``(3 N / 4b)(1 - t^2)``: zero outside the
    patch, the centre's depth 3/2 of the patch's mean (to 1e-7 on a 2 um cell, achieved
    9.3e-9)."""
    edges = np.array([-2 * B, -B, -1e-6, 1e-6, B, 2 * B])
    depth = profile_wear_depth(edges, 0.0, B, N, GAMMA, D, coefficient=K, hardness=H, radius=R)
    assert depth[0] == 0.0 and depth[-1] == 0.0
    mean = float(archard_volume(K, N, GAMMA * D, H)) / (2 * math.pi * R * 2 * B)
    assert depth[2] == pytest.approx(1.5 * mean, rel=1e-7)


def test_bad_inputs_are_refused():
    with pytest.raises(ValueError, match="pressure"):
        profile_wear_depth([0, 1], 0, B, N, GAMMA, D, coefficient=K, hardness=H, radius=R, pressure="cone")
    with pytest.raises(ValueError, match="increasing"):
        profile_wear_depth([0, 0], 0, B, N, GAMMA, D, coefficient=K, hardness=H, radius=R)
    with pytest.raises(ValueError, match="semi_b"):
        profile_wear_depth([0, 1], 0, 0.0, N, GAMMA, D, coefficient=K, hardness=H, radius=R)


def test_usfd_wear_on_the_profile_holds_the_mass():
    """The USFD wear rate's mass (rate x A x distance) equals the profile's depth x width x
    2 pi R x density, to 1e-13 (achieved: rounding); the trapezoid weights of a run's
    distances sum to its length."""
    from express.rail.wear import wear_rate_of_contact
    from express.rail.wear_profile import WHEEL_STEEL_DENSITY, rolled_per_instant, usfd_profile_wear

    distance = np.linspace(0.0, 30.0, 7)
    rolled = rolled_per_instant(distance)
    assert float(np.sum(rolled)) == pytest.approx(30.0, rel=1e-15)
    tgamma, area = np.array([5.0, 50.0, 120.0, 150.0, 0.0, 80.0, 90.0]), np.full(7, 30e-6)
    centre = np.linspace(-0.01, 0.01, 7)
    edges = np.linspace(-0.03, 0.03, 61)
    depth = usfd_profile_wear(edges, centre, B, tgamma, area, rolled, radius=R)
    mass = float(np.sum(depth * np.diff(edges)) * 2 * math.pi * R * WHEEL_STEEL_DENSITY)
    expected = float(np.sum(wear_rate_of_contact(tgamma, area) * area * 1e6 * rolled) * 1e-9)
    assert mass == pytest.approx(expected, rel=1e-13)
