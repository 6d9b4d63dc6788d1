#!/usr/bin/env python3
"""``express eigen`` on long trains (issue 24): the command against a named baseline.

Run from the repository root::

    PYTHONPATH=src python3 benchmarks/bench_train_eigen.py                 # 20 cars, ~3 min
    PYTHONPATH=src python3 benchmarks/bench_train_eigen.py --cars 100 --runs 1   # long (eig alone: minutes)

For every train (``examples/make_vehicles.py --cars N``):

* ``express eigen TRAIN --speed 100``, a fresh process per start, warm cache (each tree
  fills its own cache folder first, untimed), wall clock; medians of ``--runs`` starts,
  the two trees taking turns so that a change of load hits them alike:

  - **baseline**: the source tree of ``--baseline`` (default ``78517b5``, main before
    this work: the modes named one by one with Python dictionaries, the eigenvalues
    computed twice), extracted with ``git archive``;
  - **this tree**: ``src/``.

  Whether the two printed tables are identical is printed too.
* in one process of this tree (medians of ``--runs``, taking turns): ``eig`` of ``A``
  on one and on two BLAS threads (and whether their eigenvalues are the same bits),
  and :func:`express.analysis.modes.modes.modes_of` (the modes' names, energies and dominant
  DOFs).

The last line is ``eigen_s=<this tree, largest train> baseline_s=<...> ratio=<...>``.
"""

from __future__ import annotations

import argparse
import datetime
import os
import platform
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from machine import cpu_name, usable_cores  # benchmarks/machine.py

ROOT = Path(__file__).resolve().parents[1]
BASELINE = "78517b5"
SPEED_KMH = "100"


def _environment(source: Path, cache: Path) -> dict[str, str]:
    environment = dict(os.environ)
    environment["PYTHONPATH"] = str(source)
    environment["EXPRESS_CACHE_DIR"] = str(cache)
    for name in ("EXPRESS_NO_CACHE", "PYTHONDONTWRITEBYTECODE", "EXPRESS_BLAS_THREADS"):
        environment.pop(name, None)
    return environment


def _eigen(source: Path, cache: Path, train: Path) -> tuple[float, str]:
    """Wall time [s] and standard output of one ``express eigen`` start."""
    start = time.perf_counter()
    done = subprocess.run([sys.executable, "-m", "express", "eigen", str(train), "--speed", SPEED_KMH],
                          env=_environment(source, cache), capture_output=True, text=True, check=False)
    wall = time.perf_counter() - start
    if done.returncode != 0:
        raise SystemExit(f"express eigen failed ({source}):\n{done.stderr}")
    return wall, done.stdout


def _warm(source: Path, cache: Path, train: Path) -> None:
    code = f"from express.numeric.statespace import load_vehicle\nload_vehicle({str(train)!r})\n"
    subprocess.run([sys.executable, "-c", code], env=_environment(source, cache), check=True)


_IN_PROCESS = """
import json, statistics, sys, time
import numpy as np
from express.analysis.modes.modes import modes_of
from express.base.threads import blas_threads
from express.numeric.statespace import load_vehicle

vehicle = load_vehicle(sys.argv[1])
speed = float(sys.argv[2]) / 3.6
runs = int(sys.argv[3])
a = vehicle.state_matrix(speed)
times = {"eig, 1 BLAS thread": [], "eig, 2 BLAS threads": [], "modes_of": []}
results = {}
for _ in range(runs):
    for threads in (1, 2):
        with blas_threads(threads):
            start = time.perf_counter(); results[threads] = np.linalg.eig(a)
            times[f"eig, {threads} BLAS thread{'s' if threads > 1 else ''}"].append(time.perf_counter() - start)
    with blas_threads():
        start = time.perf_counter(); modes = modes_of(vehicle, *results[1], speed=speed)
        times["modes_of"].append(time.perf_counter() - start)
print(json.dumps({"states": a.shape[0], "modes": len(modes),
                  "same_bits": bool(np.array_equal(results[1][0], results[2][0])),
                  "medians": {name: statistics.median(values) for name, values in times.items()}}))
"""


def _breakdown(cache: Path, train: Path, runs: int) -> dict:
    import json

    done = subprocess.run([sys.executable, "-c", _IN_PROCESS, str(train), SPEED_KMH, str(runs)],
                          env=_environment(ROOT / "src", cache), capture_output=True, text=True, check=True)
    return json.loads(done.stdout.strip().splitlines()[-1])


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--cars", type=int, action="append", help="train length (repeatable; default 20)")
    parser.add_argument("--runs", type=int, default=3, help="starts per tree and train (median)")
    parser.add_argument("--baseline", default=BASELINE, help="git commit of the baseline tree")
    arguments = parser.parse_args()
    cars = arguments.cars or [20]
    print(f"{datetime.datetime.now(datetime.UTC):%Y-%m-%d %H:%M} UTC, {cpu_name()}, {usable_cores()} usable cores, "
          f"Python {platform.python_version()}; load average {os.getloadavg()[0]:.1f}")
    summary = ""
    with tempfile.TemporaryDirectory(prefix="bench-train-eigen-") as folder:
        work = Path(folder)
        baseline = work / "baseline"
        baseline.mkdir()
        archive = subprocess.run(["git", "-C", str(ROOT), "archive", arguments.baseline, "src"],
                                 capture_output=True, check=True).stdout
        subprocess.run(["tar", "-x", "-C", str(baseline)], input=archive, check=True)
        trees = {f"baseline {arguments.baseline}": baseline / "src", "this tree": ROOT / "src"}
        for count in cars:
            train = work / f"train{count}.toml"
            subprocess.run([sys.executable, str(ROOT / "examples" / "make_vehicles.py"), "--cars", str(count),
                            "-o", str(train)], check=True, capture_output=True)
            caches = {name: work / f"cache-{index}" for index, name in enumerate(trees)}
            for name, source in trees.items():
                _warm(source, caches[name], train)
            walls: dict[str, list[float]] = {name: [] for name in trees}
            tables: dict[str, str] = {}
            for _ in range(arguments.runs):
                for name, source in trees.items():
                    wall, tables[name] = _eigen(source, caches[name], train)
                    walls[name].append(wall)
            medians = {name: statistics.median(values) for name, values in walls.items()}
            base, new = medians[f"baseline {arguments.baseline}"], medians["this tree"]
            print(f"\n{count}-car train, express eigen --speed {SPEED_KMH} (warm cache, wall, median of "
                  f"{arguments.runs}; load average now {os.getloadavg()[0]:.1f}):")
            for name, value in medians.items():
                print(f"  {name:<20} {value:8.2f} s   (runs: {', '.join(f'{v:.2f}' for v in walls[name])})")
            print(f"  ratio baseline / this tree: {base / new:.2f}x; printed tables identical: "
                  f"{len(set(tables.values())) == 1}")
            parts = _breakdown(caches["this tree"], train, arguments.runs)
            print(f"  this tree in one process ({parts['states']} states, {parts['modes']} modes), medians "
                  f"(eigenvalues of 1 and 2 threads the same bits: {parts['same_bits']}):")
            for name, value in parts["medians"].items():
                print(f"    {name:<36} {value:8.2f} s")
            summary = f"eigen_s={new:.2f} baseline_s={base:.2f} ratio={base / new:.2f}"
    print(summary)
    return 0


if __name__ == "__main__":
    sys.exit(main())
