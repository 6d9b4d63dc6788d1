"""The closed forms of the equivalent linearisations of the nonlinear force elements
(issue 31, item 6): describing functions at a harmonic amplitude, and their Gaussian
(statistical) counterparts at an rms.

**The series spring–slider** (a friction element: pre-slip stiffness ``k``, friction
limit ``L``, slip deflection ``d = L/k``) under ``delta = X cos(w t)``: below ``X = d`` it
sticks, ``F = k delta``; above, its steady loop is the elastic–perfectly plastic
parallelogram, whose first harmonic is ``F1 = a delta + (b/w) delta'`` with::

    cos p = 1 - 2 d / X,   a = (k / pi) (p - sin(2 p) / 2),   b = (4 L / (pi X)) (1 - d / X)

(derived in ``docs/analyses.md``, "Linearisation of the nonlinear elements"; Caughey,
"Sinusoidal excitation of a system with bilinear hysteresis", J. Appl. Mech. 27 (1960)
640–643, for the bilinear loop whose second slope is zero).  ``pi b X**2 = 4 L (X - d)``
is the area of the loop, the energy of one cycle (tested against the march's return
mapping).

**Its statistical linearisation** (Caughey, "Random excitation of a system with bilinear
hysteresis", J. Appl. Mech. 27 (1960) 649–652): for a narrow-band Gaussian deflection of
rms ``s`` the amplitude is Rayleigh distributed, ``p(X) = X/s**2 exp(-X**2 / (2 s**2))``,
and the equivalent coefficients are the describing function's averaged over it,
``<a>(s)``, ``<b>(s)`` (integrated here by quadrature, exact below ``d``).

**A piecewise-linear characteristic** ``F(r)`` (breakpoints ``xs``, ``fs``; the end slopes
continued): its describing function at amplitude ``X`` about ``r = 0`` is exactly::

    a(X) = 2 / (pi X**2) integral_{-X}^{X} F'(r) sqrt(X**2 - r**2) dr
         = sum_i s_i 2 / (pi X**2) [G(r_(i+1)) - G(r_i)],   G(r) = (r sqrt(X**2 - r**2) + X**2 asin(r/X)) / 2

(by parts from ``a = 1/(pi X) integral F(X sin t) sin t dt``; ``s_i`` the slope of segment
``i``, its ends clipped to ``[-X, X]``), and its Gaussian linearisation at rms ``s`` is
``E[F'(r)] = sum_i s_i (Phi(r_(i+1)/s) - Phi(r_i/s))`` (Booton's, equal to ``E[r F(r)]/s**2``
for a zero-mean Gaussian ``r``).  A damper's characteristic (force against velocity) takes
the velocity's amplitude or rms.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["jenkin_describing", "jenkin_statistical", "table_describing", "table_statistical"]


def jenkin_describing(stiffness: float, limit: float, amplitude: float) -> tuple[float, float]:
    """``(a, b)`` of the series spring–slider at deflection amplitude ``amplitude``
    (module docstring): ``a`` [N/m] the in-phase part, ``b`` [N/m] the quadrature part
    (an equivalent viscous damping ``b / w`` at frequency ``w``).  Rotational elements the
    same in N m/rad and rad."""
    k, L, X = float(stiffness), float(limit), abs(float(amplitude))
    if L <= 0.0:  # no friction: the slider slips freely, the spring carries nothing
        return 0.0, 0.0
    d = L / k
    if d >= X:
        return k, 0.0
    p = math.acos(1.0 - 2.0 * d / X)
    return k / math.pi * (p - 0.5 * math.sin(2.0 * p)), 4.0 * L / (math.pi * X) * (1.0 - d / X)


def jenkin_statistical(stiffness: float, limit: float, rms: float) -> tuple[float, float]:
    """``(<a>, <b>)`` of the series spring–slider for a narrow-band Gaussian deflection
    of rms ``rms``: the describing function averaged over Rayleigh-distributed amplitudes
    (Caughey 1960; module docstring), [N/m]."""
    from scipy.integrate import quad

    k, L, s = float(stiffness), float(limit), abs(float(rms))
    if L <= 0.0:
        return 0.0, 0.0
    if s == 0.0:
        return k, 0.0
    d = L / k
    below = -math.expm1(-0.5 * (d / s) ** 2)  # P(X <= d): stuck, a = k, b = 0

    def weight(x: float) -> float:
        return x / s**2 * math.exp(-0.5 * (x / s) ** 2)

    upper = d + 40.0 * s
    a = quad(lambda x: jenkin_describing(k, L, x)[0] * weight(x), d, upper, limit=200, epsabs=0.0, epsrel=1e-11)[0]
    b = quad(lambda x: jenkin_describing(k, L, x)[1] * weight(x), d, upper, limit=200, epsabs=0.0, epsrel=1e-11)[0]
    return k * below + a, b


def _segments(xs: np.ndarray, fs: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The table's segments ``(lower, upper, slope)``, the end segments continued to
    infinity."""
    x, f = np.asarray(xs, dtype=float), np.asarray(fs, dtype=float)
    slopes = np.diff(f) / np.diff(x)
    lower, upper = x[:-1].copy(), x[1:].copy()
    lower[0], upper[-1] = -np.inf, np.inf
    return lower, upper, slopes


def table_describing(xs: np.ndarray, fs: np.ndarray, amplitude: float) -> float:
    """The describing function ``a(X)`` of the piecewise-linear characteristic
    (breakpoints ``xs``, ``fs``) about ``r = 0`` at amplitude ``amplitude`` > 0, exact
    (module docstring) [force per unit of ``r``]."""
    X = abs(float(amplitude))
    lower, upper, slopes = _segments(xs, fs)
    if X == 0.0:
        inside = (lower < 0.0) & (upper > 0.0)
        at = (lower == 0.0) | (upper == 0.0)
        return float(slopes[inside].sum() if inside.any() else slopes[at].mean())

    def g(r: np.ndarray) -> np.ndarray:
        c = np.clip(r, -X, X)
        return 0.5 * (c * np.sqrt(np.maximum(X * X - c * c, 0.0)) + X * X * np.arcsin(c / X))

    return float(np.sum(slopes * (g(upper) - g(lower))) * 2.0 / (math.pi * X * X))


def table_statistical(xs: np.ndarray, fs: np.ndarray, rms: float) -> float:
    """``E[F'(r)]`` of the piecewise-linear characteristic for a zero-mean Gaussian ``r``
    of rms ``rms`` (module docstring); the describing function's limit at ``rms = 0``."""
    from scipy.special import ndtr

    s = abs(float(rms))
    if s == 0.0:
        return table_describing(xs, fs, 0.0)
    lower, upper, slopes = _segments(xs, fs)
    return float(np.sum(slopes * (ndtr(upper / s) - ndtr(lower / s))))
