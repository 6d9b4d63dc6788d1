#!/usr/bin/env python3
"""Spectrum realisation benchmark: evaluating a random track irregularity.

Run from the repository root::

    PYTHONPATH=src python3 benchmarks/bench_track_spectrum.py            # full run (~3 min idle)
    PYTHONPATH=src python3 benchmarks/bench_track_spectrum.py --quick    # smoke test

Measured (medians of ``--runs`` runs after one warm-up, one core):

* ``Harmonics.evaluate`` (``express.rail.track.irregularity``: blocks of 64 harmonics
  sharing one complex exponential, Horner's rule inside a block), value and rate, for
  the default realisation (ERRI low, 3 m to 120 m, period 10 km: 3250 harmonics) at the
  points a simulation of the paper's curve asks for (460 m at 120 km/h, dt = 1 ms, 4
  wheelsets: 55 200 points) and for a 9750-harmonic realisation (period 30 km);
* baseline: the definition, one cosine per harmonic per point
  (``cos(outer(s, Omega) + phi) @ a``, in chunks of 2e6 terms), same points, same run;
* the largest difference between the two, relative to the largest |yR|.
"""

from __future__ import annotations

import argparse
import os
import statistics
import time

for _name in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_name, "1")

import numpy as np  # noqa: E402  (after the thread settings)

from express.rail.track import SpectrumIrregularity  # noqa: E402

try:
    from machine import cpu_name, usable_cores  # type: ignore[import-not-found]
except ImportError:  # run from elsewhere
    from benchmarks.machine import cpu_name, usable_cores  # type: ignore[import-not-found,no-redef]


def cosine_sum(s: np.ndarray, w: np.ndarray, a: np.ndarray, phi: np.ndarray, derivative: bool) -> np.ndarray:
    """The baseline: one cosine (sine) per harmonic per point."""
    out = np.empty_like(s)
    chunk = max(1, 2_000_000 // w.size)
    for i in range(0, s.size, chunk):
        arg = np.outer(s[i : i + chunk], w) + phi
        out[i : i + chunk] = -np.sin(arg) @ (a * w) if derivative else np.cos(arg) @ a
    return out


def median_time(function, runs: int) -> float:
    function()
    times = []
    for _ in range(runs):
        start = time.perf_counter()
        function()
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--quick", action="store_true", help="fewer points and runs")
    args = parser.parse_args()
    runs = 2 if args.quick else args.runs
    points = 5_520 if args.quick else 55_200
    print(f"machine: {cpu_name()}, {usable_cores()} usable cores; numpy {np.__version__}; medians of {runs}")
    s = np.linspace(0.0, 460.0, points)
    for period in (10_000.0, 30_000.0):
        h = SpectrumIrregularity("erri_low", seed=1, period=period).harmonics
        n = h.wavenumbers.size
        for derivative in (False, True):
            ours = median_time(lambda: h.evaluate(s, derivative), runs)  # noqa: B023
            base = median_time(lambda: cosine_sum(s, h.wavenumbers, h.amplitudes, h.phases, derivative), runs)  # noqa: B023
            y = h.evaluate(s, derivative)
            ref = cosine_sum(s, h.wavenumbers, h.amplitudes, h.phases, derivative)
            diff = np.max(np.abs(y - ref)) / np.max(np.abs(ref))
            what = "rate " if derivative else "value"
            print(f"{n:6d} harmonics, {points} points, {what}: blocks {ours:7.3f} s, cosine sum {base:7.3f} s, "
                  f"ratio {base / ours:5.1f}, largest relative difference {diff:.1e}")


if __name__ == "__main__":
    main()
