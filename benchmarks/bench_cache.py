#!/usr/bin/env python3
"""Derivation-cache benchmark (issue 24): commands with a warm cache against ``--no-cache``.

Run from the repository root::

    PYTHONPATH=src python3 benchmarks/bench_cache.py              # ~5 min on a quiet machine
    PYTHONPATH=src python3 benchmarks/bench_cache.py --runs 3     # quicker
    PYTHONPATH=src python3 benchmarks/bench_cache.py --train 100  # the 100-car train too (long)

Every command is a fresh process, as a user starts it, timed wall clock and CPU (user +
system of the child: what a machine shared with other jobs changes least); medians of
``--runs`` starts, the three ways taking turns so that a change of load hits them alike:

* ``--no-cache``: derives everything (the named baseline, today's cost);
* cold: an empty cache folder each start (derives and stores: the cost of a first run);
* warm: the folder filled by an earlier start (reads the entry back).

Commands: ``eigen --speed 100``, ``critical-speed`` and ``frf --points 200`` on the
bundled forced-steering and Manchester cars and on the 37-coordinate 3-D coach with
series dampers (``tests/data/coach-series-dampers.toml``).  Targets: warm <= 0.5 s
each; cold <= 1.1 x ``--no-cache``.

Also: ``load_vehicle`` of a cached model in one process, after the imports (medians over
``--runs * 5`` loads with the in-process reuse cleared, so each reads the disk entries;
target <= 50 ms), and whether it imported SymPy (a warm load must not: it reads no model
records, ``src/express/numeric/warm.py``); the first-run Numba compilation (``express
conicity S1002 60E1``, whose kernels are compiled on first use, with an empty
``NUMBA_CACHE_DIR`` and then again with it filled).  With ``--train N``: an N-car train
(``examples/make_vehicles.py``), ``frf --points 50`` three ways and its warm
``load_vehicle`` (target: any command <= 3 s; ``eigen`` is left out: the dense
eigenvalue problem of a 4 800-state train alone takes minutes, cache or not).

The children run without ``PYTHONDONTWRITEBYTECODE``: an installed package has its
modules compiled, and a source tree compiles them on the first (untimed) start.

The last line is ``warm_max_s=<x> load_vehicle_ms=<y> cold_over_uncached=<r>``.
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
MODELS = {
    "forced-steering": ROOT / "examples" / "forced-steering.toml",
    "manchester": ROOT / "examples" / "manchester.toml",
    "coach (37 coordinates)": ROOT / "tests" / "data" / "coach-series-dampers.toml",
}
COMMANDS = {
    "eigen": ["eigen", "--speed", "100"],
    "critical-speed": ["critical-speed"],
    "frf": ["frf", "--points", "200"],
}
WARM_TARGET_S = 0.5
LOAD_TARGET_MS = 50.0
TRAIN_TARGET_S = 3.0
COLD_LIMIT = 1.10


def _environment(cache: Path) -> dict[str, str]:
    environment = dict(os.environ)
    environment["PYTHONPATH"] = str(ROOT / "src") + os.pathsep + environment.get("PYTHONPATH", "")
    environment["EXPRESS_CACHE_DIR"] = str(cache)
    environment.pop("EXPRESS_NO_CACHE", None)
    environment.pop("PYTHONDONTWRITEBYTECODE", None)  # compiled modules, as installed
    return environment


def _time(argv: list[str], environment: dict[str, str]) -> tuple[float, float]:
    """(wall, CPU) seconds of one start: CPU (user + system of the child) is what a loaded
    machine changes least."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    result = subprocess.run([sys.executable, "-m", "express", *argv], env=environment, capture_output=True, text=True)
    elapsed = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if result.returncode not in (0, 1):
        raise SystemExit(f"express {' '.join(argv)} failed ({result.returncode}): {result.stderr.strip()[-400:]}")
    return elapsed, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def _three_ways(argv: list[str], runs: int, scratch: Path) -> dict[str, tuple[float, float]]:
    """Medians of the (wall, CPU) times of --no-cache, cold and warm starts."""
    warm_folder = scratch / "warm"
    _time(argv, _environment(warm_folder))  # fill it
    times: dict[str, list[tuple[float, float]]] = {"uncached": [], "cold": [], "warm": []}
    for run in range(runs):
        times["uncached"].append(_time([*argv, "--no-cache"], _environment(scratch / "unused")))
        times["cold"].append(_time(argv, _environment(scratch / f"cold-{run}-{time.time_ns()}")))
        times["warm"].append(_time(argv, _environment(warm_folder)))
    return {way: (statistics.median(w for w, _ in found), statistics.median(c for _, c in found))
            for way, found in times.items()}


def _load_vehicle_ms(model: Path, runs: int, scratch: Path) -> tuple[float, bool]:
    """Median ms of a warm load_vehicle (after the imports), and whether SymPy was imported."""
    code = f"""
import os, statistics, sys, time
os.environ["EXPRESS_CACHE_DIR"] = {str(scratch / "load")!r}
from express.numeric import statespace, warm
statespace.load_vehicle({str(model)!r})
statespace._GENERATED.clear()
warm._READ.clear()
for module in [name for name in sys.modules if name == "sympy" or name.startswith("sympy.")]:
    del sys.modules[module]
loads = []
for _ in range({runs}):
    statespace._GENERATED.clear()
    warm._READ.clear()
    start = time.perf_counter(); statespace.load_vehicle({str(model)!r}); loads.append(time.perf_counter() - start)
print(statistics.median(loads) * 1e3, "sympy" in sys.modules)
"""
    result = subprocess.run([sys.executable, "-c", code], env=_environment(scratch / "load"), capture_output=True,
                            text=True, check=True)
    total, sympy = result.stdout.split()
    return float(total), sympy == "True"


def _numba_first_run(scratch: Path) -> tuple[tuple[float, float], tuple[float, float]]:
    environment = _environment(scratch / "numba-express")
    environment["NUMBA_CACHE_DIR"] = str(scratch / f"numba-{time.time_ns()}")
    argv = ["conicity", "S1002", "60E1", "--json"]
    return _time(argv, environment), _time(argv, environment)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--runs", type=int, default=5, help="starts per way (median)")
    parser.add_argument("--train", type=int, default=0, help="also a train of this many cars (examples/make_vehicles.py)")
    parser.add_argument("--no-numba", action="store_true", help="skip the first-run Numba compilation")
    args = parser.parse_args(argv)
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    print(f"# bench_cache {datetime.datetime.now(datetime.timezone.utc):%Y-%m-%d %H:%M} UTC; {cpu_name()}, "
          f"{usable_cores()} usable cores, load average {load:.1f}; Python {platform.python_version()}")
    models = dict(MODELS)
    with tempfile.TemporaryDirectory(prefix="bench-cache-") as folder:
        scratch = Path(folder)
        if args.train:
            train = scratch / f"train{args.train}.toml"
            subprocess.run([sys.executable, str(ROOT / "examples" / "make_vehicles.py"), "--cars", str(args.train),
                            "-o", str(train)], check=True, capture_output=True)
            models[f"train of {args.train} cars"] = train
        print(f"{'model':<24} {'command':<15} {'wall: --no-cache':>16} {'cold':>7} {'warm':>7} {'speed-up':>8} "
              f"{'cold/none':>9}  {'CPU: --no-cache':>15} {'cold':>7} {'warm':>7} {'speed-up':>8} {'cold/none':>9}")
        warm_max, cold_ratios, cold_cpu_ratios, warm_cpu_max, train_warm = 0.0, [], [], 0.0, None
        for label, model in models.items():
            train = label.startswith("train")
            commands = {"frf": ["frf", "--points", "50"]} if train else COMMANDS
            for name, command in commands.items():
                # a train's --no-cache and cold starts take minutes: one of each
                ways = _three_ways([command[0], str(model), *command[1:]], 1 if train else args.runs, scratch)
                (uncached, uncached_cpu), (cold, cold_cpu), (warm, warm_cpu) = ways["uncached"], ways["cold"], ways["warm"]
                if train:
                    train_warm = (warm, warm_cpu)
                else:
                    warm_max, warm_cpu_max = max(warm_max, warm), max(warm_cpu_max, warm_cpu)
                cold_ratios.append(cold / uncached)
                cold_cpu_ratios.append(cold_cpu / uncached_cpu)
                print(f"{label:<24} {name:<15} {uncached:16.3f} {cold:7.3f} {warm:7.3f} {uncached / warm:7.1f}x "
                      f"{cold / uncached:9.3f}  {uncached_cpu:15.3f} {cold_cpu:7.3f} {warm_cpu:7.3f} "
                      f"{uncached_cpu / warm_cpu:7.1f}x {cold_cpu / uncached_cpu:9.3f}", flush=True)
        loads = {label: _load_vehicle_ms(model, args.runs * 5 if label in MODELS else 1, scratch)
                 for label, model in models.items()}
        for label, (total, sympy) in loads.items():
            print(f"load_vehicle (cached) {label}: {total:.1f} ms{', imported SymPy' if sympy else ', no SymPy'}")
        if not args.no_numba:
            first, second = _numba_first_run(scratch)
            print(f"first run after installing (Numba kernels compiled, empty NUMBA_CACHE_DIR): "
                  f"express conicity S1002 60E1 {first[0]:.1f} s wall, {first[1]:.1f} s CPU; "
                  f"the second run {second[0]:.1f} s wall, {second[1]:.1f} s CPU")
    worst_load = max(total for label, (total, _) in loads.items() if label in MODELS)
    cold_median = statistics.median(cold_ratios)
    verdicts = [
        f"warm <= {WARM_TARGET_S} s: {'met' if warm_max <= WARM_TARGET_S else 'TARGET MISSED'} (worst {warm_max:.3f} s "
        f"wall, {warm_cpu_max:.3f} s CPU)",
        f"load_vehicle <= {LOAD_TARGET_MS:.0f} ms: {'met' if worst_load <= LOAD_TARGET_MS else 'TARGET MISSED'} "
        f"(worst {worst_load:.1f} ms)",
        f"cold <= {COLD_LIMIT} x --no-cache: {'met' if cold_median <= COLD_LIMIT else 'TARGET MISSED'} "
        f"(median ratio {cold_median:.3f} wall, {statistics.median(cold_cpu_ratios):.3f} CPU)",
    ]
    if train_warm is not None:
        verdicts.append(f"a command on the cached {args.train}-car train <= {TRAIN_TARGET_S} s: "
                        f"{'met' if train_warm[0] <= TRAIN_TARGET_S else 'TARGET MISSED'} (frf {train_warm[0]:.3f} s wall, "
                        f"{train_warm[1]:.3f} s CPU)")
    print("\n".join(verdicts))
    print(f"warm_max_s={warm_max:.3f} load_vehicle_ms={worst_load:.1f} cold_over_uncached={cold_median:.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
