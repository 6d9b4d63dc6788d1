#!/usr/bin/env python3
"""``frf``'s route for small models (issue 24): NumPy's stacked solve against the route
taken before the SciPy import was counted.

Run from the repository root::

    PYTHONPATH=src python3 benchmarks/bench_frf_route.py             # ~1 min
    PYTHONPATH=src python3 benchmarks/bench_frf_route.py --runs 9
    PYTHONPATH=src python3 benchmarks/bench_frf_route.py --train 20   # and a train's parts

Warm ``express frf MODEL --points 200`` (a cache folder filled by an earlier start) on the
bundled forced-steering and Manchester cars and the 37-coordinate coach
(``tests/data/coach-series-dampers.toml``), as fresh processes, two ways taking turns:

* **now**: ``express frf ...`` started as ``python -m express`` starts it (``runpy``, after
  importing this script, as the baseline does; the route by
  :func:`express.analysis.frequency.banded.choose_route`, which charges the 0.25 s SciPy import to the
  banded and Schur routes);
* **before** (the named baseline): the same command with the route chosen by the rule of
  before (no import charged: the Schur form from ``2 N`` frequencies on, the banded LU when
  its band halves a dense LU), reproduced here and patched into the child.

Medians of ``--runs`` starts, wall and CPU (user + system of the child), and whether the
child imported ``scipy.linalg``.  Then, in this process with SciPy loaded, the response
itself by each route (median of 20 calls, one BLAS thread as ``frf`` runs it) and the
largest difference between the old and the new route's amplitudes, relative to the largest
amplitude; and the import of ``scipy.linalg`` in a fresh interpreter after NumPy.

With ``--train N``: an N-car train (``examples/make_vehicles.py``), its warm ``frf --points
50`` in one process, part by part with one BLAS thread as the command runs them: the warm
``load_vehicle``, the stability check (``require_stable``: every eigenvalue of the dense
``A``) and the banded response; then the same dense eigenvalues with two BLAS threads.

The last line is ``warm_max_s=<x> ratio_max=<r>`` (now / before, wall).
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

from bench_cache import _environment  # the children's environment: a cache folder, compiled modules
from machine import cpu_name, usable_cores  # benchmarks/machine.py

ROOT = Path(__file__).resolve().parents[1]
MODELS = {
    "forced-steering": ROOT / "examples" / "forced-steering.toml",
    "manchester": ROOT / "examples" / "manchester.toml",
    "coach (37 coordinates)": ROOT / "tests" / "data" / "coach-series-dampers.toml",
}
POINTS = 200
TARGET_S = 0.4

def before(n: int, states: int, frequencies: int, layout) -> str:
    """The route rule of before (no SciPy import charged), patched into the ``before`` child."""
    from express.analysis.frequency import banded

    per_call, per_operation = banded._PER_CALL, banded._PER_OPERATION
    schur = banded._SCHUR_OPERATION * 10.0 * states**3 + frequencies * (per_call + per_operation * states**2)
    if layout.work < n**3 / 6.0:
        solves = frequencies * (per_call + per_operation * layout.work)
        return "schur" if schur < solves else "banded"
    return "schur" if frequencies >= 2 * states else "stacked"


_CHILD = """
import runpy, sys
{patch}
sys.argv = ["express", *{argv!r}]
try:
    runpy.run_module("express", run_name="__main__", alter_sys=True)
finally:
    sys.stderr.write("scipy.linalg loaded: %s\\n" % ("scipy.linalg" in sys.modules))
"""


def _start(command: list[str], environment: dict[str, str]) -> tuple[float, float, str]:
    """(wall, CPU) seconds of one start and its standard error."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    result = subprocess.run(command, env=environment, capture_output=True, text=True)
    elapsed = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if result.returncode != 0:
        raise SystemExit(f"{' '.join(command)} failed ({result.returncode}): {result.stderr.strip()[-400:]}")
    return elapsed, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime), result.stderr


def _commands(model: Path) -> dict[str, list[str]]:
    argv = ["frf", str(model), "--points", str(POINTS)]
    load = f"sys.path.insert(0, {str(Path(__file__).parent)!r})\nimport bench_frf_route\n"  # both ways alike
    patch = load + "import express.analysis.frequency.banded\nexpress.analysis.frequency.banded.choose_route = bench_frf_route.before\n"
    return {
        "now": [sys.executable, "-c", _CHILD.format(patch=load, argv=argv)],
        "before": [sys.executable, "-c", _CHILD.format(patch=patch, argv=argv)],
    }


def _scipy_import_s(runs: int) -> float:
    code = "import time, numpy; t = time.perf_counter(); import scipy.linalg; print(time.perf_counter() - t)"
    return statistics.median(float(subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                                                  check=True).stdout) for _ in range(runs))


def _in_process(model: Path, cache: Path) -> tuple[str, str, dict[str, float], float]:
    """(route now, route before, median seconds of the response by each, largest relative
    difference between the two routes' amplitudes)."""
    import numpy as np

    os.environ["EXPRESS_CACHE_DIR"] = str(cache)
    from express.analysis.frequency.banded import band_layout, choose_route
    from express.analysis.frequency.frequency import irregularity_delays, steady_response
    from express.base.threads import blas_threads
    from express.numeric.statespace import load_vehicle

    vehicle = load_vehicle(model)
    frequencies = np.geomspace(0.1, 20.0, POINTS)
    columns = [vehicle.inputs.index(name) for name in vehicle.layout.irregularity]
    delays = irregularity_delays(vehicle, vehicle.speed)
    amplitudes = 1e-3 * np.exp(-2j * np.pi * frequencies[:, None] * delays[None, :])[:, :, None]
    layout = band_layout(vehicle.mass, vehicle.damping(vehicle.speed), vehicle.stiffness)
    now = choose_route(vehicle.n, vehicle.form.size, POINTS, layout)
    old = before(vehicle.n, vehicle.form.size, POINTS, layout)
    times, results = {}, {}
    with blas_threads(1):
        for route in ("stacked", "banded", "schur"):
            found = []
            for _ in range(20):
                start = time.perf_counter()
                results[route] = steady_response(vehicle, frequencies, vehicle.speed, columns, amplitudes, route=route)
                found.append(time.perf_counter() - start)
            times[route] = statistics.median(found)
    difference = float(np.abs(results[now] - results[old]).max() / np.abs(results[old]).max())
    return now, old, times, difference


def _train_parts(cars: int, cache: Path) -> None:
    """Print the parts of a warm ``frf --points 50`` of a ``cars``-car train."""
    import numpy as np

    os.environ["EXPRESS_CACHE_DIR"] = str(cache)
    from express.analysis.frequency.banded import band_layout, choose_route
    from express.analysis.frequency.frequency import irregularity_delays, require_stable, steady_response
    from express.base.threads import blas_threads
    from express.numeric.statespace import load_vehicle

    train = cache / f"train{cars}.toml"
    subprocess.run([sys.executable, str(ROOT / "examples" / "make_vehicles.py"), "--cars", str(cars), "-o", str(train)],
                   check=True, capture_output=True)
    start = time.perf_counter()
    load_vehicle(train)  # derives and stores (untimed)
    derived = time.perf_counter() - start
    from express.numeric import statespace, warm

    statespace._GENERATED.clear()
    warm._READ.clear()
    start = time.perf_counter()
    vehicle = load_vehicle(train)
    loaded = time.perf_counter() - start
    speed = 100 / 3.6
    frequencies = np.geomspace(0.1, 20.0, 50)
    columns = [vehicle.inputs.index(name) for name in vehicle.layout.irregularity]
    delays = irregularity_delays(vehicle, speed)
    amplitudes = 1e-3 * np.exp(-2j * np.pi * frequencies[:, None] * delays[None, :])[:, :, None]
    layout = band_layout(vehicle.mass, vehicle.damping(speed), vehicle.stiffness)
    route = choose_route(vehicle.n, vehicle.form.size, frequencies.size, layout)
    with blas_threads(1):
        start = time.perf_counter()
        require_stable(vehicle, speed)
        check = time.perf_counter() - start
        start = time.perf_counter()
        steady_response(vehicle, frequencies, speed, columns, amplitudes)
        response = time.perf_counter() - start
    a = vehicle.state_matrix(speed)
    with blas_threads(2):
        start = time.perf_counter()
        np.linalg.eigvals(a)
        two = time.perf_counter() - start
    print(f"train of {cars} cars ({vehicle.n} DOFs, {vehicle.form.size} states; derived in {derived:.1f} s): warm "
          f"load_vehicle {loaded:.2f} s; stability check {check:.2f} s (1 BLAS thread); the response ({route} "
          f"route, 50 frequencies) {response:.2f} s; the check's dense eigenvalues with 2 BLAS threads (as frf runs "
          f"them from 1000 states, large_problem_threads) {two:.2f} s")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--runs", type=int, default=5, help="starts per way (median)")
    parser.add_argument("--train", type=int, default=0, help="also the parts of a train of this many cars")
    args = parser.parse_args(argv)
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    print(f"# bench_frf_route {datetime.datetime.now(datetime.timezone.utc):%Y-%m-%d %H:%M} UTC; {cpu_name()}, "
          f"{usable_cores()} usable cores, load average {load:.1f}; Python {platform.python_version()}")
    warm_max, ratios = 0.0, []
    with tempfile.TemporaryDirectory(prefix="bench-frf-route-") as folder:
        cache = Path(folder)
        environment = _environment(cache)
        print(f"warm frf --points {POINTS}: medians of {args.runs} starts each, taking turns")
        print(f"{'model':<24} {'wall: before':>12} {'now':>7} {'now/before':>10}  {'CPU: before':>11} {'now':>7} "
              f"{'now/before':>10}  scipy.linalg imported (before, now)")
        for label, model in MODELS.items():
            commands = _commands(model)
            _start(commands["now"], environment)  # fills the cache, compiles the modules
            found: dict[str, list[tuple[float, float, str]]] = {"before": [], "now": []}
            for _ in range(args.runs):
                for way, command in commands.items():
                    found[way].append(_start(command, environment))
            wall = {way: statistics.median(w for w, _, _ in runs) for way, runs in found.items()}
            cpu = {way: statistics.median(c for _, c, _ in runs) for way, runs in found.items()}
            loaded = {way: "scipy.linalg loaded: True" in runs[-1][2] for way, runs in found.items()}
            warm_max = max(warm_max, wall["now"])
            ratios.append(wall["now"] / wall["before"])
            print(f"{label:<24} {wall['before']:12.3f} {wall['now']:7.3f} {wall['now'] / wall['before']:10.2f}  "
                  f"{cpu['before']:11.3f} {cpu['now']:7.3f} {cpu['now'] / cpu['before']:10.2f}  "
                  f"{loaded['before']}, {loaded['now']}", flush=True)
        print(f"import scipy.linalg after numpy, fresh interpreter: {_scipy_import_s(args.runs):.3f} s (median)")
        print("the response alone, in-process (SciPy loaded, 1 BLAS thread), median of 20 calls:")
        for label, model in MODELS.items():
            now, old, times, difference = _in_process(model, cache)
            spent = ", ".join(f"{route} {seconds * 1e3:.1f} ms" for route, seconds in times.items())
            print(f"  {label:<24} before: {old}, now: {now}; {spent}; largest difference {difference:.1e} "
                  "of the largest amplitude")
        if args.train:
            _train_parts(args.train, cache)
    verdict = "met" if warm_max <= TARGET_S else "TARGET MISSED"
    print(f"warm frf <= {TARGET_S} s: {verdict} (worst {warm_max:.3f} s wall)")
    print(f"warm_max_s={warm_max:.3f} ratio_max={max(ratios):.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
