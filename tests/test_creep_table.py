"""The creep law from tables of the exact theory (express.rail.creep_table).

It tends to Kalker's linear theory (f11, f22, f23 and the spin moment's f23, f33 of
express.rail.contact) for small creepages, keeps the half-space's symmetries, saturates at
mu N, and against CONTACT's exact results on 280 cases off the table's grid
(tests/data/contact_exact/validation.csv, six regimes) stays within the stated errors;
FASTSIM 3 x 5 and Polach are measured on the same cases (docs/validation.md)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from express.rail.contact_forces import LAWS, quasi_static_forces
from express.rail.creep_table import TABLE_GRID, TABLE_POISSON, tabulated, tabulated_forces, tabulated_with_moment
from express.rail.kalker import kalker_coefficients

G = 80e9
NORMAL = 50e3
MU = 0.3
SHAPES = [(3e-3, 6e-3), (5e-3, 4.5e-3), (6e-3, 2e-3), (8.6e-3, 0.36e-3)]
DATA = Path(__file__).parent / "data" / "contact_exact" / "validation.csv"


def _args(a, b, xi, eta, phi, nu=0.3):
    c11, c22, c23, _ = kalker_coefficients(a, b, nu)
    return (NORMAL, MU, a, b, G, c11, c22, c23, xi, eta, phi)


@pytest.mark.parametrize("a, b", SHAPES)
@pytest.mark.parametrize("xi, eta, phi", [(1e-8, 0, 0), (0, 1e-8, 0), (0, 0, 1e-6), (-1e-8, 2e-8, -3e-6),
                                          (1e-8, -1e-8, 4e-6)])
def test_linear_limit_is_kalker(a, b, xi, eta, phi):
    """Small creepages: Fx = -f11 xi, Fy = -f22 eta - f23 phi to 1e-5 relative to the
    linear force's size (the first interval is linear in F / |u|, and the normalisation
    by the C_ij makes the slopes the same at every a/b: exact also for the ellipse
    0.36 x 8.6 mm), and Mz = f23 eta - f33 phi
    (f_ij = G (ab)^k C_ij) to 5e-2 of the moment's size (achieved 3.9e-2, at a/b = 0.5):
    its slopes C23 / C22 and C33 / C23 vary with a/b (C33 as b / a for a short rolling
    axis) and are interpolated linearly between the table's ratios, 1.5 apart."""
    c11, c22, c23, c33 = kalker_coefficients(a, b, TABLE_POISSON)
    f11, f22 = G * a * b * c11, G * a * b * c22
    f23, f33 = G * (a * b) ** 1.5 * c23, G * (a * b) ** 2 * c33
    fx, fy, mz = tabulated_with_moment(*_args(a, b, xi, eta, phi))
    want = np.array([-f11 * xi, -f22 * eta - f23 * phi])
    scale = math.hypot(f11 * xi, math.hypot(f22 * eta, f23 * phi))
    assert np.abs(np.array([fx, fy]) - want).max() <= 1e-5 * scale
    moment = f23 * eta - f33 * phi
    if np.isfinite(c33):  # Kalker gives no C33 for slender ellipses long in the rolling direction
        assert abs(mz - moment) <= 5e-2 * math.hypot(f23 * eta, f33 * phi)


@pytest.mark.parametrize("a, b", SHAPES[:3])
@pytest.mark.parametrize("xi, eta, phi", [(1e-3, 2e-3, 1.5), (-4e-4, 1e-3, -3.0), (2e-3, -5e-3, 6.0)])
def test_symmetries_of_the_half_space(a, b, xi, eta, phi):
    """(xi, -eta, -phi) gives (Fx, -Fy, -Mz), (-xi, eta, phi) gives (-Fx, Fy, Mz), all
    negated all negated (exactly: the kernel folds the quadrants by them)."""
    base = np.array(tabulated_with_moment(*_args(a, b, xi, eta, phi)))
    mirrored = np.array(tabulated_with_moment(*_args(a, b, xi, -eta, -phi)))
    turned = np.array(tabulated_with_moment(*_args(a, b, -xi, eta, phi)))
    odd = np.array(tabulated_with_moment(*_args(a, b, -xi, -eta, -phi)))
    np.testing.assert_allclose(mirrored, base * [1, -1, -1], rtol=1e-14)
    np.testing.assert_allclose(turned, base * [-1, 1, 1], rtol=1e-14)
    np.testing.assert_allclose(odd, -base, rtol=1e-14)


@pytest.mark.parametrize("a, b", SHAPES[:3])
@pytest.mark.parametrize("direction", [0.0, 0.7, 1.9])
def test_full_slip_is_mu_n_against_the_creepage(a, b, direction):
    """Large translational creepage: the force is mu N opposite to the creepage (within
    1e-3 of mu N: the last interval ends on the full-slip limit), never above mu N."""
    xi, eta = 0.5 * math.cos(direction), 0.5 * math.sin(direction)
    fx, fy = tabulated(*_args(a, b, xi, eta, 0.0))
    assert math.hypot(fx, fy) <= MU * NORMAL * (1 + 1e-6)
    np.testing.assert_allclose([fx, fy], [-MU * NORMAL * math.cos(direction), -MU * NORMAL * math.sin(direction)],
                               atol=1e-3 * MU * NORMAL)


def test_two_returns_and_arrays_agree():
    """The two-return kernel and the array form are the three-return kernel's."""
    args = _args(5e-3, 4.5e-3, 1e-3, -2e-3, 2.5)
    assert tabulated(*args) == tabulated_with_moment(*args)[:2]
    fx, fy, mz = tabulated_forces(*args[:8], np.array([1e-3, 0.0]), -2e-3, 2.5)
    assert (fx[0], fy[0], mz[0]) == tabulated_with_moment(*args)
    assert tabulated(0.0, *args[1:]) == (0.0, 0.0)
    assert tabulated(*args[:8], 0.0, 0.0, 0.0) == (0.0, 0.0)
    assert len(TABLE_GRID) == 4


# ------------------------------------------------------------------ against CONTACT


def _validation():
    labels = np.loadtxt(DATA, delimiter=",", skiprows=1, usecols=0, dtype=str)
    return labels, np.loadtxt(DATA, delimiter=",", skiprows=1, usecols=range(1, 12))


def _errors(rows, law):
    """``|F - F_exact| / |F_exact|`` and ``/ (mu N)`` of the tangential force per case."""
    rel, of_limit = [], []
    for aa, bb, fn, mu, gg, cksi, ceta, cphi, fx, fy, _ in rows:
        a, b = aa * 1e-3, bb * 1e-3
        c11, c22, c23, _ = kalker_coefficients(a, b, 0.3)
        got = law(fn, mu, a, b, gg * 1e6, c11, c22, c23, cksi, ceta, cphi * 1e3)
        miss = math.hypot(got[0] - fx, got[1] - fy)
        rel.append(miss / math.hypot(fx, fy))
        of_limit.append(miss / (mu * fn))
    return np.array(rel), np.array(of_limit)


#: Asserted (median, 90th percentile, max) of the table's relative error per regime, near
#: the achieved ones written beside them.
TOLERANCES = {
    "linear": (0.020, 0.035, 0.070),  # achieved 1.5, 2.6, 5.5 % (CONTACT's mesh: 1-2 % above Kalker's C_ij)
    "partial": (0.022, 0.050, 0.080),  # achieved 1.7, 3.8, 6.4 %
    "full": (0.004, 0.022, 0.055),  # achieved 0.28, 1.6, 4.2 %
    "spin": (0.035, 0.095, 0.170),  # achieved 2.7, 7.4, 13 %
    "flange": (0.013, 0.065, 0.180),  # achieved 0.99, 5.1, 14 %
    "slender": (0.14, 0.32, 0.42),  # achieved 11, 25, 32 %: a/b 5...25, beyond issue 33's range
}
#: Asserted largest error of the table's force as a share of mu N, per regime (achieved
#: 0.48, 3.9, 4.1, 2.7, 4.8, 5.9 %).
OF_LIMIT = {"linear": 0.007, "partial": 0.05, "full": 0.055, "spin": 0.035, "flange": 0.062, "slender": 0.077}


@pytest.mark.parametrize("regime", list(TOLERANCES))
def test_table_against_contact(regime):
    """Against CONTACT (60 x 60 elements) on 50 cases per regime (30 slender) off the table's grid: the
    median, 90th percentile and largest relative error of the tangential force, and the
    largest as a share of mu N, within TOLERANCES and OF_LIMIT (about 1.3 times what is
    achieved; the goal of issue 33 is 3 %, 10 %, 25 %)."""
    labels, rows = _validation()
    rel, of_limit = _errors(rows[labels == regime], tabulated)
    median, p90, worst = TOLERANCES[regime]
    assert np.median(rel) < median
    assert np.percentile(rel, 90) < p90
    assert rel.max() < worst
    assert of_limit.max() < OF_LIMIT[regime]


def test_contact_data_covers_the_regimes():
    """280 cases, 50 per regime (30 slender flange roots, a/b 5...25), a/b over 0.2...5
    elsewhere, both signs of eta against spin in flange contact."""
    labels, rows = _validation()
    assert len(rows) == 280
    counts = {regime: int((labels == regime).sum()) for regime in TOLERANCES}
    assert counts == {**dict.fromkeys(TOLERANCES, 50), "slender": 30}
    slender = rows[labels == "slender"]
    assert (slender[:, 0] / slender[:, 1]).min() > 5.0 and (slender[:, 0] / slender[:, 1]).max() > 20.0
    ratio = rows[labels != "slender", 0] / rows[labels != "slender", 1]
    assert ratio.min() < 0.25 and ratio.max() > 4.0
    flange = rows[labels == "flange"]
    assert 10 < int((np.sign(flange[:, 6]) != np.sign(flange[:, 7])).sum()) < 40


def test_table_is_a_law_of_the_wheelset_forces():
    """The wheelset kernel takes "table": a centred S1002/60E1 wheelset nearly at rest
    (y = 0.1 mm, yaw 1e-5) has the same yaw moment and longitudinal force by the table,
    FASTSIM 3 x 5 and Polach to 12 % (achieved: table -392 N m, FASTSIM -359, Polach -419;
    the tread's spin, about 0.07 1/m, is as large as the translational creepages here,
    where the laws differ, docs/validation.md)."""
    assert LAWS["table"] == 2
    from express.rail.contact_forces import wheelset_contact
    from express.rail.contact_geometry import ContactSetup
    from express.rail.contact_tables import contact_tables
    from express.rail.profiles import standard_profile

    contact = wheelset_contact(contact_tables(standard_profile("S1002"), standard_profile("60E1"), ContactSetup()),
                               50e3, 0.3)
    table = quasi_static_forces(contact, 1e-4, 1e-5, speed=30.0, law="table")
    for law in ("fastsim", "polach"):
        other = quasi_static_forces(contact, 1e-4, 1e-5, speed=30.0, law=law)
        assert table["M"] == pytest.approx(other["M"], rel=0.12)
        assert table["Fx_left"] == pytest.approx(other["Fx_left"], rel=0.12)
