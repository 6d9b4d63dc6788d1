"""The linear critical speed of Wickens' wheelset against its closed form.

The smallest rail vehicle of the tests (``tests/test_profile_contact.py``: a wheelset held
to the ground by lateral springs ``ky`` and longitudinal springs ``kx`` at ``+-d``) with
a constant conicity and given creep coefficients has the classic linear equations of
Wickens (1965; the paper's eqs. 8-11)::

    m y''   + (2 f22 / v) y'           + ky y - 2 f22 psi                    = 0
    I psi'' + (2 b^2 f11 / v) psi'     + (2 b f11 lambda / r0) y + kpsi psi  = 0,

with ``kpsi = 2 kx d^2``.  Their characteristic polynomial ``a4 s^4 + ... + a0`` is
written out here by hand, and the critical speed is where its Hurwitz determinant
``a3 a2 a1 - a1^2 a4 - a3^2 a0`` changes sign (scipy's brentq): an independent derivation
of what EXPRESS computes from the model file through the symbolic generator, the
wheel/rail terms and its eigenvalue search.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import brentq

from express.analysis.study.critical import CriticalOptions, fast_critical_speed
from express.io.toml_model import parse_toml_model
from express.numeric.statespace import vehicle_model
from test_profile_contact import WHEELSET

CONICITY, F11, F22 = 0.2, 9e6, 8e6
TEXT = WHEELSET.replace('f1 = "Gamma_e_f11"\nf2 = "Gamma_e_f22"', f"f1 = {F11:g}\nf2 = {F22:g}").replace(
    'conicity = { from = "profiles", wheel = "S1002", rail = "60E1", inclination = "1:40", gauge = "1435 mm", '
    'flange_back = "1360 mm", amplitude = "A" }', f"conicity = {CONICITY}")


@pytest.fixture(scope="module")
def wheelset():
    return vehicle_model(parse_toml_model(TEXT, "wheelset.toml"))


def wickens_matrices(values: dict, speed: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """M, C, K of Wickens' equations in the DOF order (y, psi)."""
    m, inertia, b, r0 = values["mw"], values["Iwz"], values["b"], values["r0"]
    k_psi = 2 * values["kx"] * values["d"] ** 2
    mass = np.diag([m, inertia])
    damping = np.diag([2 * F22 / speed, 2 * b**2 * F11 / speed])
    stiffness = np.array([[values["ky"], -2 * F22], [2 * b * F11 * CONICITY / r0, k_psi]])
    return mass, damping, stiffness


def hurwitz(values: dict, speed: float) -> float:
    """a3 a2 a1 - a1^2 a4 - a3^2 a0 of det(M s^2 + C s + K), positive while stable."""
    mass, damping, stiffness = wickens_matrices(values, speed)
    (m, i), (c1, c2) = np.diag(mass), np.diag(damping)
    k11, k12, k21, k22 = stiffness.ravel()
    a4 = m * i
    a3 = m * c2 + i * c1
    a2 = m * k22 + c1 * c2 + i * k11
    a1 = c1 * k22 + c2 * k11
    a0 = k11 * k22 - k12 * k21
    return a3 * a2 * a1 - a1**2 * a4 - a3**2 * a0


def test_the_generated_matrices_are_wickens(wheelset):
    values = wheelset.values
    order = [wheelset.dof_index("W1.y"), wheelset.dof_index("W1.rz")]
    for speed in (10.0, 40.0):
        mass, damping, stiffness = wickens_matrices(values, speed)
        assert np.allclose(wheelset.mass[np.ix_(order, order)], mass, rtol=1e-14, atol=0)
        assert np.allclose(wheelset.damping(speed)[np.ix_(order, order)], damping, rtol=1e-14, atol=0)
        assert np.allclose(wheelset.stiffness[np.ix_(order, order)], stiffness, rtol=1e-14, atol=0)


def test_critical_speed_is_the_closed_form(wheelset):
    values = wheelset.values
    closed_form = brentq(lambda v: hurwitz(values, v), 1.0, 400.0, xtol=1e-12, rtol=1e-14)  # 150.13 m/s
    # the crossing of the largest real part through the threshold (1e-12 1/s here; the
    # default 1e-6 1/s puts it 3.5e-8 higher): achieved 3.5e-14 relative
    ours = fast_critical_speed(wheelset, CriticalOptions(v_max=400.0, tolerance=0.0, threshold=1e-12)).crossing.speed
    assert ours == pytest.approx(closed_form, rel=1e-13)
    assert hurwitz(values, 0.9 * closed_form) > 0 > hurwitz(values, 1.1 * closed_form)
