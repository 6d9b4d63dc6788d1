"""Kalker's creep coefficients as shipped code: the MATLAB/Octave and Python functions.

An exported model whose creep coefficients are derived (``[rail.creep]``) computes them
itself, so that changing a mass in the export moves the wheel load and with it f1 and
f2.  This module owns the source of that function in both languages:
:func:`matlab_kalker` (local functions of the exported ``.m`` file) and
:func:`python_kalker` (module-level code of the exported ``.py`` module).

The method is that of :func:`express.rail.contact.creep_coefficients`, for a conical
tread on a straight rail:

1. Hertz: relative curvatures ``A = 1/(2 wheel_radius)``, ``B = 1/(2 rail_head_radius)``;
   the axis ratio g = minor/major semi-axis solves
   ``min(A,B)/max(A,B) = g^2 (K - E)/(E - g^2 K)`` (K, E complete elliptic integrals of
   parameter ``m = 1 - g^2``, here by the arithmetic-geometric mean; the root by
   bisection to the last bit, on ``[1e-9, 1]``); then
   ``c^3 = 3 N rho E / (4 pi E* sqrt(g))``, ``E* = E_mod/(2 (1 - nu^2))``,
   ``rho = 2/(A + B)``, semi-axes ``c sqrt(g)`` and ``c/sqrt(g)``, the longer one along
   the direction of the smaller curvature.
2. Kalker (1990) Table E.3, C11 and C22, emitted as literal arrays: linear in g
   (g = a/b or b/a, the table's abscissa) for nu = 0, 1/4, 1/2, then the parabola
   through 1/C in nu; Kalker's asymptotes below g = 0.1.
3. ``f11 = G a b C11``, ``f22 = G a b C22``, ``G = E_mod/(2 (1 + nu))``.

The table values are read from :func:`express.rail.kalker.kalker_coefficients` at the
table's nodes, where it returns them exactly, so there is one copy of the table in
the source.
"""

from __future__ import annotations

__all__ = ["G_NODES", "KALKER_MATLAB_FUNCTIONS", "KALKER_PYTHON_NAMES", "kalker_table",
           "matlab_kalker", "python_kalker"]

#: Abscissa of Kalker's table (g = short/long semi-axis) and its Poisson's ratios.
G_NODES = tuple(k / 10 for k in range(1, 11))
NU_NODES = (0.0, 0.25, 0.5)

#: Names of the local functions of a MATLAB export (reserved for its variables).
KALKER_MATLAB_FUNCTIONS = ("kalker_creep", "kalker_elliptic")
#: Module-level names of a Python export's Kalker code (reserved for its variables).
KALKER_PYTHON_NAMES = ("kalker_creep", "_kalker_elliptic", "_kalker_c11_c22", "_kalker_interpolate",
                       "_KALKER_G", "_KALKER_A_LE_B", "_KALKER_A_GT_B")


def kalker_table() -> dict[str, tuple[tuple[float, ...], ...]]:
    """Kalker's C11 and C22 at the table's nodes, from :mod:`express.rail.contact`.

    Returns
    -------
    dict
        ``"a_le_b"`` (g = a/b) and ``"a_gt_b"`` (g = b/a): one row per g of
        :data:`G_NODES`, columns C11 at nu = 0, 1/4, 1/2, then C22 at the same nu.
    """
    from express.rail.kalker import kalker_coefficients

    def row(a: float, b: float) -> tuple[float, ...]:
        c11 = [kalker_coefficients(a, b, nu)[0] for nu in NU_NODES]
        c22 = [kalker_coefficients(a, b, nu)[1] for nu in NU_NODES]
        return (*c11, *c22)

    return {
        "a_le_b": tuple(row(g, 1.0) for g in G_NODES),
        "a_gt_b": tuple(row(1.0, g) for g in G_NODES),
    }


def _matlab_rows(rows: tuple[tuple[float, ...], ...]) -> str:
    return ("; ...\n" + " " * 8).join(" ".join(repr(x) for x in row) for row in rows)


_MATLAB = """
function [f11, f22] = kalker_creep(wheel_load, wheel_radius, rail_head_radius, youngs_modulus, poisson)
%KALKER_CREEP  Kalker's creep coefficients f11, f22 [N] of a wheel on a rail.
%   Hertz ellipse of a wheel (rolling radius wheel_radius [m], conical tread) on a
%   rail head (transverse radius rail_head_radius [m]) under wheel_load [N], steel
%   of youngs_modulus [Pa] and poisson [-]; Kalker (1990) Table E.3 for C11, C22;
%   f = G a b C with G = E/(2 (1 + nu)). As express.rail.contact.creep_coefficients.
if ~(wheel_load > 0 && wheel_load < Inf)
    error('kalker_creep: wheel_load must be a positive finite number, got %g', wheel_load);
end
if ~(wheel_radius > 0) || ~(rail_head_radius > 0)
    error('kalker_creep: wheel_radius and rail_head_radius must be positive, got %g and %g', ...
          wheel_radius, rail_head_radius);
end
if ~(youngs_modulus > 0 && youngs_modulus < Inf)
    error('kalker_creep: youngs_modulus must be a positive finite number, got %g', youngs_modulus);
end
if ~(poisson >= 0 && poisson <= 0.5)
    error('kalker_creep: poisson must lie in [0, 0.5], got %g', poisson);
end
curv_a = 0.5/wheel_radius;
curv_b = 0.5/rail_head_radius;
ratio = min(curv_a, curv_b)/max(curv_a, curv_b);
if ratio == 1
    g = 1;
else
    % Hertz's relation for g = minor/major semi-axis, by bisection to the last bit
    lo = 1e-9;
    hi = 1;
    [K, E] = kalker_elliptic(lo);
    if ratio <= lo^2*(K - E)/(E - lo^2*K)
        error('kalker_creep: curvature ratio %g is too small: the contact ellipse would be more slender than b/a = 1e-9', ratio);
    end
    while true
        mid = 0.5*(lo + hi);
        if mid <= lo || mid >= hi
            break;
        end
        [K, E] = kalker_elliptic(mid);
        if mid^2*(K - E)/(E - mid^2*K) < ratio
            lo = mid;
        else
            hi = mid;
        end
    end
    g = hi;
end
[~, E] = kalker_elliptic(g);
e_star = youngs_modulus/(2*(1 - poisson^2));
rho = 2/(curv_a + curv_b);
c = (3*wheel_load*rho*E/(4*pi*e_star*sqrt(g)))^(1/3);
if curv_a >= curv_b
    a = c*sqrt(g);
    b = c/sqrt(g);
else
    a = c/sqrt(g);
    b = c*sqrt(g);
end
% Kalker (1990), Table E.3: rows g = 0.1:0.1:1; columns C11 at nu = 0, 1/4, 1/2, then C22
nodes = [{nodes}];
if a <= b
    gk = a/b;
    table = [{a_le_b}];
else
    gk = b/a;
    table = [{a_gt_b}];
end
nu = poisson;
if gk < 0.1
    % Kalker's asymptotes for g -> 0
    if a <= b
        c11 = pi^2/(4*(1 - nu));
        c22 = pi^2/4;
    else
        lam = log(16/gk^2);
        shifted = lam - 2*nu;
        weighted = (1 - nu)*lam + 2*nu;
        c11 = 2*pi/(shifted*gk)*(1 + (3 - log(4))/shifted);
        c22 = 2*pi/(gk*weighted)*(1 + (1 - nu)*(3 - log(4))/weighted);
    end
else
    i = sum(nodes <= gk);
    if i >= numel(nodes)
        row = table(end, :);
    else
        t = (gk - nodes(i))/(nodes(i + 1) - nodes(i));
        row = table(i, :) + t*(table(i + 1, :) - table(i, :));
    end
    if nu == 0
        c11 = row(1); c22 = row(4);
    elseif nu == 0.25
        c11 = row(2); c22 = row(5);
    elseif nu == 0.5
        c11 = row(3); c22 = row(6);
    else
        % the parabola through 1/C at nu = 0, 1/4, 1/2
        w0 = 8*(nu - 0.25)*(nu - 0.5);
        w1 = -16*nu*(nu - 0.5);
        w2 = 8*nu*(nu - 0.25);
        c11 = 1/(w0/row(1) + w1/row(2) + w2/row(3));
        c22 = 1/(w0/row(4) + w1/row(5) + w2/row(6));
    end
end
shear = youngs_modulus/(2*(1 + poisson));
f11 = shear*a*b*c11;
f22 = shear*a*b*c22;
end

function [K, E] = kalker_elliptic(g)
%KALKER_ELLIPTIC  Complete elliptic integrals K(m), E(m) of parameter m = 1 - g^2,
%   by the arithmetic-geometric mean (Abramowitz & Stegun 17.6).
p = g*g;
a = 1;
b = sqrt(p);
total = 0.5*(1 - p);
weight = 0.5;
for k = 1:64
    c = 0.5*(a - b);
    b = sqrt(a*b);
    a = a - c;
    weight = 2*weight;
    total = total + weight*c^2;
    if abs(c) <= eps*a
        break;
    end
end
K = pi/(2*a);
E = K*(1 - total);
end
"""


def matlab_kalker() -> str:
    """Source of the local functions ``kalker_creep`` and ``kalker_elliptic`` of a
    MATLAB/Octave function file (to be appended after the main function's ``end``)."""
    table = kalker_table()
    return _MATLAB.format(
        nodes=" ".join(repr(g) for g in G_NODES),
        a_le_b=_matlab_rows(table["a_le_b"]),
        a_gt_b=_matlab_rows(table["a_gt_b"]),
    )


_PYTHON = '''

# Kalker (1990), Table E.3: rows g = 0.1, ..., 1.0 (short/long semi-axis); columns C11
# at nu = 0, 1/4, 1/2, then C22 at the same nu.
_KALKER_G = {nodes}
_KALKER_A_LE_B = (  # g = a/b
{a_le_b}
)
_KALKER_A_GT_B = (  # g = b/a
{a_gt_b}
)


def kalker_creep(wheel_load, wheel_radius, rail_head_radius, youngs_modulus, poisson):
    """Kalker's creep coefficients ``(f11, f22)`` [N] of a wheel on a rail.

    The Hertz ellipse of a wheel (rolling radius ``wheel_radius`` [m], conical tread) on
    a rail head (transverse radius ``rail_head_radius`` [m]) under ``wheel_load`` [N],
    steel of ``youngs_modulus`` [Pa] and ``poisson`` [-]; Kalker's C11, C22 (Table E.3);
    ``f = G a b C`` with ``G = E/(2 (1 + nu))``.  The method of
    ``express.rail.contact.creep_coefficients``.
    """
    if not 0.0 < wheel_load < float('inf'):
        raise ValueError(f"wheel_load must be a positive finite number, got {{wheel_load!r}}")
    if not (wheel_radius > 0.0 and rail_head_radius > 0.0):
        raise ValueError(f"wheel_radius and rail_head_radius must be positive, got {{wheel_radius!r}} and {{rail_head_radius!r}}")
    if not 0.0 < youngs_modulus < float('inf'):
        raise ValueError(f"youngs_modulus must be a positive finite number, got {{youngs_modulus!r}}")
    if not 0.0 <= poisson <= 0.5:
        raise ValueError(f"poisson must lie in [0, 0.5], got {{poisson!r}}")
    curv_a = 0.5 / wheel_radius
    curv_b = 0.5 / rail_head_radius
    ratio = min(curv_a, curv_b) / max(curv_a, curv_b)
    g = 1.0
    if ratio != 1.0:
        # Hertz's relation for g = minor/major semi-axis, by bisection to the last bit
        def hertz(g):
            big_k, big_e = _kalker_elliptic(g)
            return g * g * (big_k - big_e) / (big_e - g * g * big_k)

        lo, hi = 1e-9, 1.0
        if ratio <= hertz(lo):
            raise ValueError(f"curvature ratio {{ratio:.3g}} is too small: the contact ellipse would be more slender than b/a = 1e-9")
        while lo < 0.5 * (lo + hi) < hi:
            mid = 0.5 * (lo + hi)
            if hertz(mid) < ratio:
                lo = mid
            else:
                hi = mid
        g = hi
    big_e = _kalker_elliptic(g)[1]
    e_star = youngs_modulus / (2.0 * (1.0 - poisson**2))
    rho = 2.0 / (curv_a + curv_b)
    c = (3.0 * wheel_load * rho * big_e / (4.0 * numpy.pi * e_star * numpy.sqrt(g))) ** (1.0 / 3.0)
    minor, major = c * numpy.sqrt(g), c / numpy.sqrt(g)
    a, b = (minor, major) if curv_a >= curv_b else (major, minor)
    c11, c22 = _kalker_c11_c22(a, b, poisson)
    shear = youngs_modulus / (2.0 * (1.0 + poisson))
    return float(shear * a * b * c11), float(shear * a * b * c22)


def _kalker_elliptic(g):
    """K(m), E(m) of parameter m = 1 - g**2 by the arithmetic-geometric mean."""
    p = g * g
    a, b = 1.0, numpy.sqrt(p)
    total, weight = 0.5 * (1.0 - p), 0.5
    for _ in range(64):
        c = 0.5 * (a - b)
        a, b = a - c, numpy.sqrt(a * b)
        weight *= 2.0
        total += weight * c * c
        if abs(c) <= 2.220446049250313e-16 * a:
            break
    big_k = numpy.pi / (2.0 * a)
    return big_k, big_k * (1.0 - total)


def _kalker_c11_c22(a, b, nu):
    """Kalker's C11, C22 for semi-axes a (rolling direction), b and Poisson's ratio nu."""
    if a <= b:
        g, table = a / b, _KALKER_A_LE_B
    else:
        g, table = b / a, _KALKER_A_GT_B
    if g < 0.1:  # Kalker's asymptotes for g -> 0
        if a <= b:
            return numpy.pi**2 / (4.0 * (1.0 - nu)), numpy.pi**2 / 4.0
        lam = numpy.log(16.0 / g**2)
        shifted = lam - 2.0 * nu
        weighted = (1.0 - nu) * lam + 2.0 * nu
        c11 = 2.0 * numpy.pi / (shifted * g) * (1.0 + (3.0 - numpy.log(4.0)) / shifted)
        c22 = 2.0 * numpy.pi / (g * weighted) * (1.0 + (1.0 - nu) * (3.0 - numpy.log(4.0)) / weighted)
        return c11, c22
    i = sum(1 for node in _KALKER_G if node <= g) - 1
    if i >= len(_KALKER_G) - 1:
        row = table[-1]
    else:
        t = (g - _KALKER_G[i]) / (_KALKER_G[i + 1] - _KALKER_G[i])
        row = tuple(lo + t * (hi - lo) for lo, hi in zip(table[i], table[i + 1]))
    return _kalker_interpolate(row[0:3], nu), _kalker_interpolate(row[3:6], nu)


def _kalker_interpolate(values, nu):
    """The parabola through 1/C at nu = 0, 1/4, 1/2 (a node's value as is)."""
    if nu in (0.0, 0.25, 0.5):
        return values[(0.0, 0.25, 0.5).index(nu)]
    w0 = 8.0 * (nu - 0.25) * (nu - 0.5)
    w1 = -16.0 * nu * (nu - 0.5)
    w2 = 8.0 * nu * (nu - 0.25)
    return 1.0 / (w0 / values[0] + w1 / values[1] + w2 / values[2])
'''


def _python_rows(rows: tuple[tuple[float, ...], ...]) -> str:
    return "\n".join("    (" + ", ".join(repr(x) for x in row) + ")," for row in rows)


def python_kalker() -> str:
    """Module-level source of ``kalker_creep`` (and its helpers and table) of a Python
    export; it needs ``numpy`` imported as ``numpy``."""
    table = kalker_table()
    return _PYTHON.format(
        nodes=repr(G_NODES),
        a_le_b=_python_rows(table["a_le_b"]),
        a_gt_b=_python_rows(table["a_gt_b"]),
    )
