#!/usr/bin/env python3
"""The Y25 freight wagon with friction elements against the same wagon without them
(issue 31, item 9 and its performance target).

Run from the repository root::

    PYTHONPATH=src python3 benchmarks/bench_wagon.py            # R600 track, 3 runs each
    PYTHONPATH=src python3 benchmarks/bench_wagon.py --quick    # smoke test

On ONE core (BLAS/OpenMP threads set to 1 before NumPy is imported), in the same run:

- ``friction``: ``examples/y25-wagon.toml`` (tare) — 30 friction elements (Lenoir links in
  x, y, z with their limits proportional to the coils' loads, centre-bowl and side-bearer
  friction torques proportional to theirs) and 8 bilinear coil characteristics — through
  ``simulate()`` on the bundled R600 track with the contact from the profiles' tables, at
  the default 5 ms step;
- ``baseline``: the same wagon without the new elements — every friction element its
  stuck pre-slip spring, every coil its tangent (what the linear analyses see) — on the
  same track at the same step.

The realtime factor is ``travel time / wall time`` of the median of ``--runs`` runs after
one warm-up (target >= 200 for the wagon with friction); the ratio ``friction / baseline``
says what the new elements cost.  The last line is exactly
``realtime_factor=<x> baseline_realtime_factor=<y> ratio=<z>``.
"""

from __future__ import annotations

import os

for _variable in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS", "NUMEXPR_NUM_THREADS",
                  "NUMBA_NUM_THREADS", "VECLIB_MAXIMUM_THREADS"):
    os.environ.setdefault(_variable, "1")

import argparse  # noqa: E402
import re  # noqa: E402
import statistics  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

from machine import cpu_name, usable_cores  # noqa: E402  (benchmarks/machine.py)

ROOT = Path(__file__).resolve().parents[1]
if str(ROOT / "src") not in sys.path:
    sys.path.insert(0, str(ROOT / "src"))

WAGON = ROOT / "examples" / "y25-wagon.toml"
TARGET = 200.0


def without_new_elements(text: str) -> str:
    """The wagon's text with every friction element its stuck pre-slip spring and every
    characteristic its tangent (``kz1``): the same linear model, no nonlinear elements."""
    text = re.sub(r', friction = \{[^}]*\}', "", text)
    return re.sub(r'characteristic = \{ shape = "bilinear"[^}]*\}', 'stiffness = "kz1"', text)


def _median(function, runs: int):
    function()  # warm-up (compiles or loads the kernels)
    times = []
    for _ in range(runs):
        start = time.perf_counter()
        result = function()
        times.append(time.perf_counter() - start)
    return statistics.median(times), times, result


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--quick", action="store_true", help="one run each, 200 m of the track")
    args = parser.parse_args()
    from express.analysis.time.simulate import simulate
    from express.io import parse_toml_model
    from express.numeric.statespace import vehicle_model
    from express.rail.track.named import named_track

    track, _ = named_track("R600")
    end = 200.0 if args.quick else None
    runs = 1 if args.quick else args.runs
    text = WAGON.read_text()
    vehicles = {"friction": vehicle_model(parse_toml_model(text, str(WAGON))),
                "baseline": vehicle_model(parse_toml_model(without_new_elements(text), str(WAGON)))}
    print(f"machine: {cpu_name()}, {usable_cores()} usable cores, load {os.getloadavg()[0]:.2f} "
          f"(1-minute average at the start)")
    factors = {}
    for name, vehicle in vehicles.items():
        median, times, result = _median(lambda v=vehicle: simulate(v, track, progress=False, end=end), runs)
        travel = float(result.time[-1] - result.time[0])
        factors[name] = travel / median
        kinds = sorted(k for k in ("friction", "characteristics") if k in result.options)
        print(f"{name:9s} n={vehicle.n} DOFs, {result.time.size - 1} steps of 5 ms, travel {travel:.2f} s: median "
              f"{median * 1e3:.1f} ms of [{', '.join(f'{t * 1e3:.1f}' for t in sorted(times))}] ms, realtime "
              f"factor {factors[name]:.0f} (nonlinear suspension: {', '.join(kinds) or 'none'})")
    ratio = factors["baseline"] / factors["friction"]
    verdict = "ok" if factors["friction"] >= TARGET else "TARGET MISSED"
    print(f"wagon with friction: {factors['friction']:.0f}x real time (target >= {TARGET:.0f}: {verdict}); "
          f"{ratio:.2f} times the wall time of the wagon without the new elements; "
          f"load {os.getloadavg()[0]:.2f} at the end")
    print(f"realtime_factor={factors['friction']:.1f} baseline_realtime_factor={factors['baseline']:.1f} "
          f"ratio={ratio:.3f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
