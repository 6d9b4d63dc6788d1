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

The reader makes the beam a node of the parameter graph (:func:`free_free_beam`, the
derivation ``"free_free_beam"``): its length, stiffnesses, the body's mass and the
points' stations are its inputs, the modes' frequencies and shapes its outputs, so a
``--set`` of any of them (``CB_vertical_EI``, ``mc``, ``lT``), a study point and a
sensitivity recompute the modes.

Examples
--------
>>> [round(r, 9) for r in free_free_roots(2)]
[4.730040745, 7.853204624]
"""

from __future__ import annotations

import math

import numpy as np
from scipy.optimize import brentq

__all__ = [
    "BEAM_DERIVATION",
    "BEAM_NAMES",
    "bending_frequency",
    "bending_shape",
    "free_free_beam",
    "free_free_roots",
    "torsion_frequency",
    "torsion_shape",
]

#: The derivation kind of the beam (:func:`express.model.parameters.register_derivation`).
BEAM_DERIVATION = "free_free_beam"
#: Prefix of the beam's mode names by kind (``vb1``, ``lb1``, ``to1``).
BEAM_NAMES = {"vertical": "vb", "lateral": "lb", "torsion": "to"}
#: Prefix of the station arguments of :func:`free_free_beam` (``x_CB_T1L``).
STATION = "x_"


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


def free_free_beam(*, length: float, mass: float, vertical: str = "0", lateral: str = "0", torsion: str = "0",
                   vertical_EI: float | None = None, lateral_EI: float | None = None,
                   torsion_GJ: float | None = None, torsional_inertia: float | None = None,
                   **stations: float) -> dict[str, float]:
    """The beam's modes as a derivation of the parameter graph.

    Parameters
    ----------
    length : float
        ``L`` [m].
    mass : float
        The body's mass ``m`` [kg] (``mu = m / L``).
    vertical, lateral, torsion : str
        Numbers of modes kept of each kind (text settings of the node).
    vertical_EI, lateral_EI, torsion_GJ : float, optional
        [N m^2]; needed for a kind with modes.
    torsional_inertia : float, optional
        ``rho Ip`` [kg m]; needed with torsion modes.
    **stations : float
        ``x_<point>``: the point's offset ``lx`` [m] from the body centre.

    Returns
    -------
    dict of str to float
        ``<mode>_w`` [rad/s] and ``<mode>_<point>`` (the mass-normalised shape: 1/sqrt(kg)
        for bending, rad/(sqrt(kg) m) for torsion), modes named ``vb<n>``, ``lb<n>``, ``to<n>``.

    Raises
    ------
    ValueError
        A length, mass, stiffness or inertia that is not positive, a point beyond the ends.

    Examples
    --------
    >>> out = free_free_beam(length=24.0, mass=40000.0, vertical="1", vertical_EI=2e9, x_P=12.0)
    >>> round(out["vb1_w"] / (2 * math.pi), 4), round(out["vb1_P"] * math.sqrt(40000.0), 12)
    (6.772, 2.0)
    """
    if not (length > 0 and mass > 0):
        raise ValueError(f"the beam's length and the body's mass must be positive, got {length:g} m, {mass:g} kg")
    where = {}
    for key, x in stations.items():
        if not key.startswith(STATION):
            raise ValueError(f"unknown argument {key}")
        if abs(x) > length / 2 * (1 + 1e-9):
            raise ValueError(f"point {key[len(STATION):]} (lx = {x:g} m) lies beyond the beam's ends (L = {length:g} m)")
        where[key[len(STATION):]] = x / length + 0.5
    results: dict[str, float] = {}
    for kind, count_text, stiffness in (("vertical", vertical, vertical_EI), ("lateral", lateral, lateral_EI),
                                        ("torsion", torsion, torsion_GJ)):
        count = int(count_text)
        if count == 0:
            continue
        words = "torsion_GJ" if kind == "torsion" else f"{kind}_EI"
        if stiffness is None or not stiffness > 0:
            raise ValueError(f"{words} must be positive, got {stiffness if stiffness is not None else 'none'}")
        if kind == "torsion":
            if torsional_inertia is None or not torsional_inertia > 0:
                raise ValueError("torsional_inertia (rho*Ip per length) must be positive")
            scale = math.sqrt(2.0 / (torsional_inertia * length))
            for n in range(1, count + 1):
                results[f"to{n}_w"] = torsion_frequency(n, length, stiffness, torsional_inertia)
                for point, s in where.items():
                    results[f"to{n}_{point}"] = float(scale * torsion_shape(n, s))
            continue
        root_mass = math.sqrt(mass)
        for n, root in enumerate(free_free_roots(count), start=1):
            name = f"{BEAM_NAMES[kind]}{n}"
            results[f"{name}_w"] = bending_frequency(root, length, stiffness, mass / length)
            for point, s in where.items():
                results[f"{name}_{point}"] = float(bending_shape(root, s)) / root_mass
    return results


def _register() -> None:
    from express.model.parameters import register_derivation

    register_derivation(BEAM_DERIVATION, free_free_beam)


_register()
