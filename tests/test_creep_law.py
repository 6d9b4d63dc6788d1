"""Creep-force laws (express.rail.creep_law): Polach's method and FASTSIM.

FASTSIM tends to Kalker's linear theory (f11, f22, f23 of the Hertz ellipse and Table
E.3, express.rail.contact) for small creepages, Polach's method for one creepage at a
time (with spin); both saturate at mu N and are odd in the creepages.  Polach's closed form is checked at a point by hand and its spin factor K_M
against its two limits; FASTSIM converges with its grid.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from express.rail.creep_law import (
    _fastsim,
    _fastsim_factors,
    _fastsim_grid,
    fastsim,
    polach,
    polach_forces,
    spin_reduction,
)
from express.rail.kalker import kalker_coefficients

G = 80e9
NORMAL = 50e3
MU = 0.3
LAWS = {"polach": polach, "fastsim": fastsim}
# ellipses long across, round and long along the rolling direction, and very slender (a flange)
SHAPES = [(3e-3, 6e-3), (5e-3, 4.5e-3), (6e-3, 2e-3), (8.6e-3, 0.36e-3)]


def linear(a, b, nu=0.3):
    c11, c22, c23, _ = kalker_coefficients(a, b, nu)
    return G * a * b * c11, G * a * b * c22, G * (a * b) ** 1.5 * c23, (c11, c22, c23)


CREEPAGES = [(1e-7, 0, 0), (0, 1e-7, 0), (0, 0, 1e-5), (0, -2e-7, 3e-5), (1e-7, 0, 3e-5), (1e-7, -2e-7, 3e-5)]


@pytest.mark.parametrize("a, b", SHAPES)
@pytest.mark.parametrize("xi, eta, phi", CREEPAGES)
def test_fastsim_linear_limit_is_kalker(a, b, xi, eta, phi):
    f11, f22, f23, c = linear(a, b)
    fx, fy = fastsim(NORMAL, MU, a, b, G, *c, xi, eta, phi)
    assert fx == pytest.approx(-f11 * xi, rel=1e-5, abs=1e-9)
    assert fy == pytest.approx(-f22 * eta - f23 * phi, rel=1e-5, abs=1e-9)


@pytest.mark.parametrize("a, b", SHAPES)
@pytest.mark.parametrize("xi, eta, phi", CREEPAGES)
def test_polach_linear_limit(a, b, xi, eta, phi):
    """Kalker's f11, f22, f23 for one creepage at a time (spin added to either); for
    combined xi and eta Polach's single coefficient c = sqrt((C11 xi)^2 + (C22 eta)^2)/s
    acts along the creepage: F = G a b c (xi, eta)."""
    f11, f22, f23, c = linear(a, b)
    fx, fy = polach(NORMAL, MU, a, b, G, *c, xi, eta, phi)
    s = math.hypot(xi, eta)
    blended = G * a * b * math.hypot(c[0] * xi, c[1] * eta) / s if s else 0.0
    assert fx == pytest.approx(-blended * xi, rel=1e-5, abs=1e-9)
    assert fy == pytest.approx(-blended * eta - f23 * phi, rel=1e-5, abs=1e-9)
    if xi == 0 or eta == 0:
        assert fx == pytest.approx(-f11 * xi, rel=1e-5, abs=1e-9)
        assert fy == pytest.approx(-f22 * eta - f23 * phi, rel=1e-5, abs=1e-9)


@pytest.mark.parametrize("law", LAWS)
@pytest.mark.parametrize("direction", [(1, 0), (0, 1), (0.6, -0.8), (-1, 0)])
def test_full_slip_reaches_mu_n_and_never_more(law, direction):
    a, b = 5e-3, 4.5e-3
    *_, c = linear(a, b)
    sizes = np.geomspace(1e-5, 0.2, 40)
    totals = [math.hypot(*LAWS[law](NORMAL, MU, a, b, G, *c, s * direction[0], s * direction[1], 0.0)) for s in sizes]
    assert max(totals) <= MU * NORMAL * (1 + 1e-12)
    assert totals[-1] == pytest.approx(MU * NORMAL, rel=3e-6)  # at creepage 0.2: Polach 1.1e-6 below, FASTSIM exact
    assert np.all(np.diff(totals) >= -1e-9 * MU * NORMAL)  # rises monotonically to the limit


@pytest.mark.parametrize("law", LAWS)
def test_odd_in_the_creepages(law):
    *_, c = linear(5e-3, 4e-3)
    for creep in [(1e-3, 2e-3, 0.5), (-4e-3, 1e-3, -2.0), (0.02, -0.01, 3.0)]:
        plus = LAWS[law](NORMAL, MU, 5e-3, 4e-3, G, *c, *creep)
        minus = LAWS[law](NORMAL, MU, 5e-3, 4e-3, G, *c, *(-v for v in creep))
        assert minus == pytest.approx((-plus[0], -plus[1]), rel=1e-12, abs=1e-9)


def test_polach_closed_form_by_hand():
    # pure longitudinal creepage with e = 1: F = (2 mu N / pi)(1/2 + pi/4) = mu N (1/pi + 1/2)
    a, b = 5e-3, 4e-3
    c11 = kalker_coefficients(a, b, 0.3)[0]
    xi = 4 * MU * NORMAL / (math.pi * G * a * b * c11)
    fx, fy = polach(NORMAL, MU, a, b, G, c11, 1.0, 1.0, xi, 0.0, 0.0)
    assert fx == pytest.approx(-MU * NORMAL * (1 / math.pi + 0.5), rel=1e-12)
    assert fy == 0.0


def test_spin_factor_limits_and_a_point():
    # K_M = |e| (d^3/3 - d^2/2 + 1/6) - sqrt((1 - d^2)^3)/3, d = (e^2 - 1)/(e^2 + 1)
    def direct(e):
        d = (e * e - 1) / (e * e + 1)
        return e * (d**3 / 3 - d**2 / 2 + 1 / 6) - math.sqrt((1 - d * d) ** 3) / 3

    for e in (0.3, 1.0, 2.0):
        assert spin_reduction(e) == pytest.approx(direct(e), rel=1e-12)
    assert spin_reduction(1.0) == pytest.approx(-1 / 6, rel=1e-14)
    assert spin_reduction(1e-6) == pytest.approx(-2e-6 / 3, rel=1e-6)
    assert spin_reduction(1e3) == pytest.approx(-2 / (3 * 1e9), rel=1e-3)


def test_polach_spin_raises_the_resultant_creepage_only_when_it_adds():
    a, b = 5e-3, 4e-3
    *_, c = linear(a, b)
    # spin opposite to a large lateral creepage: eta_C = eta, the spin force alone is added
    fx, fy_both = polach(NORMAL, MU, a, b, G, *c, 0.0, 0.01, -0.5)
    _, fy_plain = polach(NORMAL, MU, a, b, G, *c, 0.0, 0.01, 0.0)
    assert fx == 0.0 and abs(fy_both) < abs(fy_plain) + 1e-9


def test_fastsim_grid_convergence():
    a, b = 8.6e-3, 0.36e-3  # the flange contact of S1002 on 60E1
    *_, c = linear(a, b, 0.28)
    creep = (-0.0183, -0.039, -1.94)
    reference = _fastsim(15e3, MU, a, b, G, *c, *creep, *_fastsim_grid(40, 40), *_fastsim_factors(40, 40))
    coarse = fastsim(15e3, MU, a, b, G, *c, *creep)
    # the simulation's coarse grid (FASTSIM_GRID) is within 3 % of mu N of a 40 x 40 grid
    assert np.abs(np.subtract(coarse, reference)).max() < 0.03 * MU * 15e3


def test_array_form():
    *_, c = linear(5e-3, 4e-3)
    fx, fy = polach_forces(NORMAL, MU, 5e-3, 4e-3, G, *c, np.array([1e-3, -1e-3]), 0.0, 0.0)
    assert fx.shape == (2,) and fx[0] == -fx[1] and np.all(fy == 0)
    assert polach(0.0, MU, 5e-3, 4e-3, G, *c, 1e-3, 0, 0) == (0.0, 0.0)
    assert fastsim(NORMAL, MU, 5e-3, 4e-3, G, *c, 0.0, 0.0, 0.0) == (0.0, 0.0)
