#!/usr/bin/env python3
"""Every command on a cached long train (issue 24: "any command on a cached 100-car train
<= 3 s"), each a fresh process, wall clock and CPU (user + system of the child).

Run from the repository root::

    PYTHONPATH=src python3 benchmarks/bench_train100.py               # 100 cars: ~15 min
    PYTHONPATH=src python3 benchmarks/bench_train100.py --cars 20     # quicker
    PYTHONPATH=src python3 benchmarks/bench_train100.py --only generate,export-npz

The train is ``examples/make_vehicles.py --cars N`` (N forced-steering cars coupled by
couplers: 24 N DOFs, 48 N states).  The script fills a private cache folder first (the
cold ``load_vehicle``, a few minutes for 100 cars, and one cold run of each command that
keeps a product of its own: ``generate``, ``draw``), then runs every command ``--runs``
times warm (median).  The named baseline, in the same run: ``generate --format json``
with ``--no-cache`` (``--baseline``; it derives the readable matrices, minutes for
100 cars).  A command that needs the whole spectrum of the dense state matrix
(``eigen``, ``critical-speed``, ``frf``'s stability check) is bounded below by LAPACK's
dense eigenvalues, which the script times alone (``numpy.linalg.eigvals`` of ``A`` in
one process, two BLAS threads).

The last line is ``max_warm_s=<x> eigvals_s=<y>``.
"""

from __future__ import annotations

import argparse
import datetime
import os
import platform
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from machine import cpu_name, usable_cores  # benchmarks/machine.py

ROOT = Path(__file__).resolve().parents[1]


def commands(train: Path, out: Path) -> dict[str, list[str]]:
    """Every command of the command line that takes a model, as a user runs it."""
    return {
        "generate": ["generate", str(train), "--format", "json", "-o", str(out / "train.json")],
        "generate-matlab": ["generate", str(train), "--format", "matlab", "-o", str(out / "train.m")],
        "export-npz": ["export", str(train), "-o", str(out / "train.npz")],
        "export-mat": ["export", str(train), "-o", str(out / "train.mat")],
        "draw": ["draw", str(train), "-o", str(out / "train.png")],
        "simulate": ["simulate", str(train), "--linear", "-o", str(out / "run.csv")],
        "frf": ["frf", str(train), "--points", "50"],
        "eigen": ["eigen", str(train), "--speed", "100"],
        "critical-speed": ["critical-speed", str(train)],
        "curving": ["curving", str(train), "--radius", "600", "--cant", "100"],
    }


def run(argv: list[str], env: dict[str, str], timeout: float) -> tuple[float, float, int]:
    """``(wall, cpu, status)`` of ``python -m express argv`` (status -1: timed out)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    try:
        done = subprocess.run([sys.executable, "-m", "express", *argv], env=env, capture_output=True, text=True,
                              timeout=timeout)
        status = done.returncode
    except subprocess.TimeoutExpired:
        status = -1
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return wall, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime), status


def eigvals_seconds(train: Path, env: dict[str, str]) -> float:
    """LAPACK's dense eigenvalues of the train's A at 100 km/h, in a fresh process (the floor
    of the spectral commands)."""
    code = ("import time, numpy as np\nfrom express.numeric.statespace import load_vehicle\n"
            f"a = load_vehicle({str(train)!r}).state_matrix(100 / 3.6)\n"
            "t = time.perf_counter(); np.linalg.eigvals(a); print(time.perf_counter() - t)\n")
    done = subprocess.run([sys.executable, "-c", code], env={**env, "OPENBLAS_NUM_THREADS": "2"},
                          capture_output=True, text=True, timeout=3600)
    return float(done.stdout.split()[-1]) if done.returncode == 0 else float("nan")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--cars", type=int, default=100)
    parser.add_argument("--runs", type=int, default=3, help="warm runs of the quick commands (median)")
    parser.add_argument("--only", help="comma-separated command names")
    parser.add_argument("--timeout", type=float, default=900.0, help="per run [s]")
    parser.add_argument("--no-baseline", dest="baseline", action="store_false")
    args = parser.parse_args()
    work = Path(tempfile.mkdtemp(prefix="express-train-bench-"))
    train = work / f"train{args.cars}.toml"
    subprocess.run([sys.executable, str(ROOT / "examples" / "make_vehicles.py"), "--cars", str(args.cars), "-o", str(train)],
                   check=True, capture_output=True)
    env = {k: v for k, v in os.environ.items() if k not in ("EXPRESS_NO_CACHE", "PYTHONDONTWRITEBYTECODE")}
    env.update(EXPRESS_CACHE_DIR=str(work / "cache"), PYTHONPATH=str(ROOT / "src"), EXPRESS_COMPILE_NOTE="0")
    print(f"# {datetime.datetime.now(datetime.timezone.utc):%Y-%m-%d %H:%M} UTC, {cpu_name()}, {usable_cores()} cores, "
          f"load {os.getloadavg()[0]:.1f}, Python {platform.python_version()}; {args.cars} cars")
    wall, cpu, _ = run(["frf", str(train), "--points", "2"], env, 3600)
    print(f"filling the cache (cold frf --points 2): {wall:.1f} s wall, {cpu:.1f} s CPU")
    table = commands(train, work)
    chosen = args.only.split(",") if args.only else list(table)
    print(f"{'command':<16} {'runs':>4} {'wall s':>9} {'CPU s':>9}  status")
    worst = 0.0
    for name in chosen:
        argv = table[name]
        run(argv, env, args.timeout)  # untimed: the command's own products stored, modules compiled
        heavy = name in ("eigen", "critical-speed", "curving", "simulate", "frf")
        results = [run(argv, env, args.timeout) for _ in range(1 if heavy else args.runs)]
        wall = statistics.median(r[0] for r in results)
        cpu = statistics.median(r[1] for r in results)
        statuses = sorted({r[2] for r in results})
        worst = max(worst, wall)
        print(f"{name:<16} {len(results):>4} {wall:9.2f} {cpu:9.2f}  {statuses}", flush=True)
    if args.baseline:
        wall, cpu, status = run([*table["generate"], "--no-cache"], env, 3600)
        print(f"baseline generate --no-cache: {wall:.1f} s wall, {cpu:.1f} s CPU (status {status})")
    floor = eigvals_seconds(train, env)
    print(f"numpy.linalg.eigvals of the dense A alone: {floor:.1f} s (two BLAS threads)")
    print(f"max_warm_s={worst:.2f} eigvals_s={floor:.1f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
