"""Kalker's linear creepage and spin coefficients of an elliptic contact (Table E.3).

This module owns Kalker's published table of ``C11, C22, C23, C33`` (Kalker 1990,
Table E.3) as literal data, its interpolation in the axis ratio and in Poisson's
ratio the way Vollebregt's CONTACT does it, Kalker's asymptotes below the table, and
the argument checks of the contact's elastic data. The dimensional coefficients are
:func:`express.rail.contact.creep_coefficients`.

References
----------
J. J. Kalker, *Three-dimensional elastic bodies in rolling contact*, Kluwer,
1990, Appendix E, Table E.3.
E. A. H. Vollebregt, CONTACT (open source, Apache-2.0), ``src/m_hertz.f90``,
subroutine ``linrol``.
"""

from __future__ import annotations

import math
from bisect import bisect_right

from express.base.diagnostics import ArgumentError

__all__ = ["kalker_coefficients", "require_poisson", "require_positive_finite"]

# ---------------------------------------------------------------------------
# Kalker's table
# ---------------------------------------------------------------------------

#: Abscissa of Kalker's table: the ratio g = (short semi-axis)/(long semi-axis),
#: i.e. g = a/b on the a <= b half of the table and g = b/a on the a >= b half.
_G_NODES: tuple[float, ...] = (0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0)

#: The three tabulated Poisson's ratios.
_POISSON_NODES: tuple[float, float, float] = (0.0, 0.25, 0.5)

#: Names of the four coefficients, in the order of the table's column groups.
_COEFFICIENTS: tuple[str, ...] = ("C11", "C22", "C23", "C33")

# Kalker, "Three-dimensional elastic bodies in rolling contact" (1990), Table E.3:
# creepage and spin coefficients of the linear theory for an elliptic contact
# area with semi-axes a (rolling direction) and b (lateral).  One row per g; each
# column group holds the values for nu = 0, 1/4, 1/2.
#
# C11, C22 and C23 were checked value by value against three independent
# transcriptions, which agree except for the typos noted here:
#   * CONTACT, src/m_hertz.f90, subroutine linrol (github.com/eve70a/CONTACT);
#     a copy of linrol in CONTACT's table-generation program, and a C++ port of
#     it, read C23(a/b = 0.8, nu = 1/4) = 1.15 -- the table value is 1.25;
#   * OpenRailVehicleDynamics, libs/wheel_rail_contact/src/
#     kalker_coefficient_table.cc (github.com/wenquantongxin/OpenRailVehicleDynamics);
#   * a Python/MATLAB wheel-rail model ("QUICKTANG"), which also lists the g -> 0
#     limits and reads C11(b/a = 0.4, nu = 1/2) = 5.57 -- the table value is 6.57.
# C33 is NOT cross-checked: CONTACT does not use it and none of the sources
# above lists it, and no other copy of Table E.3 could be consulted when this
# module was written.  The C33 columns were entered from the author's
# knowledge of Kalker's table and are checked only for internal consistency
# (monotone in a/b, within 6 % of Kalker's g -> 0 limit at a/b = 0.1).
# Verify them against Table E.3 before relying on f33.
#
#     g   C11 nu=0  1/4   1/2   C22 nu=0  1/4   1/2   C23 nu=0  1/4    1/2   C33 nu=0  1/4   1/2
_TABLE_E3_A_LE_B: tuple[tuple[float, ...], ...] = (  # g = a/b
    (0.1, 2.51, 3.31, 4.85, 2.51, 2.52, 2.53, 0.334, 0.473, 0.731, 6.42, 8.28, 11.7),
    (0.2, 2.59, 3.37, 4.81, 2.59, 2.63, 2.66, 0.483, 0.603, 0.809, 3.46, 4.27, 5.66),
    (0.3, 2.68, 3.44, 4.80, 2.68, 2.75, 2.81, 0.607, 0.715, 0.889, 2.49, 2.96, 3.72),
    (0.4, 2.78, 3.53, 4.82, 2.78, 2.88, 2.98, 0.720, 0.823, 0.977, 2.02, 2.32, 2.77),
    (0.5, 2.88, 3.62, 4.83, 2.88, 3.01, 3.14, 0.827, 0.929, 1.07, 1.74, 1.93, 2.22),
    (0.6, 2.98, 3.72, 4.91, 2.98, 3.14, 3.31, 0.930, 1.03, 1.18, 1.56, 1.68, 1.86),
    (0.7, 3.09, 3.81, 4.97, 3.09, 3.28, 3.48, 1.03, 1.14, 1.29, 1.43, 1.50, 1.60),
    (0.8, 3.19, 3.91, 5.05, 3.19, 3.41, 3.65, 1.13, 1.25, 1.40, 1.34, 1.37, 1.42),
    (0.9, 3.29, 4.01, 5.12, 3.29, 3.54, 3.82, 1.23, 1.36, 1.51, 1.27, 1.27, 1.27),
    (1.0, 3.40, 4.12, 5.20, 3.40, 3.67, 3.98, 1.33, 1.47, 1.63, 1.21, 1.19, 1.16),
)
_TABLE_E3_A_GE_B: tuple[tuple[float, ...], ...] = (  # g = b/a
    (0.1, 10.7, 11.7, 12.9, 10.7, 12.8, 16.0, 12.2, 14.6, 18.0, 0.795, 0.526, 0.228),
    (0.2, 6.96, 7.78, 8.82, 6.96, 8.14, 9.79, 5.72, 6.63, 7.89, 0.828, 0.601, 0.341),
    (0.3, 5.57, 6.34, 7.34, 5.57, 6.40, 7.51, 3.79, 4.32, 5.01, 0.868, 0.674, 0.446),
    (0.4, 4.84, 5.57, 6.57, 4.84, 5.48, 6.31, 2.88, 3.24, 3.70, 0.912, 0.747, 0.549),
    (0.5, 4.37, 5.10, 6.11, 4.37, 4.90, 5.56, 2.35, 2.62, 2.96, 0.958, 0.819, 0.650),
    (0.6, 4.06, 4.78, 5.80, 4.06, 4.50, 5.04, 2.01, 2.23, 2.50, 1.01, 0.892, 0.751),
    (0.7, 3.82, 4.54, 5.58, 3.82, 4.21, 4.67, 1.76, 1.95, 2.18, 1.05, 0.965, 0.852),
    (0.8, 3.65, 4.36, 5.42, 3.65, 3.99, 4.39, 1.58, 1.75, 1.94, 1.10, 1.04, 0.954),
    (0.9, 3.51, 4.22, 5.30, 3.51, 3.81, 4.16, 1.44, 1.59, 1.77, 1.16, 1.11, 1.06),
    (1.0, 3.40, 4.12, 5.20, 3.40, 3.67, 3.98, 1.33, 1.47, 1.63, 1.21, 1.19, 1.16),
)

# Columns per coefficient for nu = 0, 1/4, 1/2 (each a series over _G_NODES).
_Series = tuple[tuple[float, ...], tuple[float, ...], tuple[float, ...]]


def _columns(rows: tuple[tuple[float, ...], ...]) -> dict[str, _Series]:
    """Regroup table rows into ``{coefficient: (series nu=0, nu=1/4, nu=1/2)}``."""
    if tuple(row[0] for row in rows) != _G_NODES:
        raise AssertionError("Kalker table rows are not at the expected g nodes")
    table: dict[str, _Series] = {}
    for k, name in enumerate(_COEFFICIENTS):
        first = 1 + 3 * k
        nu0, nu1, nu2 = (tuple(row[first + j] for row in rows) for j in range(len(_POISSON_NODES)))
        table[name] = (nu0, nu1, nu2)
    return table


#: ``_KALKER[short_side][coefficient][poisson node][g node]``; ``short_side`` is
#: ``"a"`` when a <= b (g = a/b) and ``"b"`` when a > b (g = b/a).
_KALKER: dict[str, dict[str, _Series]] = {
    "a": _columns(_TABLE_E3_A_LE_B),
    "b": _columns(_TABLE_E3_A_GE_B),
}


def _interpolate_in_g(series: tuple[float, ...], g: float) -> float:
    """Piecewise-linear interpolation of one table column in g (0.1 <= g <= 1).

    Written as ``c_lo + t (c_hi - c_lo)`` so that a node (t = 0) returns the
    tabulated value exactly.
    """
    i = bisect_right(_G_NODES, g) - 1
    if i >= len(_G_NODES) - 1:
        return series[-1]
    g_lo, g_hi = _G_NODES[i], _G_NODES[i + 1]
    t = (g - g_lo) / (g_hi - g_lo)
    return series[i] + t * (series[i + 1] - series[i])


def _interpolate_in_poisson(c0: float, c1: float, c2: float, poisson: float) -> float:
    """CONTACT's interpolation in nu: the parabola through 1/C at nu = 0, 1/4, 1/2.

    At a tabulated nu the tabulated value is returned as is (CONTACT's formula
    would give ``1/(1/c)``, which can differ from ``c`` in the last bit).
    """
    if poisson in _POISSON_NODES:
        return (c0, c1, c2)[_POISSON_NODES.index(poisson)]
    w0 = 8.0 * (poisson - 0.25) * (poisson - 0.5)
    w1 = -16.0 * poisson * (poisson - 0.5)
    w2 = 8.0 * poisson * (poisson - 0.25)
    return 1.0 / (w0 / c0 + w1 / c1 + w2 / c2)


def _asymptotes_short_rolling_axis(g: float, poisson: float) -> tuple[float, float, float, float]:
    """Kalker's g -> 0 limits for a < b (ellipse narrow in the rolling direction), g = a/b.

    C11, C22, C23 as in CONTACT's ``linrol``; C33 = pi^2 / (16 (1 - nu) g) is the
    same strip-theory limit (each lateral strip rolls as a 2-D contact).
    """
    nu = poisson
    c11 = math.pi**2 / (4.0 * (1.0 - nu))
    c22 = math.pi**2 / 4.0
    c23 = math.pi * math.sqrt(g) / (3.0 * (1.0 - nu)) * (1.0 + nu * (math.log(16.0 / g) - 5.0))
    c33 = math.pi**2 / (16.0 * (1.0 - nu) * g)
    return c11, c22, c23, c33


def _asymptotes_long_rolling_axis(g: float, poisson: float) -> tuple[float, float, float, float]:
    """Kalker's g -> 0 limits for a > b (ellipse long in the rolling direction), g = b/a.

    C11, C22, C23 as in CONTACT's ``linrol``.  No C33 limit is implemented for
    this side (CONTACT has none), so C33 is returned as NaN.
    """
    nu = poisson
    lam = math.log(16.0 / g**2)
    shifted = lam - 2.0 * nu
    weighted = (1.0 - nu) * lam + 2.0 * nu
    c11 = 2.0 * math.pi / (shifted * g) * (1.0 + (3.0 - math.log(4.0)) / shifted)
    c22 = 2.0 * math.pi / (g * weighted) * (1.0 + (1.0 - nu) * (3.0 - math.log(4.0)) / weighted)
    c23 = 2.0 * math.pi / (3.0 * g**1.5 * ((1.0 - nu) * lam - 2.0 + 4.0 * nu))
    return c11, c22, c23, math.nan


def kalker_coefficients(a: float, b: float, poisson: float) -> tuple[float, float, float, float]:
    """Kalker's creepage and spin coefficients for an elliptic contact.

    Parameters
    ----------
    a : float
        Semi-axis of the contact ellipse in the rolling direction [m] (any
        length unit: only ``a/b`` matters).
    b : float
        Semi-axis of the contact ellipse across the rolling direction [m].
    poisson : float
        Poisson's ratio nu [-], ``0 <= nu <= 0.5`` (both bodies alike).

    Returns
    -------
    tuple of float
        ``(C11, C22, C23, C33)`` [-].  ``C33`` is NaN for ``a/b > 10`` (see
        Notes).

    Raises
    ------
    ArgumentError
        If ``a`` or ``b`` is not a positive finite number, or if ``poisson`` is
        outside ``[0, 0.5]``.

    Notes
    -----
    The values come from Kalker (1990), Table E.3, tabulated at
    g = 0.1, 0.2, ..., 1.0 on two halves, g = a/b for ``a <= b`` and g = b/a
    for ``a >= b``, and at nu = 0, 1/4, 1/2.  They are evaluated exactly as
    Vollebregt's CONTACT does in its subroutine ``linrol``:

    1. g = min(a/b, b/a) selects the half of the table; inside that half the
       table is interpolated *linearly in g*, i.e. in the table's own abscissa
       (b/a, not a/b, when the ellipse is longer in the rolling direction).
    2. The three values so obtained for nu = 0, 1/4, 1/2 are combined by the
       *quadratic through their reciprocals*:
       ``1/C = 8 (nu-1/4)(nu-1/2)/C(0) - 16 nu (nu-1/2)/C(1/4) + 8 nu (nu-1/4)/C(1/2)``.
       (Not linear in nu: 1/C11 is nearly linear in nu because C11 behaves
       like 1/(1-nu).)
    3. For g < 0.1 Kalker's asymptotic expressions for g -> 0 are used
       instead of the table, with L = ln(16/g^2).  For a < b:
       C11 = pi^2/(4(1-nu)), C22 = pi^2/4,
       C23 = pi sqrt(g)/(3(1-nu)) (1 + nu(L/2 + ln 4 - 5)),
       C33 = pi^2/(16(1-nu) g).  For a > b:
       C11 = 2 pi/((L-2nu) g) (1 + (3-ln 4)/(L-2nu)),
       C22 = 2 pi/(g W) (1 + (1-nu)(3-ln 4)/W) with W = (1-nu) L + 2 nu,
       C23 = 2 pi/(3 g^1.5 ((1-nu) L - 2 + 4 nu)), and C33 = NaN.

    Differences from CONTACT, all deliberate:

    * CONTACT switches to the asymptotes for g < 0.101; here the switch is at
      g < 0.1, so that the table nodes at g = 0.1 are reproduced exactly.  The
      jump between table and asymptote at the switch (up to about 5 %) exists
      in both.
    * CONTACT does not compute C33.  Here C33 is interpolated by the same
      rule as the other coefficients; below the table it uses the strip-theory
      limit above for a < b, and is NaN for a > b, where no asymptote is
      implemented.
    * Table values are returned bit-exactly at the nodes (CONTACT's formulas
      round them in the last bit).

    The C11, C22 and C23 columns were checked against three independent
    transcriptions of Table E.3; the C33 columns could not be (see the
    comment at the table in the source).

    A consequence of CONTACT's order of operations (linear in g for each
    tabulated nu, *then* the reciprocal parabola in nu): at a tabulated nu the
    result is piecewise linear in g and always lies between neighbouring
    nodes, but at other nu it need not.  Scanning the whole table, the
    excursion beyond the neighbours is at most about 1e-5 (relative) for C11,
    zero for C22 and C23, and 0.9 % for C33 (b/a between 0.1 and 0.2, nu near
    0.1).

    Examples
    --------
    A table node (a/b = 0.5 at nu = 1/4) and an ellipse 1.27 times longer
    than wide at nu = 0.3 (the 50 kN wheel of :func:`express.rail.contact.creep_coefficients`):

    >>> kalker_coefficients(0.5, 1.0, 0.25)
    (3.62, 3.01, 0.929, 1.93)
    >>> [round(c, 3) for c in kalker_coefficients(1.27, 1.0, 0.3)]
    [4.56, 4.094, 1.812, 1.014]
    """
    require_positive_finite("semi-axis a", a)
    require_positive_finite("semi-axis b", b)
    require_poisson(poisson)
    a, b, poisson = float(a), float(b), float(poisson)

    short_side = "a" if a <= b else "b"
    g = a / b if short_side == "a" else b / a
    if not g >= 1e-12:  # the asymptotes' powers and logarithms of g would underflow
        raise ArgumentError(f"semi-axes a = {a!r} m, b = {b!r} m: a degenerate contact ellipse (ratio below 1e-12)")

    if g < _G_NODES[0]:
        if short_side == "a":
            return _asymptotes_short_rolling_axis(g, poisson)
        return _asymptotes_long_rolling_axis(g, poisson)

    half = _KALKER[short_side]
    values = []
    for name in _COEFFICIENTS:
        c0, c1, c2 = (_interpolate_in_g(series, g) for series in half[name])
        values.append(_interpolate_in_poisson(c0, c1, c2, poisson))
    c11, c22, c23, c33 = values
    return c11, c22, c23, c33


# ---------------------------------------------------------------------------
# Argument checks
# ---------------------------------------------------------------------------


def require_positive_finite(name: str, value: float) -> None:
    """Raise unless ``0 < value < inf``.

    Parameters
    ----------
    name : str
        What the value is, for the message (``"load"``, ``"semi-axis a"``).
    value : float
        The value, in its own unit (N, m, Pa).

    Raises
    ------
    ArgumentError
        If ``value`` is not a positive finite number (NaN included).
    """
    if not 0.0 < value < math.inf:
        raise ArgumentError(f"{name} must be a positive finite number, got {value!r}")


def require_poisson(poisson: float) -> None:
    """Raise unless ``0 <= poisson <= 0.5`` (the range Kalker tabulated).

    Parameters
    ----------
    poisson : float
        Poisson's ratio nu [-].

    Raises
    ------
    ArgumentError
        If ``poisson`` lies outside ``[0, 0.5]`` (NaN included).
    """
    if not 0.0 <= poisson <= 0.5:
        raise ArgumentError(
            f"poisson must lie in [0, 0.5] (Kalker's table covers nu = 0, 0.25, 0.5), "
            f"got {poisson!r}"
        )
