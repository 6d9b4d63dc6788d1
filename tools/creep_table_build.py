"""The grid of EXPRESS's table of the exact theory (:mod:`express.rail.creep_table`) and
its assembly from CONTACT's results (run by ``tools/contact_creep_runs.py table``).

Nodes: ``a/b`` log-spaced over 0.2...25; the direction of the normalised creepage
``u = (u_x, u_y, u_phi)`` by its angle ``theta`` from the ``+u_phi`` axis (0...pi) and
its azimuth ``alpha`` in the ``(u_x, u_y)`` plane (0...pi/2: the symmetries of the
half-space give the other quadrants); its size ``|u|`` by ``r = |u| / (1 + |u|)``.
``r = 0`` holds Kalker's linear theory and ``r = 1`` the full-slip limit (the rigid slip's
direction at every point, a quadrature); CONTACT fills the nodes between.
"""

from __future__ import annotations

import hashlib
import math
import sys
from collections.abc import Callable
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "src"))

from express.rail.kalker import kalker_coefficients

POISSON = 0.3
RATIOS = np.geomspace(0.2, 25.0, 13)  # 1.495 apart: 0.2 ... 5 (9 nodes), then to 25 (flange ellipses)
THETAS = np.linspace(0.0, math.pi, 11)
ALPHAS = np.linspace(0.0, 0.5 * math.pi, 6)
RADII = np.linspace(0.0, 1.0, 11)


def directions() -> np.ndarray:
    """Unit vectors ``(u_x, u_y, u_phi)`` of the nodes, shape ``(theta, alpha, 3)``."""
    t, a = np.meshgrid(THETAS, ALPHAS, indexing="ij")
    out = np.stack([np.sin(t) * np.cos(a), np.sin(t) * np.sin(a), np.cos(t)], axis=-1)
    out[np.abs(out) < 1e-15] = 0.0
    return out


def linear_limit(ratio: float, unit: np.ndarray) -> np.ndarray:
    """``(Fx, Fy) / (mu N |u|)`` and ``Mz / (mu N c |u|)`` of Kalker's linear theory for
    the unit direction ``unit``: ``-3 u_x``, ``-3 (u_y + u_phi)``,
    ``3 (u_y C23 / C22 - u_phi C33 / C23)``."""
    a, b = math.sqrt(ratio), 1.0 / math.sqrt(ratio)
    _, c22, c23, c33 = kalker_coefficients(a, b, POISSON)
    ux, uy, up = unit
    return np.array([-3.0 * ux, -3.0 * (uy + up), 3.0 * (uy * c23 / c22 - up * c33 / c23)])


def full_slip(ratio: float, unit: np.ndarray, n: int = 400) -> np.ndarray:
    """``(Fx, Fy) / (mu N)``, ``Mz / (mu N c)`` in full slip along the rigid slip
    ``(xi - phi y, eta + phi x)`` (lengths over ``c``), Hertz's pressure, midpoint rule
    on ``n x n`` cells."""
    a, b = math.sqrt(ratio), 1.0 / math.sqrt(ratio)
    c11, c22, c23, _ = kalker_coefficients(a, b, POISSON)
    xi, eta, phi = unit[0] / c11, unit[1] / c22, unit[2] / c23
    t = (np.arange(n) + 0.5) / n * 2.0 - 1.0
    x, y = np.meshgrid(a * t, b * t, indexing="ij")
    p = np.sqrt(np.clip(1.0 - (x / a) ** 2 - (y / b) ** 2, 0.0, None))
    p /= p.sum()
    wx = xi - phi * y
    wy = eta + phi * x
    size = np.hypot(wx, wy)
    size[size == 0.0] = 1.0
    wx /= size
    wy /= size
    return np.array([-(p * wx).sum(), -(p * wy).sum(), -(p * (x * wy - y * wx)).sum()])


#: Ratios of the fine series of the spin moment's linear slopes per table interval.
FINE = 8


def moment_slopes(values: np.ndarray) -> np.ndarray:
    """The spin moment's linear slopes ``(C23 / C22, C33 / C23)`` on ``FINE`` times finer
    ratios than the table's, shape ``(2, FINE (n - 1) + 1)``: the kernel corrects the
    table's linear Mz by them.  Where Kalker's C33 is missing, the table's own slope (from
    CONTACT's first node) interpolated between its ratios."""
    fine = np.exp(np.linspace(np.log(RATIOS[0]), np.log(RATIOS[-1]), FINE * (RATIOS.size - 1) + 1))
    coarse_phi = -values[:, 0, 0, 0, 2] / 3.0  # the +u_phi pole's linear Mz slope, per table ratio
    out = np.empty((2, fine.size))
    for k, ratio in enumerate(fine):
        _, c22, c23, c33 = kalker_coefficients(math.sqrt(ratio), 1.0 / math.sqrt(ratio), POISSON)
        out[0, k] = c23 / c22
        out[1, k] = c33 / c23 if np.isfinite(c33) else np.interp(np.log(ratio), np.log(RATIOS), coarse_phi)
    return out


def table_cases() -> np.ndarray:
    """CONTACT's cases ``(a/b, u_x, u_y, u_phi)`` of the inner radii, shape ``(n, 4)``, in the
    order ratio, theta, alpha, radius; the poles' repeated azimuths are run once."""
    rows = []
    units = directions()
    for ratio in RATIOS:
        for i in range(THETAS.size):
            for j in range(ALPHAS.size if 0 < i < THETAS.size - 1 else 1):
                for r in RADII[1:-1]:
                    rows.append((ratio, *(units[i, j] * r / (1.0 - r))))
    return np.array(rows)


def build_table(out: Path, contact: Callable[[np.ndarray], np.ndarray], grid: int) -> None:
    """Run ``contact`` on :func:`table_cases` and write the table ``out`` (``.npz``): nodes,
    the spin moment's linear slopes (:func:`moment_slopes`) and
    ``values[ratio, theta, alpha, radius, k]``: the excess of ``(Fx, Fy) / (mu N)`` and
    ``Mz / (mu N c)`` over ``w(r)`` times the linear theory's slopes (:func:`linear_limit`
    with those slopes), ``w`` piecewise linear through 0, ``r1``, 0 at the first three radii
    and zero beyond: the excess is zero at ``r = 0``, and only the first node has one.  The
    forces' excess is stored along and across the direction ``beta`` of ``(xi, eta)`` at the
    node (so that a translational creepage's full-slip force, ``mu N`` against it,
    interpolates exactly)."""
    cases = table_cases()
    results = contact(cases)
    units = directions()
    raw = np.zeros((RATIOS.size, THETAS.size, ALPHAS.size, RADII.size, 3))
    k = 0
    inner = RADII.size - 2
    for m, ratio in enumerate(RATIOS):
        for i in range(THETAS.size):
            pole = not 0 < i < THETAS.size - 1
            for j in range(1 if pole else ALPHAS.size):
                raw[m, i, j, 1:-1] = results[k:k + inner]
                k += inner
                raw[m, i, j, 0] = linear_limit(ratio, units[i, j])
                if not np.isfinite(raw[m, i, j, 0, 2]):  # no C33 (slender, long rolling axis): CONTACT's
                    raw[m, i, j, 0, 2] = raw[m, i, j, 1, 2] * (1.0 - RADII[1]) / RADII[1]
                raw[m, i, j, -1] = full_slip(ratio, units[i, j])
            if pole:
                raw[m, i, 1:] = raw[m, i, 0]
    slopes = moment_slopes(raw)
    values = raw.copy()
    for m in range(RATIOS.size):
        k_eta, k_phi = slopes[:, m * FINE]
        for i in range(THETAS.size):
            for j in range(ALPHAS.size):
                ux, uy, up = units[i, j]
                slope = np.array([-3.0 * ux, -3.0 * (uy + up), 3.0 * (uy * k_eta - up * k_phi)])
                values[m, i, j, 1] -= RADII[1] * slope  # the linear part's weight: r, r1, 0 at the first three nodes
    values[:, :, :, 0] = 0.0
    for m, ratio in enumerate(RATIOS):  # the forces along and across the direction of (xi, eta)
        c11, c22, _, _ = kalker_coefficients(math.sqrt(ratio), 1.0 / math.sqrt(ratio), POISSON)
        beta = np.arctan2(np.sin(ALPHAS) / c22, np.cos(ALPHAS) / c11)[None, :, None]
        fx, fy = values[m, ..., 0].copy(), values[m, ..., 1].copy()
        values[m, ..., 0] = fx * np.cos(beta) + fy * np.sin(beta)
        values[m, ..., 1] = -fx * np.sin(beta) + fy * np.cos(beta)
    np.savez_compressed(out, ratios=RATIOS, thetas=THETAS, alphas=ALPHAS, radii=RADII,
                        values=values.astype(np.float32), poisson=POISSON, grid=grid, moment_slopes=slopes)
    digest = hashlib.sha256(out.read_bytes()).hexdigest()[:16]
    print(f"{len(cases)} CONTACT cases; table {values.shape} -> {out} ({out.stat().st_size} bytes, digest {digest}: "
          "TABLE_DIGEST of express/rail/creep_table.py)")
