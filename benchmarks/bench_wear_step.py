#!/usr/bin/env python3
"""Benchmark: one wear step of a route of 20 curve cases for the Manchester S1002 car
(issue 37, item 4: at most 60 s on 2 cores).

Run from the repository root::

    PYTHONPATH=src python3 benchmarks/bench_wear_step.py --runs 3

The route: 20 curves, radii 300 m to 3000 m (geometric), 100 mm cant, each at the speed of
0.2 m/s^2 of cant deficiency (at most 160 km/h), equal shares.  One step is
:func:`express.analysis.wear.prediction.predict_wear` resumed from its step 0 for one step
(``stop_after=1``): the 20 steady states on 2 worker processes, the wear across the profile,
the smoothing, the worn profile's contact tables rebuilt, its conicity, linear critical
speed and flange dimensions, the outputs and figures written.  Baseline, alongside: the same
step on one process.  Wall time (the step is parallel), medians of ``--runs`` alternating
runs after a warm-up; the load (``os.getloadavg``) before and after.  The last line is
exactly ``ratio_vs_baseline=<x> target_seconds=60 step_seconds=<t>``.
"""

from __future__ import annotations

import argparse
import math
import os
import shutil
import statistics
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
MODEL = ROOT / "examples" / "manchester-s1002.toml"
TARGET = 60.0


def route_text() -> str:
    """The 20-case route (module docstring)."""
    lines = ['[route]\nname = "20 curves"\n']
    for k, radius in enumerate(300.0 * 10.0 ** (i / 19.0) for i in range(20)):
        sin_phi = 0.1 / 1.5
        speed = min(math.sqrt((0.2 + 9.81 * sin_phi) * radius / math.sqrt(1 - sin_phi**2)), 160 / 3.6)
        share = 0.05
        lines.append(f'[[case]]\nname = "curve {k + 1}"\nradius = "{radius:.1f} m"\ncant = "100 mm"\n'
                     f'speed = "{speed:.4f} m/s"\nshare = {share}\n')
    return "\n".join(lines)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=3)
    args = parser.parse_args()
    from express.analysis.wear.prediction import predict_wear, prediction_identity
    from express.analysis.wear.route import read_route, route_problems
    from express.numeric.statespace import load_vehicle

    work = Path(tempfile.mkdtemp(prefix="bench-wear-"))
    (work / "route.toml").write_text(route_text(), encoding="utf-8")
    route = read_route(work / "route.toml")
    vehicle = load_vehicle(MODEL)
    vehicle = vehicle.origin.twin() if vehicle.origin.cached else vehicle
    problems, speeds = route_problems(route, 1.5, 9.81)
    assert not problems, problems
    identity = prediction_identity(MODEL.read_text(encoding="utf-8"), {}, route, __import__(
        "express.analysis.wear.prediction", fromlist=["WearSettings"]).WearSettings())
    start = work / "start"
    predict_wear(vehicle, route, speeds, 1e8, start, identity=identity, stop_after=0)  # step 0 only

    def step(workers: int) -> float:
        target = work / f"run-{workers}"
        shutil.rmtree(target, ignore_errors=True)
        shutil.copytree(start, target)
        began = time.perf_counter()
        result = predict_wear(vehicle, route, speeds, 1e8, target, identity=identity, workers=workers, stop_after=1)
        assert result.run_now == 1
        return time.perf_counter() - began

    load = os.getloadavg()[0]
    step(2)  # warm-up: Numba's cache, the workers' first tables
    times: dict[int, list[float]] = {1: [], 2: []}
    for _ in range(args.runs):
        for workers in (2, 1):
            times[workers].append(step(workers))
    after = os.getloadavg()[0]
    shutil.rmtree(work, ignore_errors=True)
    median = {w: statistics.median(t) for w, t in times.items()}
    for w in (2, 1):
        print(f"{w} worker(s): " + ", ".join(f"{t:.1f}" for t in times[w]) + f" s; median {median[w]:.1f} s")
    print(f"load (1 min) before {load:.2f}, after {after:.2f}; {os.cpu_count()} CPUs")
    if median[2] > TARGET:
        print("TARGET MISSED")
    print(f"ratio_vs_baseline={median[2] / median[1]:.3f} target_seconds={TARGET:g} step_seconds={median[2]:.1f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
