#!/usr/bin/env python3
"""Benchmark: what the step check of an assessed run costs (issue 32, item 3; target: at most
2.5 times a single run).

Run from the repository root::

    PYTHONPATH=src python3 benchmarks/bench_step_check.py
    PYTHONPATH=src python3 benchmarks/bench_step_check.py --runs 3 --model examples/conventional.toml

One core (BLAS/OpenMP threads 1).  The baseline is the same assessed run without the
check, in the same process: ``simulate()`` and ``assess_run()`` of
``examples/manchester-s1002.toml`` (the stiffest bundled car) along the bundled curve R400 at
95 km/h and the default 5 ms step; the check adds the run at 10 ms and, when the EN 14363
quantities move by more than 1 % of a limit, finer ones
(:func:`express.analysis.time.step_check.checked_run`).  After a warm-up (Numba's cache),
``--runs`` of each alternate; CPU time (``time.process_time``: the machine is shared), the
medians.  The last line is exactly ``ratio_vs_baseline=<x> target=2.5``; exit code 0 even
when it is missed (``TARGET MISSED`` is printed).
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import time

for _name in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ.setdefault(_name, "1")

TARGET = 2.5


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--model", default="examples/manchester-s1002.toml")
    args = parser.parse_args(argv)

    from express.analysis.curving.assessment import assess_run
    from express.analysis.time.divergence import find_divergence
    from express.analysis.time.simulate import simulate
    from express.analysis.time.step_check import checked_run
    from express.io import load_model
    from express.numeric.statespace import vehicle_model
    from express.rail.track.named import named_track

    vehicle = vehicle_model(load_model(args.model))
    track = named_track("R400")[0]
    speed = 95 / 3.6

    def assessed(dt: float):
        result = simulate(vehicle, track, speed=speed, dt=dt, progress=False)
        return None if find_divergence(result, vehicle) is not None else (result, assess_run(vehicle, track, result)[1])

    def single() -> None:
        assessed(0.005)

    def checked() -> str:
        return checked_run(assessed, 0.005)[2].sentence()

    single()
    sentence = checked()
    times: dict[str, list[float]] = {"single": [], "checked": []}
    for _ in range(args.runs):
        for name, task in (("single", single), ("checked", checked)):
            start = time.process_time()
            task()
            times[name].append(time.process_time() - start)
    medians = {name: statistics.median(values) for name, values in times.items()}
    print(f"{args.model}, R400 at 95 km/h, dt 5 ms, {args.runs} runs each; load {os.getloadavg()[0]:.2f}")
    print(f"  the check: {sentence}")
    for name, values in times.items():
        print(f"  {name:8s} median {medians[name]:.3f} s CPU  (runs {', '.join(f'{v:.3f}' for v in values)})")
    ratio = medians["checked"] / medians["single"]
    if ratio > TARGET:
        print("TARGET MISSED")
    print(f"ratio_vs_baseline={ratio:.3f} target={TARGET}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
