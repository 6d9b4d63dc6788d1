"""Wheel/rail creep coefficients from the Hertz ellipse and Kalker's linear theory.

This module owns the small-creepage ("linear") tangential contact law used by the
linear vehicle models:

1. :func:`hertz_contact` -- the Hertz contact ellipse (semi-axes ``a`` along the
   rolling direction and ``b`` across it) of a wheel pressed on a rail, from the
   principal radii of the two bodies, the normal load and the (common) elastic
   constants.
2. :func:`express.rail.kalker.kalker_coefficients` -- Kalker's dimensionless
   creepage and spin coefficients ``C11, C22, C23, C33`` for that ellipse, from
   Kalker's published table (Kalker 1990, Table E.3), interpolated the way
   Vollebregt's CONTACT does (the table and its interpolation live in
   :mod:`express.rail.kalker`).
3. :func:`creep_coefficients` -- the dimensional creep coefficients
   ``f11 = G a b C11``, ``f22 = G a b C22``, ``f23 = G (ab)^1.5 C23`` and
   ``f33 = G (ab)^2 C33`` that enter the linear equations of motion.

Everything is SI (N, m, Pa) and every function is pure.

Sign convention (Kalker): with longitudinal creepage ``xi``, lateral creepage
``eta`` and spin ``phi`` [1/m], the linear forces on the wheel are

    Fx = -f11 xi,    Fy = -f22 eta - f23 phi,    Mz = f23 eta - f33 phi.

References
----------
J. J. Kalker, *Three-dimensional elastic bodies in rolling contact*, Kluwer,
1990, Appendix E, Table E.3.
E. A. H. Vollebregt, CONTACT (open source, Apache-2.0), ``src/m_hertz.f90``,
subroutines ``hzcalc3d``, ``eli`` and ``linrol``.
K. L. Johnson, *Contact mechanics*, Cambridge University Press, 1985, sec. 3.7.
"""

from __future__ import annotations

import math
import sys
from dataclasses import astuple, dataclass

from scipy.optimize import brentq
from scipy.special import ellipe, ellipkm1

from express.base.diagnostics import ArgumentError
from express.rail.kalker import kalker_coefficients, require_poisson, require_positive_finite

__all__ = [
    "CreepCoefficients",
    "HertzContact",
    "creep_coefficients",
    "hertz_contact",
]


# ---------------------------------------------------------------------------
# Hertz ellipse
# ---------------------------------------------------------------------------


@dataclass(frozen=True)
class HertzContact:
    """Hertz contact ellipse of a wheel on a rail.

    Attributes
    ----------
    a : float
        Semi-axis in the rolling direction x [m].
    b : float
        Semi-axis across the rolling direction (lateral, y) [m].
    A : float
        Relative curvature in the rolling direction [1/m]: the undeformed gap
        between the bodies is ``h = A x^2 + B y^2``.
    B : float
        Relative curvature in the lateral direction [1/m].
    load : float
        Normal load N [N].
    """

    a: float
    b: float
    A: float
    B: float
    load: float

    @property
    def semi_axis_ratio(self) -> float:
        """``a/b`` [-]; greater than 1 when the patch is longer along the rail."""
        return self.a / self.b

    @property
    def area(self) -> float:
        """Contact area ``pi a b`` [m^2]."""
        return math.pi * self.a * self.b

    @property
    def max_pressure(self) -> float:
        """Peak Hertz pressure ``p0 = 3 N / (2 pi a b)`` [Pa]."""
        return 1.5 * self.load / self.area


def _curvature_ratio(g: float) -> float:
    """min(A, B)/max(A, B) of the Hertz ellipse with axis ratio g = minor/major.

    With e^2 = 1 - g^2 the eccentricity and K, E the complete elliptic integrals
    of modulus e, Hertz's relation reads
    ``min(A,B)/max(A,B) = (K - E) / (E/g^2 - K) = g^2 (K - E) / (E - g^2 K)``.
    ``ellipkm1(p) = ellipk(1 - p)`` keeps full precision for slender ellipses.
    For nearly circular ellipses K - E cancels: when |A/B - 1| < 1e-6 the axis
    ratio found from this function is good to about 1e-9 (immaterial next to
    the 3-digit Kalker table).
    """
    if g == 1.0:
        return 1.0
    p = g * g
    big_k = float(ellipkm1(p))
    big_e = float(ellipe(1.0 - p))
    return p * (big_k - big_e) / (big_e - p * big_k)


#: Most slender ellipse the solver will look for (minor/major semi-axis).
_SMALLEST_AXIS_RATIO = 1e-9


def _axis_ratio_from_curvatures(curvature_ratio: float) -> float:
    """Solve Hertz's relation for g = minor/major semi-axis, given min(A,B)/max(A,B)."""
    if curvature_ratio == 1.0:
        return 1.0
    lowest = _curvature_ratio(_SMALLEST_AXIS_RATIO)
    if curvature_ratio <= lowest:
        raise ArgumentError(
            f"curvature ratio min(A,B)/max(A,B) = {curvature_ratio:.3g} is too small: "
            f"the contact ellipse would be more slender than b/a = {_SMALLEST_AXIS_RATIO:g}"
        )
    return brentq(
        lambda g: _curvature_ratio(g) - curvature_ratio,
        _SMALLEST_AXIS_RATIO,
        1.0,
        xtol=1e-15,
        rtol=4.0 * sys.float_info.epsilon,
    )


def hertz_contact(
    load: float,
    wheel_radius: float,
    rail_head_radius: float,
    youngs_modulus: float = 206e9,
    poisson: float = 0.3,
    wheel_transverse_radius: float = math.inf,
    rail_longitudinal_radius: float = math.inf,
) -> HertzContact:
    """Hertz contact ellipse of a wheel on a rail (both convex, same material).

    Parameters
    ----------
    load : float
        Normal load N [N], positive.
    wheel_radius : float
        Wheel rolling radius, i.e. the wheel's radius of curvature in the
        rolling direction x [m], positive.
    rail_head_radius : float
        Transverse radius of the rail head, its radius of curvature in the
        lateral direction y [m], positive (``math.inf`` for a flat head).
    youngs_modulus : float, optional
        Young's modulus E of wheel and rail [Pa].  Default 206e9 (steel).
    poisson : float, optional
        Poisson's ratio nu of wheel and rail [-], in ``[0, 0.5]``.  Default 0.3.
    wheel_transverse_radius : float, optional
        Radius of the wheel tread profile in the lateral direction [m],
        positive; default ``math.inf`` (conical tread).
    rail_longitudinal_radius : float, optional
        Radius of the rail in the rolling direction [m], positive; default
        ``math.inf`` (straight rail; a finite value models e.g. a roller rig).

    Returns
    -------
    HertzContact
        Semi-axes ``a`` (rolling direction) and ``b`` (lateral) [m], the
        relative curvatures ``A`` and ``B`` [1/m] and the load [N].

    Raises
    ------
    ArgumentError
        If the load, a radius or Young's modulus is not positive, if nu is
        outside ``[0, 0.5]``, or if a relative curvature vanishes (line
        contact, which has no Hertz ellipse).

    Notes
    -----
    The undeformed gap is ``h = A x^2 + B y^2`` with

        A = (1/wheel_radius + 1/rail_longitudinal_radius) / 2,
        B = (1/wheel_transverse_radius + 1/rail_head_radius) / 2.

    The ellipse is longer in the direction of the smaller relative curvature.
    Its axis ratio g = minor/major solves Hertz's relation
    ``min(A,B)/max(A,B) = (K(e) - E(e)) / (E(e)/g^2 - K(e))``, e^2 = 1 - g^2,
    with the complete elliptic integrals K, E from ``scipy.special``
    (root found with ``scipy.optimize.brentq``).  Then, with the contact
    modulus ``E* = E / (2 (1 - nu^2))`` of two identical bodies and
    ``rho = 2 / (A + B)``,

        c^3 = (ab)^(3/2) = 3 N rho E(e) / (4 pi E* sqrt(g)),

    minor semi-axis ``c sqrt(g)``, major semi-axis ``c / sqrt(g)``.  This is
    the formulation used by Kalker (1990) and coded in CONTACT's ``hzcalc3d``;
    it is equivalent to the elliptic-contact relations of Johnson (1985),
    sec. 3.7, which the tests use as an independent check.

    Examples
    --------
    A 50 kN wheel load, 0.43 m rolling radius, 0.30 m rail head radius, steel:

    >>> c = hertz_contact(50e3, 0.43, 0.30)
    >>> round(c.a * 1e3, 3), round(c.b * 1e3, 3)   # mm
    (5.535, 4.355)
    >>> round(c.max_pressure / 1e6)                 # MPa
    990
    """
    require_positive_finite("load", load)
    _require_positive("wheel_radius", wheel_radius)
    _require_positive("rail_head_radius", rail_head_radius)
    _require_positive("wheel_transverse_radius", wheel_transverse_radius)
    _require_positive("rail_longitudinal_radius", rail_longitudinal_radius)
    require_positive_finite("youngs_modulus", youngs_modulus)
    require_poisson(poisson)
    load, youngs_modulus, poisson = float(load), float(youngs_modulus), float(poisson)

    curv_a = 0.5 * (1.0 / wheel_radius + 1.0 / rail_longitudinal_radius)
    curv_b = 0.5 * (1.0 / wheel_transverse_radius + 1.0 / rail_head_radius)
    if curv_a == 0.0:
        raise ArgumentError(
            "relative curvature A in the rolling direction is zero (wheel_radius and "
            "rail_longitudinal_radius both infinite): line contact, not a Hertz ellipse"
        )
    if curv_b == 0.0:
        raise ArgumentError(
            "relative curvature B in the lateral direction is zero (wheel_transverse_radius "
            "and rail_head_radius both infinite): line contact, not a Hertz ellipse"
        )

    g = _axis_ratio_from_curvatures(min(curv_a, curv_b) / max(curv_a, curv_b))
    big_e = float(ellipe(1.0 - g * g))
    e_star = youngs_modulus / (2.0 * (1.0 - poisson**2))
    rho = 2.0 / (curv_a + curv_b)
    denominator = 4.0 * math.pi * e_star * math.sqrt(g)
    c = (3.0 * load * rho * big_e / denominator) ** (1.0 / 3.0) if denominator > 0.0 else math.inf
    minor, major = c * math.sqrt(g), c / math.sqrt(g)
    if not (minor > 0.0 and major < math.inf):  # values at the ends of the double range
        raise ArgumentError(
            f"the contact data (load {load!r} N, E {youngs_modulus!r} Pa) give no finite contact ellipse"
        )

    # The ellipse is long where the gap opens slowly (small curvature).
    a, b = (minor, major) if curv_a >= curv_b else (major, minor)
    return HertzContact(a=a, b=b, A=float(curv_a), B=float(curv_b), load=load)


# ---------------------------------------------------------------------------
# Creep coefficients
# ---------------------------------------------------------------------------


@dataclass(frozen=True)
class CreepCoefficients:
    """Kalker's linear creep coefficients of one wheel/rail contact.

    Attributes
    ----------
    f11 : float
        Longitudinal creep coefficient ``G a b C11`` [N].
    f22 : float
        Lateral creep coefficient ``G a b C22`` [N].
    f23 : float
        Lateral/spin creep coefficient ``G (ab)^1.5 C23`` [N m].
    f33 : float
        Spin creep coefficient ``G (ab)^2 C33`` [N m^2] (NaN when ``a/b > 10``;
        C33 is the one column of Kalker's table not cross-checked, see
        :func:`express.rail.kalker.kalker_coefficients`).
    """

    f11: float
    f22: float
    f23: float
    f33: float


def creep_coefficients(
    load: float,
    wheel_radius: float,
    rail_head_radius: float,
    youngs_modulus: float = 206e9,
    poisson: float = 0.3,
    *,
    wheel_transverse_radius: float = math.inf,
    rail_longitudinal_radius: float = math.inf,
) -> CreepCoefficients:
    """Kalker's linear creep coefficients of a wheel on a rail.

    Parameters
    ----------
    load : float
        Normal load N [N].
    wheel_radius : float
        Wheel rolling radius [m].
    rail_head_radius : float
        Transverse radius of the rail head [m].
    youngs_modulus : float, optional
        Young's modulus E of wheel and rail [Pa].  Default 206e9.
    poisson : float, optional
        Poisson's ratio nu [-], in ``[0, 0.5]``.  Default 0.3.
    wheel_transverse_radius : float, optional
        Lateral radius of the wheel tread [m]; default ``math.inf`` (conical).
    rail_longitudinal_radius : float, optional
        Radius of the rail in the rolling direction [m]; default ``math.inf``.

    Returns
    -------
    CreepCoefficients
        ``f11``, ``f22`` [N], ``f23`` [N m], ``f33`` [N m^2].

    Raises
    ------
    ArgumentError
        As :func:`hertz_contact`.

    Notes
    -----
    With the Hertz semi-axes a, b of :func:`hertz_contact`, Kalker's
    coefficients of :func:`express.rail.kalker.kalker_coefficients` and the shear modulus
    ``G = E / (2 (1 + nu))``:

        f11 = G a b C11,  f22 = G a b C22,
        f23 = G (ab)^1.5 C23,  f33 = G (ab)^2 C33.

    Examples
    --------
    The 50 kN reference case: r = 0.43 m wheel on a 0.30 m rail head, steel
    (E = 206 GPa, nu = 0.3).  The patch is longer along the rail (a/b = 1.27):

    >>> f = creep_coefficients(50e3, 0.43, 0.30)
    >>> round(f.f11 / 1e6, 2), round(f.f22 / 1e6, 2)   # MN
    (8.71, 7.82)
    >>> round(f.f23), round(f.f33, 1)                   # N m, N m^2
    (17008, 46.7)
    """
    contact = hertz_contact(
        load,
        wheel_radius,
        rail_head_radius,
        youngs_modulus,
        poisson,
        wheel_transverse_radius=wheel_transverse_radius,
        rail_longitudinal_radius=rail_longitudinal_radius,
    )
    c11, c22, c23, c33 = kalker_coefficients(contact.a, contact.b, poisson)
    shear_modulus = youngs_modulus / (2.0 * (1.0 + poisson))
    ab = contact.a * contact.b
    root = math.sqrt(ab)
    coefficients = CreepCoefficients(  # products, not float powers: an overflow gives inf, not an exception
        f11=shear_modulus * ab * c11,
        f22=shear_modulus * ab * c22,
        f23=shear_modulus * ab * root * c23,
        f33=shear_modulus * ab * ab * c33,
    )
    if any(math.isinf(value) for value in astuple(coefficients)):  # NaN: no C33 for a long axis
        raise ArgumentError(
            f"the contact data (load {load!r} N, radii {wheel_radius!r} and {rail_head_radius!r} m, "
            f"E {youngs_modulus!r} Pa) give creep coefficients beyond the range of a double"
        )
    return coefficients


# ---------------------------------------------------------------------------
# Argument checks
# ---------------------------------------------------------------------------


def _require_positive(name: str, value: float) -> None:
    """Raise unless ``value > 0`` (``math.inf`` allowed, NaN rejected)."""
    if not value > 0.0:
        raise ArgumentError(f"{name} must be positive, got {value!r}")
