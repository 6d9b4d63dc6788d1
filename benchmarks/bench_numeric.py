#!/usr/bin/env python3
"""Numeric benchmark: frf and eigenvalue sweeps against plain NumPy, and re-evaluation.

Run from the repository root::

    PYTHONPATH=src python3 benchmarks/bench_numeric.py            # ~1 min
    PYTHONPATH=src python3 benchmarks/bench_numeric.py --quick    # ~20 s

Unlike the other benchmark scripts this one does NOT pin BLAS to one thread through the
environment: the library limits its own BLAS threads (``express.base.threads``), and that is
part of what is measured.  The plain-NumPy baselines are timed twice, with the default
BLAS threads (what a user's loop gets) and inside ``threadpool_limits(1)`` (the best a
plain loop can do here); the ratio is taken against the faster of the two.

Measured (medians of ``--runs`` runs after one warm-up run, garbage collector off;
baselines in the same process, on the same numeric matrices):

1. ``frequency_response`` at 200 (and 2000) frequencies 0.1..20 Hz (the paper's Fig. 10: lateral
   alignment, delays between wheelsets, floor outputs).  Baseline: a plain loop of
   ``numpy.linalg.solve(-w^2 M + i w C + K, (P + i w Pd) U)`` per frequency.
2. An eigenvalue sweep: ``root_locus`` at 400 speeds 5..500 km/h (100 for the train).  Baseline: a loop of
   ``numpy.linalg.eigvals(vehicle.state_matrix(v))``.  Besides the two models below, the
   sweep also runs on the conventional car (20 DOFs) and the Manchester 3-D car (31 DOFs),
   whose state matrices split into diagonal blocks (``express.numeric.compiled.EigenBlocks``: 34 + 6
   and 42 + 20 states); the blocks of each model are printed.
3. ``VehicleModel.with_values`` (one conicity; one car-body mass, which moves the wheel
   load and the creep coefficients through the parameter graph).  Baseline: a fresh
   ``vehicle_model(express.model.parameters.with_values(model, changes))`` (regeneration).
   The arrays of both are compared exactly.

Models: the forced-steering car (24 DOFs) and a 5-car train of it (120 DOFs), written by
``examples/make_vehicles.py`` (one block each).  ``--eig`` runs the eigenvalue sweeps only.  Targets: frf and eigenvalue sweeps at least as fast as
their plain baselines (ratio <= 1).  The last line is
``frf_ratio=<x> eig_ratio=<y> with_values_ms=<z>`` (ratios: EXPRESS time / baseline time,
worst over the models).  Exit code 0 even when a target is missed (``TARGET MISSED``).
"""

from __future__ import annotations

import argparse
import datetime
import gc
import importlib.util
import os
import platform
import statistics
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from threadpoolctl import threadpool_info, threadpool_limits

from machine import cpu_name, usable_cores  # benchmarks/machine.py

ROOT = Path(__file__).resolve().parents[1]
if str(ROOT / "src") not in sys.path:
    sys.path.insert(0, str(ROOT / "src"))

FREQUENCIES = (0.1, 20.0, 200)
SPEEDS_KMH = (5.0, 500.0, 400)


def median_time(function, runs: int) -> tuple[float, object]:
    """Median wall time [s] of ``runs`` calls after one warm-up call (GC off while timing)."""
    result = function()
    times = []
    for _ in range(runs):
        gc.collect()
        gc.disable()
        try:
            start = time.perf_counter()
            result = function()
            times.append(time.perf_counter() - start)
        finally:
            gc.enable()
    return statistics.median(times), result


def _one_thread(function):
    def limited():
        with threadpool_limits(limits=1, user_api="blas"):
            return function()

    return limited


def compare(ours, plain, runs: int) -> tuple[float, float, float, object, object]:
    """Medians of EXPRESS and of the plain baseline (default threads, one thread), the
    three timed in turn (round robin) so that a change of load hits them alike."""
    functions = {"ours": ours, "default": plain, "single": _one_thread(plain)}
    results = {name: function() for name, function in functions.items()}  # warm-up
    times: dict[str, list[float]] = {name: [] for name in functions}
    for _ in range(runs):
        for name, function in functions.items():
            gc.collect()
            gc.disable()
            try:
                start = time.perf_counter()
                results[name] = function()
                times[name].append(time.perf_counter() - start)
            finally:
                gc.enable()
    medians = {name: statistics.median(values) for name, values in times.items()}
    return medians["ours"], medians["default"], medians["single"], results["ours"], results["default"]


def train_model(cars: int, directory: Path):
    from express.io import load_model

    spec = importlib.util.spec_from_file_location("make_vehicles", ROOT / "examples" / "make_vehicles.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    path = directory / f"train{cars}.toml"
    path.write_text(module.vehicle_toml(True, cars=cars), encoding="utf-8")
    return load_model(path)


def frf_loop(vehicle, frequencies: np.ndarray, amplitude: float = 1e-3) -> np.ndarray:
    """The plain baseline: one complex solve per frequency on the same numeric matrices."""
    v = vehicle.speed
    columns = [vehicle.inputs.index(name) for name in vehicle.layout.irregularity]
    mass, damping, stiffness = vehicle.mass, vehicle.damping(v), vehicle.stiffness
    forcing, rate = vehicle.forcing(v)[:, columns], vehicle.forcing_rate(v)[:, columns]
    stations = np.array([w.station for w in vehicle.wheelsets])
    delays = (stations.max() - stations) / v
    rows = []
    for f in frequencies:
        w = 2.0 * np.pi * f
        u = amplitude * np.exp(-1j * w * delays)
        rows.append(np.linalg.solve(-w * w * mass + 1j * w * damping + stiffness, (forcing + 1j * w * rate) @ u))
    return np.array(rows)


def eig_loop(vehicle, speeds: np.ndarray) -> np.ndarray:
    return np.array([np.linalg.eigvals(vehicle.state_matrix(v)) for v in speeds])


def report(name: str, ours: float, default: float, single: float, target: bool) -> float:
    best = min(default, single)
    ratio = ours / best
    status = "" if not target or ratio <= 1.0 else "   TARGET MISSED"
    print(f"  {name:42s} EXPRESS {ours * 1e3:8.2f} ms | plain NumPy {default * 1e3:8.2f} ms (default threads), "
          f"{single * 1e3:8.2f} ms (1 thread) | ratio {ratio:.2f}{status}")
    return ratio


def _route(vehicle, frequencies: np.ndarray) -> str:
    """The route ``frequency_response`` takes (``express.analysis.frequency.banded.choose_route``)."""
    from express.analysis.frequency.banded import band_layout, choose_route

    layout = band_layout(vehicle.mass, vehicle.damping(vehicle.speed), vehicle.stiffness)
    route = choose_route(vehicle.n, vehicle.form.size, frequencies.size, layout)
    return {"schur": "Schur form", "stacked": "stacked solve", "banded": "banded LU"}.get(route, route)


def bench_frf(vehicle, label: str, runs: int) -> float:
    from express.analysis.frequency.frequency import frequency_response

    ratio = 0.0
    for count in (FREQUENCIES[2], 10 * FREQUENCIES[2]):
        frequencies = np.linspace(FREQUENCIES[0], FREQUENCIES[1], count)
        ours, default, single, result, plain = compare(
            lambda f=frequencies: frequency_response(vehicle, f), lambda f=frequencies: frf_loop(vehicle, f), runs
        )
        difference = np.abs(result.X - plain).max() / np.abs(plain).max()
        route = _route(vehicle, frequencies)
        measured = report(f"frf, {count} frequencies, {label}", ours, default, single, count == FREQUENCIES[2])
        print(f"  {'':42s} route: {route}; largest difference {difference:.1e} of the largest amplitude")
        if count == FREQUENCIES[2]:
            ratio = measured
    return ratio


def bench_eig(vehicle, label: str, runs: int) -> float:
    from express.analysis.stability.stability import root_locus

    small = vehicle.n < 60
    count = SPEEDS_KMH[2] if small else SPEEDS_KMH[2] // 4
    speeds = np.linspace(SPEEDS_KMH[0], SPEEDS_KMH[1], count) / 3.6
    ours, default, single, locus, plain = compare(
        lambda: root_locus(vehicle, speeds), lambda: eig_loop(vehicle, speeds), runs if small else min(runs, 3)
    )
    worst = 0.0
    for k in range(0, speeds.size, max(1, speeds.size // 7)):
        distance = np.abs(plain[k][:, None] - locus[k][None, :]).min(axis=1)  # compared as sets
        worst = max(worst, float(np.max(distance / np.maximum(np.abs(plain[k]), 1.0))))
    ratio = report(f"eigenvalue sweep, {speeds.size} speeds, {label}", ours, default, single, True)
    blocks = " + ".join(str(block.size) for block in vehicle.eigen_blocks.blocks)
    print(f"  {'':42s} eigenvalues agree to {worst:.1e} (relative, 7 speeds); diagonal blocks {blocks} states")
    return ratio


def bench_with_values(vehicle, model, label: str, runs: int) -> float:
    from express.model.parameters import with_values
    from express.numeric.statespace import vehicle_model

    worst = 0.0
    for changes in ({"Gamma": 0.2}, {"mc": 33000.0}):
        ours, changed = median_time(lambda changes=changes: vehicle.with_values(changes), runs)
        fresh_runs = max(1, min(3, runs))
        regenerate, fresh = median_time(lambda changes=changes: vehicle_model(with_values(model, changes)), fresh_runs)
        same = all(
            np.array_equal(getattr(changed, name), getattr(fresh, name))
            for name in ("mass", "stiffness", "damping_base", "damping_creep", "forcing_base", "forcing_speed2")
        ) and changed.wheelsets == fresh.wheelsets
        text = ", ".join(f"{k}={v:g}" for k, v in changes.items())
        print(f"  with_values({text}), {label}: {ours * 1e3:.2f} ms | regenerate {regenerate * 1e3:.0f} ms | "
              f"ratio {ours / regenerate:.4f} | arrays identical: {same}")
        worst = max(worst, ours)
    return worst


def machine() -> str:
    import scipy
    import sympy

    blas = ", ".join(f"{p['internal_api']} {p['version']} ({p['num_threads']} threads)"
                     for p in threadpool_info() if p["user_api"] == "blas")
    try:
        load = ", ".join(f"{x:.2f}" for x in os.getloadavg())
    except OSError:
        load = "?"
    return (f"date        {datetime.datetime.now().isoformat(timespec='seconds')}\n"
            f"python      {platform.python_version()}; numpy {np.__version__}, scipy {scipy.__version__}, "
            f"sympy {sympy.__version__}\n"
            f"cpu         {cpu_name()}; usable cores {usable_cores()}; load average {load}\n"
            f"blas        {blas}; EXPRESS_BLAS_THREADS={os.environ.get('EXPRESS_BLAS_THREADS', '(unset: 1)')}")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="3 runs, the car only")
    parser.add_argument("--runs", type=int, default=None, help="timed runs per figure (default 9, --quick 3)")
    parser.add_argument("--eig", action="store_true", help="the eigenvalue sweeps only")
    args = parser.parse_args(argv)
    runs = args.runs or (3 if args.quick else 9)

    from express.io import load_model
    from express.numeric.statespace import vehicle_model

    print("EXPRESS numeric benchmark" + (" (--quick)" if args.quick else ""))
    print(machine())
    models = {"car (24 DOFs)": load_model(ROOT / "examples" / "forced-steering.toml")}
    with tempfile.TemporaryDirectory() as directory:
        if not args.quick:
            models["5-car train (120 DOFs)"] = train_model(5, Path(directory))
        vehicles = {}
        for label, model in models.items():
            start = time.perf_counter()
            vehicles[label] = vehicle_model(model)
            print(f"{label}: generated and compiled in {time.perf_counter() - start:.2f} s (not timed below)")
    sweep_only = {}
    for label, name in (("conventional car (20 DOFs)", "conventional.toml"), ("Manchester car (31 DOFs)", "manchester.toml")):
        sweep_only[label] = vehicle_model(load_model(ROOT / "examples" / name))
    frf_ratio = eig_ratio = 0.0
    with_values_ms = float("nan")
    if not args.eig:
        print("\n== 1. frf")
        for label, vehicle in vehicles.items():
            frf_ratio = max(frf_ratio, bench_frf(vehicle, label, runs))
    print("\n== 2. eigenvalue sweep")
    for label, vehicle in {**vehicles, **sweep_only}.items():
        eig_ratio = max(eig_ratio, bench_eig(vehicle, label, runs))
    if not args.eig:
        print("\n== 3. re-evaluation")
        for label, vehicle in vehicles.items():
            worst = bench_with_values(vehicle, models[label], label, runs)
            if label.startswith("car"):
                with_values_ms = worst * 1e3
    missed = [name for name, ratio in (("frf", frf_ratio), ("eigenvalue sweep", eig_ratio)) if ratio > 1.0]
    if missed:
        print(f"\nTARGET MISSED: {', '.join(missed)} slower than plain NumPy")
    print(f"\nfrf_ratio={frf_ratio:.3f} eig_ratio={eig_ratio:.3f} with_values_ms={with_values_ms:.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
