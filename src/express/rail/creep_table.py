"""Creep forces and spin moment of one Hertzian contact from tables of Kalker's exact
theory: the package table ``data/creep_table.npz`` (made by CONTACT, ``tools/``) and its
compiled interpolation.

For a Hertzian ellipse (semi-axes ``a`` along the rolling direction and ``b``), the exact
steady-rolling forces relative to ``mu N`` depend only on ``a/b``, Poisson's ratio and the
normalised creepages (``c = sqrt(ab)``, Kalker's ``C11, C22, C23`` at ``a/b``)::

    u_x = G ab C11 xi / (3 mu N),  u_y = G ab C22 eta / (3 mu N),
    u_phi = G (ab)^1.5 C23 phi / (3 mu N)

in which Kalker's linear theory reads ``Fx / (mu N) = -3 u_x``,
``Fy / (mu N) = -3 (u_y + u_phi)``.  The table holds ``(Fx, Fy) / (mu N)`` and
``Mz / (mu N c)`` (as below) over ``log(a/b)`` (0.2...25), the direction of ``u`` (its angle
``theta`` from the ``+u_phi`` axis and its azimuth ``alpha`` in ``(u_x, u_y)``, 0...pi/2)
and ``r = |u| / (1 + |u|)``: ``r = 0`` holds Kalker's linear slopes, ``r = 1`` the
full-slip limit, CONTACT the nodes between (``docs/contact.md``, "Creep forces from tables
of the exact theory").  The half-space's symmetries give the other quadrants:
``(xi, eta, phi) -> (xi, -eta, -phi)`` turns ``(Fx, Fy, Mz)`` into ``(Fx, -Fy, -Mz)``, and
``xi -> -xi`` (all creepages negated, then reflected) turns it into ``(-Fx, Fy, Mz)``.

The table stores each node's excess over ``w(r)`` times Kalker's linear slopes (``-3 u / |u|``
for the forces; ``3 (u_y C23 / C22 - u_phi C33 / C23) / |u|`` for the moment, from a series
8 times finer in ``a/b`` held with the table; the forces' excess along and across the
direction of ``(xi, eta)`` at its node, so that a translational creepage's full-slip force, against
it, interpolates exactly); the law is ``w(r)`` times the slopes at the
asked direction and ratio plus the excess interpolated multilinearly in
``(log(a/b), theta, alpha, r)`` — quadratically in ``r`` between ``r = 0`` (no excess)
and the first node, so the law tends to Kalker's linear theory exactly (the moment's where
Kalker gives C33).  ``w`` is
piecewise linear through ``0, r1, 0`` at the first three radii, zero beyond (between
nodes it is what the interpolation makes of its node values: no error from its shape).  Beyond 0.2...25
the table's edge ratio is used (the normalisation keeps the forces' linear limit exact).  The table is for ``nu = 0.3`` (:data:`TABLE_POISSON`); through
the ``C_ij`` the linear limit is exact at any ``nu``.  Signs: the forces on the wheel
oppose the creepages, as in :mod:`express.rail.creep_law`.
"""

from __future__ import annotations

import hashlib
import io
import math
from importlib import resources

import numpy as np

from express.base.kernels import kernel

__all__ = ["TABLE_GRID", "TABLE_POISSON", "load_table", "tabulated", "tabulated_forces", "tabulated_with_moment"]


#: The first 16 hex digits of the package table's SHA-256.  Numba freezes the table into the
#: cached kernels, and its cache follows this file's changes only: a new table must come
#: with its digest here (``tools/contact_creep_runs.py table`` prints it).
TABLE_DIGEST = "182d336602d1662d"


def load_table() -> dict[str, np.ndarray]:
    """The package table's arrays: ``ratios``, ``thetas``, ``alphas``, ``radii`` (nodes) and
    ``values`` of shape ``(ratio, theta, alpha, radius, 3)``, ``moment_slopes``; ``poisson``,
    ``grid`` (CONTACT's elements along each axis)."""
    path = resources.files("express").joinpath("data").joinpath("creep_table.npz")
    content = path.read_bytes()
    digest = hashlib.sha256(content).hexdigest()[:16]
    if digest != TABLE_DIGEST:
        raise RuntimeError(f"data/creep_table.npz has digest {digest}, not {TABLE_DIGEST}: set TABLE_DIGEST in "
                           "express/rail/creep_table.py to the new table's (which recompiles the cached kernels)")
    with np.load(io.BytesIO(content)) as data:
        return {name: np.asarray(data[name]) for name in data.files}


_TABLE = load_table()
#: Poisson's ratio of the table's CONTACT runs [-].
TABLE_POISSON = float(_TABLE["poisson"])
#: Nodes of the table: ratios a/b, angles theta and alpha, radii r.
TABLE_GRID = tuple(int(_TABLE[name].size) for name in ("ratios", "thetas", "alphas", "radii"))
_VALUES = np.ascontiguousarray(_TABLE["values"], dtype=np.float64)
_LOG_RATIO0 = float(np.log(_TABLE["ratios"][0]))
_LOG_RATIO_STEP = float(np.log(_TABLE["ratios"][1] / _TABLE["ratios"][0]))
_THETA_STEP = float(_TABLE["thetas"][1])
_ALPHA_STEP = float(_TABLE["alphas"][1])
_RADIUS_STEP = float(_TABLE["radii"][1])
_SLOPES = np.ascontiguousarray(_TABLE["moment_slopes"], dtype=np.float64)
#: In-plane creepage below this share of the spin's (normalised) is taken as pure spin.
_SPIN_AXIS = 1e-12


@kernel
def _cell(value, step, nodes):
    """Index of the cell holding ``value`` on uniform nodes ``0, step, ...`` (clamped to
    the grid) and the weight of its upper node."""
    t = min(max(value / step, 0.0), nodes - 1.0)
    k = min(int(t), nodes - 2)
    return k, t - k


@kernel
def _cubic_weights(t, k, nodes):
    """Catmull-Rom's weights of nodes ``k - 1 ... k + 2`` at ``t`` in cell ``k`` of
    ``nodes`` nodes; beyond an end the missing node is extrapolated linearly from the two
    inside (its weight moved onto them)."""
    t2 = t * t
    t3 = t2 * t
    w0 = -0.5 * t3 + t2 - 0.5 * t
    w1 = 1.5 * t3 - 2.5 * t2 + 1.0
    w2 = -1.5 * t3 + 2.0 * t2 + 0.5 * t
    w3 = 0.5 * t3 - 0.5 * t2
    if k == 0:
        w1 += 2.0 * w0
        w2 -= w0
        w0 = 0.0
    if k + 2 > nodes - 1:
        w2 += 2.0 * w3
        w1 -= w3
        w3 = 0.0
    return (w0, w1, w2, w3)


@kernel
def _interpolate(values, slopes, ratio, ux, uy, up, c11, c22, moment):
    """``(Fx, Fy) / (mu N)``, ``Mz / (mu N c)`` (0 unless ``moment``) at ``a/b = ratio`` and
    the normalised creepage ``(ux >= 0, uy >= 0, up)``, ``|u| > 0`` (``c11, c22``
    Kalker's): ``w(r)`` times Kalker's linear slopes (the moment's from the fine series
    ``slopes``) plus the table's excess, linear in ``log(a/b)`` and cubic (Catmull-Rom) in
    ``theta``, ``alpha`` and ``r`` — except between ``r = 0`` and the first node, where the
    excess, ``O(|u|^2)``, is quadratic in ``r``."""
    s = math.sqrt(ux * ux + uy * uy + up * up)
    r = s / (1.0 + s)
    shape = values.shape
    log_ratio = math.log(ratio) - _LOG_RATIO0
    m, wm = _cell(log_ratio, _LOG_RATIO_STEP, shape[0])
    i, ti = _cell(math.acos(min(max(up / s, -1.0), 1.0)), _THETA_STEP, shape[1])
    j, tj = _cell(math.atan2(uy, ux), _ALPHA_STEP, shape[2])
    k, t = _cell(r, _RADIUS_STEP, shape[3])
    wi = _cubic_weights(ti, i, shape[1])
    wj = _cubic_weights(tj, j, shape[2])
    wr = (0.0, 0.0, t * t, 0.0) if k == 0 else _cubic_weights(t, k, shape[3])
    along = 0.0
    across = 0.0
    spin = 0.0
    for dm in range(2):
        w_m = wm if dm else 1.0 - wm
        for di in range(4):
            w_i = w_m * wi[di]
            if w_i == 0.0:
                continue
            for dj in range(4):
                w_j = w_i * wj[dj]
                if w_j == 0.0:
                    continue
                for dr in range(4):
                    w = w_j * wr[dr]
                    if w != 0.0:
                        a, b, c, d = m + dm, i + di - 1, j + dj - 1, k + dr - 1
                        along += w * values[a, b, c, d, 0]
                        across += w * values[a, b, c, d, 1]
                        if moment:
                            spin += w * values[a, b, c, d, 2]
    f, wf = _cell(log_ratio, _LOG_RATIO_STEP * (shape[0] - 1) / (slopes.shape[1] - 1), slopes.shape[1])
    k_eta = (1.0 - wf) * slopes[0, f] + wf * slopes[0, f + 1]
    k_phi = (1.0 - wf) * slopes[1, f] + wf * slopes[1, f + 1]
    scale = 3.0 * min(r, max(2.0 * _RADIUS_STEP - r, 0.0)) / s  # w(r)
    dx, dy = ux / c11, uy / c22  # the direction of (xi, eta)
    length = math.sqrt(dx * dx + dy * dy)
    cos, sin = (dx / length, dy / length) if length > 0.0 else (1.0, 0.0)
    fx = along * cos - across * sin  # the excess along and across it, turned back
    fy = along * sin + across * cos
    return fx - scale * ux, fy - scale * (uy + up), (spin + scale * (uy * k_eta - up * k_phi)) if moment else 0.0


@kernel
def _tabulated(values, slopes, normal, friction, a, b, shear_modulus, c11, c22, c23, xi, eta, phi, moment):
    if not normal > 0.0:
        return 0.0, 0.0, 0.0
    limit = friction * normal
    area = shear_modulus * a * b / (3.0 * limit)
    size = math.sqrt(a * b)
    ux = area * c11 * xi
    uy = area * c22 * eta
    up = area * size * c23 * phi
    sign_y = 1.0
    if uy < 0.0:
        uy, up, sign_y = -uy, -up, -1.0
    sign_x = 1.0
    if ux < 0.0:
        ux, sign_x = -ux, -1.0
    if ux == 0.0 and uy == 0.0 and up == 0.0:
        return 0.0, 0.0, 0.0
    if ux * ux + uy * uy <= (_SPIN_AXIS * up) ** 2:
        # pure spin: the direction of (xi, eta) is undefined there and the table's nodes
        # at theta = 0 agree across alpha only to about 0.3 % of the force, so rounding
        # noise in xi and eta would pick a direction at random (docs/contact.md)
        ux = 0.0
        uy = 0.0
    fx, fy, mz = _interpolate(values, slopes, a / b, ux, uy, up, c11, c22, moment)
    size2 = fx * fx + fy * fy
    if size2 > 1.0:  # the cubics may overshoot full slip by ~1e-5: the force is at most mu N
        fx /= math.sqrt(size2)
        fy /= math.sqrt(size2)
    return sign_x * fx * limit, sign_y * fy * limit, sign_y * mz * limit * size


@kernel
def tabulated_with_moment(normal, friction, a, b, shear_modulus, c11, c22, c23, xi, eta, phi):
    """Tangential forces ``(Fx, Fy)`` [N] and spin moment ``Mz`` [N m] on the wheel from
    the table of the exact theory.

    Parameters
    ----------
    normal : float
        Normal force N [N] (> 0; 0 gives no force).
    friction : float
        Coefficient of friction mu [-].
    a, b : float
        Semi-axes of the contact ellipse along and across the rolling direction [m].
    shear_modulus : float
        G [Pa].
    c11, c22, c23 : float
        Kalker's coefficients for a/b and Poisson's ratio [-].
    xi, eta : float
        Longitudinal and lateral creepage [-].
    phi : float
        Spin creepage [1/m].

    Returns
    -------
    fx, fy, mz : float
        Forces [N] and moment about the contact normal [N m], in Kalker's linear limit
        ``-f11 xi``, ``-f22 eta - f23 phi``, ``f23 eta - f33 phi`` (``f33`` of the table's
        Poisson's ratio).
    """
    return _tabulated(_VALUES, _SLOPES, normal, friction, a, b, shear_modulus, c11, c22, c23, xi, eta, phi, True)


@kernel
def tabulated(normal, friction, a, b, shear_modulus, c11, c22, c23, xi, eta, phi):
    """Tangential forces ``(Fx, Fy)`` [N] on the wheel from the table of the exact theory;
    arguments as :func:`tabulated_with_moment` (and :func:`express.rail.creep_law.fastsim`)."""
    fx, fy, _ = _tabulated(_VALUES, _SLOPES, normal, friction, a, b, shear_modulus, c11, c22, c23, xi, eta, phi,
                           False)
    return fx, fy


def tabulated_forces(normal, friction, a, b, shear_modulus, c11, c22, c23, xi, eta, phi):
    """:func:`tabulated_with_moment` over arrays (broadcast); returns ``(Fx, Fy, Mz)`` as
    float arrays [N, N, N m]."""
    arrays = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in
                                   (normal, friction, a, b, shear_modulus, c11, c22, c23, xi, eta, phi)))
    out = np.empty((3,) + arrays[0].shape)
    for index in np.ndindex(arrays[0].shape):
        out[(slice(None),) + index] = tabulated_with_moment(*(float(v[index]) for v in arrays))
    return out[0], out[1], out[2]
