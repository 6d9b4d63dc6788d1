#!/usr/bin/env python3
"""Steady-state curving benchmark (issue 22): one curve after the first, and a sweep of
50 curves, against the baseline of a time march to the settled state measured in the
same run.

Run from the repository root::

    PYTHONPATH=src python3 benchmarks/bench_curving.py            # ~1 min
    PYTHONPATH=src python3 benchmarks/bench_curving.py --quick    # smoke test

Measured, for the conventional car of the paper (dead-band contact) and the Manchester
coach on S1002/60E1 (contact tables), medians of ``--runs`` runs:

1. ``SteadyCurvingSolver.solve`` of R = 600 m, 100/150 mm cant at 0.5 m/s^2 of cant
   deficiency, the solver (matrices, tables) built once beforehand (target < 0.1 s);
2. ``steady_curving`` over 50 radii 250...2000 m at 0.5 m/s^2, each solution starting
   the next, solver build included (target < 5 s);
3. baseline: ``simulate`` through 20 m straight, a 60 m transition and 600 m of the same
   curve, to the settled state the steady state equals (tests/test_curving_steady.py);
   the largest difference of the coordinates is printed.

The last line is ``steady_ms=<a>,<b> sweep_s=<c>,<d> speedup_vs_march=<e>,<f>``.  A missed
target prints ``TARGET MISSED`` (exit code 0 all the same).
"""

from __future__ import annotations

import os

for _variable in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ.setdefault(_variable, "1")

import argparse  # noqa: E402
import statistics  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))
from express.analysis.curving.steady import SteadyCurve, SteadyCurvingSolver, steady_curving  # noqa: E402
from express.analysis.time.simulate import simulate  # noqa: E402
from express.model.parameters import expression_value  # noqa: E402
from express.numeric.statespace import load_vehicle  # noqa: E402
from express.rail.track import Curve, Straight, Track, Transition  # noqa: E402
from machine import cpu_name, usable_cores  # noqa: E402

CARS = (("conventional (dead-band)", "examples/conventional.toml", 0.100),
        ("Manchester S1002/60E1 (tables)", "examples/manchester-s1002.toml", 0.150))
DEFICIENCY = 0.5


def median(function, runs: int) -> float:
    times = []
    for _ in range(runs):
        start = time.perf_counter()
        function()
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def bench(label: str, path: str, cant: float, runs: int, count: int) -> tuple[float, float, float]:
    vehicle = load_vehicle(path)
    rail = vehicle.model.rail
    base, g = expression_value(rail.cant_base, vehicle.values), expression_value(rail.gravity, vehicle.values)
    curve = SteadyCurve(600.0, cant, "right")
    speed = curve.speed_for(DEFICIENCY, base, g)
    solver = SteadyCurvingSolver(vehicle, speed)
    first = time.perf_counter()
    steady = solver.solve(curve)
    first = time.perf_counter() - first
    one = median(lambda: solver.solve(curve), runs)
    curves = [SteadyCurve(r, cant, "right") for r in np.linspace(250.0, 2000.0, count)]
    speeds = [c.speed_for(DEFICIENCY, base, g) for c in curves]
    sweep = median(lambda: steady_curving(vehicle, curves, speeds=speeds), max(1, runs // 3))
    track = Track((Straight(20.0), Transition(60.0), Curve(600.0, 600.0, "right", cant)))
    march = median(lambda: simulate(vehicle, track, speed=speed, end=650.0, progress=False), max(1, runs // 3))
    run = simulate(vehicle, track, speed=speed, end=650.0, progress=False)
    difference = float(np.max(np.abs(run.q[-1] - steady.q)))
    print(f"{label}: first curve {first * 1e3:.0f} ms (tables/compile), one curve {one * 1e3:.1f} ms "
          f"(target < 100 ms){'' if one < 0.1 else '  TARGET MISSED'}; {count} curves {sweep:.2f} s "
          f"(target < 5 s){'' if sweep < 5 else '  TARGET MISSED'}; time march to the settled state "
          f"{march:.2f} s ({march / one:.0f}x the steady solution), largest coordinate difference {difference:.1e}")
    return one, sweep, march / one


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="3 runs, 10 curves")
    parser.add_argument("--runs", type=int, default=None)
    args = parser.parse_args(argv)
    runs = args.runs or (3 if args.quick else 9)
    count = 10 if args.quick else 50
    print(f"machine: {cpu_name()}, {usable_cores()} usable cores (shared: timings are noisy); one BLAS thread")
    figures = [bench(label, path, cant, runs, count) for label, path, cant in CARS]
    print("steady_ms=" + ",".join(f"{f[0] * 1e3:.1f}" for f in figures) + " sweep_s="
          + ",".join(f"{f[1]:.2f}" for f in figures) + " speedup_vs_march=" + ",".join(f"{f[2]:.0f}" for f in figures))


if __name__ == "__main__":
    main()
