"""Closed-form free-free modes of a uniform beam: a car body as a flexible body.

A car body of length ``L`` and mass ``m`` (mass per length ``mu = m / L``) is an
Euler-Bernoulli beam in vertical and lateral bending and a Saint-Venant shaft in torsion,
free at both ends.  Measured from the rear end, ``0 <= s <= L``:

* **bending** (stiffness ``EI``): ``cos(bL) cosh(bL) = 1`` gives ``beta_n L`` =
  4.730040745, 7.853204624, 10.99560784, ... (:func:`free_free_roots`); the frequency
  is ``omega_n = (beta_n L)**2 / L**2 * sqrt(EI / mu)`` and the shape
  ``W(s) = cos bs + cosh bs - sigma (sin bs + sinh bs)`` with
  ``sigma = (cosh bL - cos bL) / (sinh bL - sin bL)``, whose ``integral W**2 ds = L``,
  so the mass-normalised shape is ``W / sqrt(m)`` [1/sqrt(kg)] (value ``2 / sqrt(m)``
  at both ends, nodes of the first mode at ``s / L = 0.2242`` and ``0.7758``);
* **torsion** (stiffness ``GJ``, torsional mass moment per length ``rho Ip`` [kg m]):
  ``omega_n = n pi / L * sqrt(GJ / rho Ip)``, shape ``cos(n pi s / L)``, mass-normalised
  ``sqrt(2 / (rho Ip L)) cos(n pi s / L)`` [rad/(sqrt(kg) m)].

Left out: shear deformation and rotary inertia (Timoshenko; they lower a car body's
first bending frequency by a few per cent when ``L`` is 10 or more section depths, more
for higher modes), warping of the section, non-uniform mass and stiffness, and the
bending-torsion coupling of a section whose shear centre is not its centroid.

Examples
--------
>>> [round(r, 9) for r in free_free_roots(2)]
[4.730040745, 7.853204624]
"""

from __future__ import annotations

import math

import numpy as np
from scipy.optimize import brentq

__all__ = ["bending_frequency", "bending_shape", "free_free_roots", "torsion_frequency", "torsion_shape"]


def _characteristic(x: float) -> float:
    """``cos x - 1 / cosh x``: zero where ``cos x cosh x = 1`` (well scaled for large x)."""
    return math.cos(x) - 1.0 / math.cosh(x)


def free_free_roots(count: int) -> list[float]:
    """The first ``count`` non-zero roots ``beta_n L`` of ``cos x cosh x = 1``.

    Each lies within ``(n + 1/2) pi +- pi/4`` and is found by bracketing (Brent) to
    machine precision.
    """
    roots = []
    for n in range(1, count + 1):
        centre = (n + 0.5) * math.pi
        roots.append(brentq(_characteristic, centre - math.pi / 4, centre + math.pi / 4, xtol=1e-15, rtol=1e-15))
    return roots


def bending_shape(root: float, s_over_l: np.ndarray | float) -> np.ndarray:
    """The free-free bending shape ``W`` at ``s / L`` (unit mean square, ``W(0) = 2``).

    Written as ``cos x - sigma sin x + ((1 - sigma) e^x + (1 + sigma) e^-x) / 2`` with
    ``1 - sigma`` formed without cancellation, so higher modes keep their digits.

    Parameters
    ----------
    root : float
        ``beta_n L`` (:func:`free_free_roots`).
    s_over_l : float or numpy.ndarray
        Position from the rear end over the length [-].
    """
    a = root
    denominator = math.sinh(a) - math.sin(a)
    sigma = (math.cosh(a) - math.cos(a)) / denominator
    one_minus_sigma = (math.cos(a) - math.sin(a) - math.exp(-a)) / denominator
    x = a * np.asarray(s_over_l, dtype=float)
    return np.cos(x) - sigma * np.sin(x) + 0.5 * (one_minus_sigma * np.exp(x) + (1.0 + sigma) * np.exp(-x))


def bending_frequency(root: float, length: float, stiffness: float, mass_per_length: float) -> float:
    """``omega_n = (beta_n L)**2 / L**2 * sqrt(EI / mu)`` [rad/s] (``EI`` [N m^2], ``mu`` [kg/m])."""
    return root**2 / length**2 * math.sqrt(stiffness / mass_per_length)


def torsion_frequency(n: int, length: float, stiffness: float, inertia_per_length: float) -> float:
    """``omega_n = n pi / L * sqrt(GJ / rho Ip)`` [rad/s] (``GJ`` [N m^2], ``rho Ip`` [kg m])."""
    return n * math.pi / length * math.sqrt(stiffness / inertia_per_length)


def torsion_shape(n: int, s_over_l: np.ndarray | float) -> np.ndarray:
    """The free-free torsion shape ``cos(n pi s / L)`` (mean square 1/2)."""
    return np.cos(n * math.pi * np.asarray(s_over_l, dtype=float))
