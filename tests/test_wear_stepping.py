"""The steps of a wear prediction (``express.analysis.wear.stepping``) against the closed
form of a rate linear in the depth, ``d(z) = a + b z``: ``z(D) = a/b (exp(b D) - 1)``."""

from __future__ import annotations

import math

import numpy as np
import pytest

from express.analysis.wear.cases import ProfileGrid
from express.analysis.wear.stepping import MAX_EVALUATIONS, euler_step, heun_step

A = np.array([1e-9, 2e-9, 0.5e-9])  # [m/m] at the new profile, per node
B = 1e-3  # [1/m]: b L = 0.1 .. 1 over the lengths below


def rate(grid: ProfileGrid, trial: int = 0) -> np.ndarray:
    return A + B * grid.z


def exact(length: float) -> np.ndarray:
    return A / B * np.expm1(B * length)


NEW = ProfileGrid(0.0, 1e-4, np.zeros(3))


@pytest.mark.parametrize("length", [100.0, 300.0, 1000.0])
def test_heun_is_second_order_and_its_estimate_is_eulers_error(length):
    """One Heun step over L = x / b (x = 0.1 .. 1): its error is exactly
    a/b (exp(x) - 1 - x - x^2/2), a b^2 L^3 / 6 to leading order (asserted to 1e-9 of it:
    the closed form's cancellation at x = 0.1 costs 3 digits), and its estimate
    L/2 max|d(z*) - d(z)| = a b L^2 / 2 (to rounding, asserted 1e-12), within 6 % of
    Euler's true error at x = 0.1 (achieved 3.4 %: the estimate is its leading term)."""
    step = heun_step(rate, NEW, rate(NEW), length, None, bound=1.0, tolerance=1.0)
    assert step.length == length and step.evaluations == 2
    error = exact(length) - step.change
    x = B * length
    assert np.allclose(error, A / B * (np.expm1(x) - x - x**2 / 2), rtol=1e-9, atol=0)
    assert np.all(error > 0) and np.allclose(error, A * B**2 * length**3 / 6, rtol=x)
    assert step.error == pytest.approx(float(np.max(A)) * B * length**2 / 2, rel=1e-12)
    euler = euler_step(rate(NEW), length, bound=1.0)
    assert euler.change == pytest.approx(A * length, rel=1e-15)
    if B * length <= 0.1:
        assert step.error == pytest.approx(float(np.max(exact(length) - euler.change)), rel=0.06)


def test_heun_shrinks_to_the_tolerance_and_the_bound():
    """A step asked for 5 km with a tolerance of 1e-8 m shrinks until its estimate is within
    it (or MAX_EVALUATIONS), and proposes at most twice its length; with a bound smaller
    than the change, the change is cut to the bound."""
    step = heun_step(rate, NEW, rate(NEW), 5000.0, None, bound=1.0, tolerance=1e-8)
    assert step.error <= 1e-8 and step.evaluations <= MAX_EVALUATIONS and step.length < 5000.0
    assert step.proposal == pytest.approx(step.length * min(2.0, 0.9 * math.sqrt(1e-8 / step.error)), rel=1e-15)
    expected = math.sqrt(2 * 1e-8 / (float(np.max(A)) * B))  # error = a b L^2 / 2
    assert step.length <= expected
    capped = heun_step(rate, NEW, rate(NEW), 5000.0, None, bound=2e-6, tolerance=1.0)
    assert float(capped.change.max()) <= 2e-6 * (1 + 1e-9)


def test_euler_takes_the_bound():
    step = euler_step(rate(NEW), 1e9, bound=1e-4)
    assert float(step.change.max()) == pytest.approx(1e-4, rel=1e-15) and step.length == pytest.approx(1e-4 / 2e-9)
    assert math.isnan(step.error) and step.proposal is None
