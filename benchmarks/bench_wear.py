#!/usr/bin/env python3
"""Benchmark: what the energy and damage numbers (Tgamma, the USFD wear rate, Burstow's RCF
index per wheel; issue 37, item 1) cost a contact run.

Run from the repository root, with a checkout of the code before them as the baseline::

    git worktree add /tmp/express-base c365159     # the commit before Tgamma
    PYTHONPATH=src python3 benchmarks/bench_wear.py --baseline-src /tmp/express-base/src
    PYTHONPATH=src python3 benchmarks/bench_wear.py --baseline-src /tmp/express-base/src --quick

One core (BLAS/OpenMP threads 1).  The run: ``examples/manchester-s1002.toml`` through the
bundled curve R400 (150 mm cant, 580 m) at 80 km/h with the contact tables (FASTSIM), the whole
``simulate()`` call timed in CPU time (``time.process_time``: the machine is shared; wall
time printed too): the march (the kernel now also computes each contact's creepages,
Tgamma and patch area) and the per-wheel columns (the wear and RCF functions on the
record); the force kernel alone over the run's states (``contact_force_history``,
static loads); and the record's columns (``WheelRailOutputs.columns``, 30 times).  Each measurement is a fresh process of one source tree (this one, or the
baseline's), a warm-up run (Numba's cache), then ``--runs`` timed runs (the kernel
``3 x --runs``), their median; the two trees alternate for ``--rounds`` rounds, so that a
change of the machine's load falls on both.  Printed: every round's medians, then the
median over the rounds of each ratio this tree / baseline (of the medians, and of the
minima, which a loaded machine disturbs least); the target is on the ``simulate()`` CPU
ratio of the medians.  The last line is exactly
``ratio_vs_baseline=<x> target=1.05``; exit code 0 even when it is missed (``TARGET
MISSED`` is printed).
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
TARGET = 1.05
#: The child's program: time ``simulate()`` in the tree on ``sys.path[0]``.
CHILD = r"""
import json, statistics, sys, time
sys.path.insert(0, sys.argv[1])
import express
from express.analysis.time.contact_march import contact_force_history
from express.analysis.time.force_elements import contact_tables_of
from express.analysis.time.simulate import simulate
from express.analysis.time.track_inputs import track_inputs
from express.io import load_model
from express.numeric.statespace import vehicle_model
from express.rail.track.named import named_track

runs = int(sys.argv[2])
vehicle = vehicle_model(load_model(sys.argv[3]))
track = named_track("R400")[0]
speed = 80 / 3.6

def run():
    return simulate(vehicle, track, speed=speed, progress=False)

result = run()  # warm-up: Numba's cache, the tables
wall, cpu = [], []
for _ in range(runs):
    begin, begin_cpu = time.perf_counter(), time.process_time()
    run()
    wall.append(time.perf_counter() - begin)
    cpu.append(time.process_time() - begin_cpu)
# the force kernel alone: every step's contact of the run again (static loads)
contact = contact_tables_of(vehicle, "tables", "fastsim")
inputs = track_inputs(vehicle, track, result.distance, speed)
iy, ipsi = [w.y for w in vehicle.wheelsets], [w.psi for w in vehicle.wheelsets]

def kernel():
    return contact_force_history(result.q, result.q_dot, iy, ipsi, inputs.y_rail, inputs.rho_wheelsets, speed,
                                 contact)

kernel()
alone = []
for _ in range(3 * runs):
    begin = time.process_time()
    kernel()
    alone.append(time.process_time() - begin)
# the per-wheel columns of the record (the wear and RCF functions on it)
columns = []
for _ in range(30):
    begin = time.process_time()
    result.wheel_rail.columns()
    columns.append(time.process_time() - begin)
print(json.dumps({"source": express.__file__, "wall": statistics.median(wall), "cpu": statistics.median(cpu),
                  "kernel": statistics.median(alone), "cpu_min": min(cpu), "kernel_min": min(alone),
                  "columns": statistics.median(columns),
                  "steps": len(result.time) - 1, "names": len(result.outputs)}))
"""


def measure(source: Path, runs: int) -> dict:
    """One fresh process of the tree at ``source``: the median of ``runs`` timed runs."""
    env = {**os.environ, "PYTHONPATH": str(source)}
    for variable in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
        env[variable] = "1"
    done = subprocess.run([sys.executable, "-c", CHILD, str(source), str(runs),
                           str(ROOT / "examples" / "manchester-s1002.toml")],
                          env=env, capture_output=True, text=True, check=True)
    return json.loads(done.stdout.strip().splitlines()[-1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--baseline-src", type=Path, required=True, help="src/ of the code before Tgamma")
    parser.add_argument("--runs", type=int, default=5, help="timed runs per process (median)")
    parser.add_argument("--rounds", type=int, default=5, help="alternating rounds (baseline, this tree)")
    parser.add_argument("--quick", action="store_true", help="2 rounds of 2 runs")
    options = parser.parse_args()
    runs, rounds = (2, 2) if options.quick else (options.runs, options.rounds)
    here = ROOT / "src"
    print(f"load: {os.getloadavg()[0]:.2f} {os.getloadavg()[1]:.2f} {os.getloadavg()[2]:.2f} (1, 5, 15 min)")
    ratios: dict[str, list[float]] = {"cpu": [], "wall": [], "kernel": [], "cpu_min": [], "kernel_min": []}
    for k in range(rounds):
        base, new = measure(options.baseline_src, runs), measure(here, runs)
        for key, found in ratios.items():
            found.append(new[key] / base[key])
        print(f"round {k + 1} ({new['steps']} steps; {base['names']} -> {new['names']} columns): "
              f"simulate() CPU {base['cpu'] * 1e3:.1f} -> {new['cpu'] * 1e3:.1f} ms (ratio {ratios['cpu'][-1]:.3f}), "
              f"wall {base['wall'] * 1e3:.1f} -> {new['wall'] * 1e3:.1f} ms; the kernel alone over the run's "
              f"states, CPU {base['kernel'] * 1e3:.2f} -> {new['kernel'] * 1e3:.2f} ms "
              f"(ratio {ratios['kernel'][-1]:.3f}); the record's columns {base['columns'] * 1e3:.2f} -> "
              f"{new['columns'] * 1e3:.2f} ms")
    ratio = statistics.median(ratios["cpu"])
    print(f"median ratios over the rounds: simulate() CPU {ratio:.3f}, wall {statistics.median(ratios['wall']):.3f}, "
          f"kernel alone {statistics.median(ratios['kernel']):.3f}; of the fastest runs (minima): simulate() CPU "
          f"{statistics.median(ratios['cpu_min']):.3f}, kernel alone {statistics.median(ratios['kernel_min']):.3f}")
    print(f"load after: {os.getloadavg()[0]:.2f}")
    if ratio > TARGET:
        print(f"TARGET MISSED: {ratio:.3f} > {TARGET}")
    print(f"ratio_vs_baseline={ratio:.3f} target={TARGET}")


if __name__ == "__main__":
    main()
