#!/usr/bin/env python3
"""Contact benchmark: contact geometry of S1002 on 60E1 and EN 15302 conicity, each
against a plain NumPy/SciPy baseline measured in the same run.

Run from the repository root::

    PYTHONPATH=src python3 benchmarks/bench_contact.py            # full run (~30 s)
    PYTHONPATH=src python3 benchmarks/bench_contact.py --quick    # smoke test

Measured (medians of ``--runs`` runs after a warm-up; garbage collector off while timing):

1. ``contact_geometry(S1002, 60E1, y)`` for y = -10..10 mm every 0.01 mm (2001
   displacements; 1435 mm gauge, 1360 mm flange back, 1:40), the whole call: splines,
   tables, the compiled solver, the table (target < 0.5 s).  The first call's Numba
   compile (or cache load) is reported apart.  Baseline: the same geometry with NumPy
   vectorised over the wheel points and ``scipy.optimize.brentq`` on the roll at each y
   (same surfaces, no compiled code); its delta r is compared.
2. ``equivalent_conicity`` of EN 15302's case E1 (137 points) at 59 amplitudes
   1..6.8 mm, and of the S1002/60E1 delta r (2001 points) at 66 amplitudes 1..7.5 mm
   (target < 50 ms each).  Baseline: the Annex B recipe done plainly, as public
   implementations do it: delta r resampled every 0.01 mm, S(y) by cumulative sums,
   turning points by search, the wavelength integral by a Riemann sum of dy / psi;
   its results are compared.

3. One creep-law evaluation (``express.rail.creep_table.tabulated``, the tables of the
   exact theory) on 20000 contacts (a/b 0.2...5, creepages from the linear range to full
   slip, spin up to 6 1/m), in a compiled loop.  Baseline, same run: FASTSIM 3 x 5
   (``express.rail.creep_law.fastsim``, the production law) in the same loop; Polach for
   information.  Printed: ns per evaluation, the ratio table / FASTSIM.

The last line is ``contact_geometry_s=<x> conicity_ms=<y> speedups=<a>,<b> law_ratio=<c>``.  A missed
target prints ``TARGET MISSED`` (exit code 0 all the same).
"""

from __future__ import annotations

import os

for _variable in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ.setdefault(_variable, "1")

import argparse  # noqa: E402
import gc  # noqa: E402
import math  # noqa: E402
import platform  # noqa: E402
import statistics  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from importlib import resources  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402
from numba import njit  # noqa: E402
from scipy.optimize import brentq  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))
from express.rail.conicity import equivalent_conicity, read_delta_r  # noqa: E402
from express.rail.contact_geometry import ContactSetup, contact_geometry, prepare_surfaces  # noqa: E402
from express.rail.creep_law import fastsim, polach  # noqa: E402
from express.rail.creep_table import tabulated  # noqa: E402
from express.rail.kalker import kalker_coefficients  # noqa: E402
from express.rail.profiles import standard_profile  # noqa: E402
from machine import cpu_name, usable_cores  # noqa: E402


def median_time(function, runs: int) -> tuple[float, object]:
    result = function()  # warm-up
    times = []
    gc.disable()
    try:
        for _ in range(runs):
            start = time.perf_counter()
            result = function()
            times.append(time.perf_counter() - start)
    finally:
        gc.enable()
    return statistics.median(times), result


# --- baseline 1: NumPy per wheel point, brentq per displacement --------------------------


def naive_delta_r(surfaces, y_values, setup) -> np.ndarray:
    wl, rl, wr, rr = surfaces
    half, r0 = setup.tapeline_half_distance, setup.wheel_radius
    grids = [(w.start + w.step * np.arange(len(w.z)), w.z) for w in (wl, wr)]
    rails = [(r.start + r.step * np.arange(len(r.z)), r.z) for r in (rl, rr)]

    def lowest(sigma, y, phi, side):
        s, zw = grids[side]
        u_rail, z_rail = rails[side]
        yw, zz = sigma * (half + s), -r0 + zw
        u = sigma * (y + math.cos(phi) * yw - math.sin(phi) * zz)
        gap = math.sin(phi) * yw + math.cos(phi) * zz - np.interp(u, u_rail, z_rail, left=-np.inf, right=-np.inf)
        i = int(np.argmin(gap))
        return gap[i], r0 - zw[i]

    out = np.empty(len(y_values))
    for k, y in enumerate(y_values):
        phi = brentq(lambda p, y=y: lowest(1.0, y, p, 0)[0] - lowest(-1.0, y, p, 1)[0], -0.02, 0.02, xtol=1e-13)
        out[k] = lowest(1.0, y, phi, 0)[1] - lowest(-1.0, y, phi, 1)[1]
    return out


# --- baseline 2: the Annex B recipe with sums ------------------------------------------------


def naive_conicity(y, delta_r, amplitudes, dy=1e-5) -> np.ndarray:
    """Annex B as public codes do it: delta r on a 0.01 mm grid, every left grid point a
    turning point, its partner the right grid point nearest in S, the integral of dy / psi
    a trapezoidal sum; tan(gamma_e) interpolated to the asked amplitudes."""
    grid = np.arange(y[0], y[-1] + dy / 2, dy)
    dr = np.interp(grid, y, delta_r)
    centre = int(np.argmin(np.abs(dr)))
    s = np.concatenate([[0.0], np.cumsum(0.5 * dy * (dr[1:] + dr[:-1]))])
    s -= s[centre]
    found_a, found_t = [], []
    for left in range(centre - 1, -1, -1):
        energy = s[left]
        right = centre + int(np.argmax(s[centre:] >= energy))
        if s[right] < energy:
            break
        if energy - s[right - 1] < s[right] - energy:  # the nearest grid point, as EN 15302 codes do
            right -= 1
        psi = np.sqrt(np.maximum(energy - s[left : right + 1], 0.0))
        psi[-1] = 0.0
        integral = np.sum(2 * dy / (psi[1:] + psi[:-1]))
        found_a.append(0.5 * (grid[right] - grid[left]))
        found_t.append(math.pi**2 / integral**2)
    return np.interp(amplitudes, found_a, found_t)


# --- 3: one creep-law evaluation ----------------------------------------------------------


def _law_loop(law):
    @njit(cache=False)
    def loop(cases):
        total = 0.0
        for k in range(cases.shape[0]):
            c = cases[k]
            fx, fy = law(c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7], c[8], c[9], c[10])
            total += fx + fy
        return total
    return loop


def law_cases(count: int = 20000) -> np.ndarray:
    """Rows ``(N, mu, a, b, G, C11, C22, C23, xi, eta, phi)`` of random contacts (seeded)."""
    rng = np.random.default_rng(1)
    rows = np.empty((count, 11))
    for k in range(count):
        ratio = math.exp(rng.uniform(math.log(0.2), math.log(5.0)))
        size = rng.uniform(3e-3, 7e-3)
        a, b = size * math.sqrt(ratio), size / math.sqrt(ratio)
        creep = 10.0 ** rng.uniform(-5, -2)
        rows[k] = (rng.uniform(2e4, 1e5), 0.3, a, b, 8.08e10, *kalker_coefficients(a, b, 0.3)[:3],
                   creep * rng.uniform(-1, 1), creep * rng.uniform(-1, 1), rng.uniform(-6.0, 6.0))
    return rows


def law_costs(runs: int) -> dict[str, float]:
    """Median ns per evaluation of each law on :func:`law_cases`."""
    cases = law_cases()
    out = {}
    for name, law in (("table", tabulated), ("fastsim", fastsim), ("polach", polach)):
        loop = _law_loop(law)
        seconds, _ = median_time(lambda loop=loop: loop(cases), runs)
        out[name] = seconds / len(cases) * 1e9
    return out


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--quick", action="store_true", help="fewer runs, baselines on a subset")
    parser.add_argument("--runs", type=int, default=None, help="timed runs (default 7, --quick 3)")
    args = parser.parse_args()
    runs = args.runs or (3 if args.quick else 7)
    print(f"machine: {cpu_name()}, {usable_cores()} usable cores, Python {platform.python_version()}, "
          f"NumPy {np.__version__}")
    missed = []

    wheel, rail, setup = standard_profile("S1002"), standard_profile("60E1"), ContactSetup()
    y = np.arange(-1000, 1001) * 1e-5
    start = time.perf_counter()
    contact_geometry(wheel, rail, y[:3], setup)
    print(f"first call (Numba compile or cache load): {time.perf_counter() - start:.2f} s")
    t_geometry, table = median_time(lambda: contact_geometry(wheel, rail, y, setup), runs)
    surfaces = prepare_surfaces(wheel, rail, setup)
    subset = y[::20] if args.quick else y
    t_naive, naive = median_time(lambda: naive_delta_r(surfaces, subset, setup), 1)
    t_naive *= len(y) / len(subset)
    # the baseline's contact is the nearest wheel point (no refinement): compare away from jumps
    quiet = np.ones(len(subset), bool)
    for jump in table.jumps:
        quiet &= np.abs(subset - 0.5 * (jump.y_before + jump.y_after)) > 0.05e-3
    difference = np.abs(naive - table.delta_r[np.searchsorted(y, subset)])[quiet].max()
    speedup_geometry = t_naive / t_geometry
    print(f"contact geometry, S1002/60E1 1:40, 2001 displacements: {t_geometry * 1e3:.1f} ms (target < 500 ms)")
    print(f"  baseline NumPy + brentq{' (extrapolated from 101)' if args.quick else ''}: {t_naive:.2f} s, "
          f"speedup {speedup_geometry:.0f}x; delta r differs by at most {difference * 1e6:.2f} um away from jumps")
    if t_geometry >= 0.5:
        missed.append("contact geometry")

    e1 = read_delta_r(str(resources.files("express").joinpath("data").joinpath("en15302").joinpath("E1.csv")))
    cases = [("EN 15302 E1 (137 points), 59 amplitudes 1..6.8 mm", e1.y, e1.delta_r, np.arange(10, 69) * 1e-4),
             ("S1002/60E1 (2001 points), 66 amplitudes 1..7.5 mm", table.y, table.delta_r, np.arange(10, 76) * 1e-4)]
    t_conicity, speedups = [], []
    for label, yy, dr, amplitudes in cases:
        t_fast, fast = median_time(lambda yy=yy, dr=dr, amplitudes=amplitudes: equivalent_conicity(yy, dr, amplitudes), runs)
        t_slow, slow = median_time(lambda yy=yy, dr=dr, amplitudes=amplitudes: naive_conicity(yy, dr, amplitudes), 1)
        t_conicity.append(t_fast)
        speedups.append(t_slow / t_fast)
        print(f"conicity, {label}: {t_fast * 1e3:.1f} ms (target < 50 ms); baseline Annex B sums {t_slow * 1e3:.0f} ms, "
              f"speedup {t_slow / t_fast:.0f}x; results differ by at most {np.abs(fast - slow).max():.4f}")
        if t_fast >= 0.05:
            missed.append(f"conicity {label}")
    costs = law_costs(runs)
    ratio = costs["table"] / costs["fastsim"]
    print(f"one creep-law evaluation (20000 contacts, compiled loop): table {costs['table']:.0f} ns; "
          f"baseline FASTSIM 3 x 5 {costs['fastsim']:.0f} ns, ratio table / FASTSIM {ratio:.2f}; "
          f"Polach {costs['polach']:.0f} ns")
    if missed:
        print("TARGET MISSED: " + ", ".join(missed))
    print(f"contact_geometry_s={t_geometry:.4f} conicity_ms={max(t_conicity) * 1e3:.2f} "
          f"speedups={speedup_geometry:.0f},{min(speedups):.0f} law_ratio={ratio:.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
