#!/usr/bin/env python3
"""Simulation benchmark: curving run, critical speed and root locus against naive baselines.

Run from the repository root::

    PYTHONPATH=src python3 benchmarks/bench_simulate.py            # full run (~1-2 min)
    PYTHONPATH=src python3 benchmarks/bench_simulate.py --quick    # smoke test (~15 s)

Everything runs on ONE core: the BLAS/OpenMP thread counts are set to 1 before NumPy is
imported (unless already set in the environment).  On a shared machine a multithreaded
OpenBLAS makes the 144 x 144 matrix exponential of the discretization 10-100 times
slower and the timings meaningless.

Measured (every timing the median of ``--runs`` runs after one warm-up run; baselines in
the same process, same run):

1. The paper's curving run (``paper_curve()``: 460 m, R = 400 m, 95 mm cant, 120 km/h,
   about 13.8 s of travel) with flange contact and creep saturation, for the
   forced-steering and the conventional vehicle: wall time of the whole ``simulate()``
   call and the realtime factor ``travel time / wall time`` (target >= 1000).  The first
   call compiles the Numba kernels; by default Numba's cache is pointed to a fresh
   temporary directory so that this compile time is real and reported separately
   (``--numba-cache project`` keeps the project's cache).
2. Baseline: ``scipy.integrate.solve_ivp`` (RK45, rtol 1e-6, atol 1e-9) on
   ``continuous_rhs`` (the same equations as a plain ``f(t, x)``), sampled on the same
   time grid; ``Q1`` is recomputed from its solution with ``derived_outputs``.  Speedup =
   solve_ivp time / ``simulate`` median over the same span (target >= 20);
   ``q1_rel_diff`` = relative difference of the peak ``|Q1|`` (target <= 1 %).  With
   ``--quick`` the reference covers only the first 100 m.
3. Critical speed against conicity, 2 vehicles x 40 conicities in 0.02..0.4, with
   ``express.analysis.stability.stability.critical_speed_vs_conicity`` (target < 2 s for both).
   Baseline: regenerate ``vehicle_model(with_values(model, {"Gamma": g}))`` per conicity
   and scan the speed densely (1 km/h steps, largest real part of
   ``numpy.linalg.eigvals(A(v))``), on a few conicities, EXTRAPOLATED to 2 x 40.
4. A 1000-speed root locus of the 24-DOF forced-steering model with
   ``express.analysis.stability.stability.root_locus`` (target < 1 s).  Baseline: a loop building
   ``A(v)`` from scratch (``numpy.linalg.inv(M)`` each time) and calling
   ``scipy.linalg.eig`` (eigenvalues only).

5. The library's ``simulate()`` against the CLI's (issue 16): in a child process that
   keeps the default BLAS threads, ``simulate()`` called from Python (the library limits
   its own threads, ``express.base.threads``) against the same call under the CLI's thread
   setting (the baseline; target: ratio <= 1.25, i.e. as fast within the noise), and,
   for information, with the limit switched off (``EXPRESS_BLAS_THREADS=none``: how the
   library ran before) and the whole ``express simulate`` command in-process.

Items 3 and 4 are skipped (and said so) if ``express.analysis.stability.stability`` is missing.
The last line of the output is exactly
``realtime_factor=<x> speedup_vs_solve_ivp=<y> q1_rel_diff=<z>``.
Exit code 0 even when a target is missed (``TARGET MISSED`` is printed).
"""

from __future__ import annotations

import os

# one core, before NumPy / SciPy / Numba are imported
for _variable in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS", "NUMEXPR_NUM_THREADS",
                  "NUMBA_NUM_THREADS", "VECLIB_MAXIMUM_THREADS"):
    os.environ.setdefault(_variable, "1")

import argparse  # noqa: E402
import datetime  # noqa: E402
import gc  # noqa: E402
import json  # noqa: E402
import platform  # noqa: E402
import statistics  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402  (Numba and express are imported later, after NUMBA_CACHE_DIR is set)

from machine import cpu_name, usable_cores  # noqa: E402  (benchmarks/machine.py)

ROOT = Path(__file__).resolve().parents[1]
if str(ROOT / "src") not in sys.path:
    sys.path.insert(0, str(ROOT / "src"))

REALTIME_TARGET = 1000.0
SPEEDUP_TARGET = 20.0
Q1_TOLERANCE = 0.01
CRITICAL_TARGET_S = 2.0
ROOT_LOCUS_TARGET_S = 1.0
CONICITIES = (0.02, 0.4, 40)
LOCUS_SPEEDS_KMH = (5.0, 500.0, 1000)
SCAN_KMH = (1.0, 540.0)  # naive critical-speed scan, 1 km/h steps (540 km/h = the fast v_max 150 m/s)
MODELS = {"forced-steering": "examples/forced-steering.toml", "conventional": "examples/conventional.toml"}


def _median_time(function, runs: int) -> tuple[float, list[float], object]:
    """Median wall time of ``runs`` calls (garbage collector off while timing)."""
    times = []
    result = None
    for _ in range(runs):
        gc.collect()
        gc.disable()
        try:
            start = time.perf_counter()
            result = function()
            times.append(time.perf_counter() - start)
        finally:
            gc.enable()
    return statistics.median(times), times, result


def _fmt_times(times) -> str:
    return "[" + ", ".join(f"{t * 1e3:.1f}" for t in sorted(times)) + "] ms"


class Bench:
    def __init__(self, args):
        self.args = args
        self.lines: list[str] = []
        self.missed: list[str] = []
        self.realtime_factor = float("nan")
        self.speedup = float("nan")
        self.q1_rel_diff = float("nan")

    def check(self, ok: bool, what: str) -> str:
        if not ok:
            self.missed.append(what)
        return "ok" if ok else "MISSED"

    # ------------------------------------------------------------------ 1. curving run
    def curving(self, vehicles, track):
        from express.analysis.time.integrator import discretize
        from express.analysis.time.simulate import simulate, track_inputs

        args = self.args
        print(f"\n== 1. curving run: paper_curve() {track.length:.0f} m, flange contact and saturation, "
              f"dt 0.005 s, medians of {args.runs} runs")
        self.simulate_medians = {}
        for index, (name, vehicle) in enumerate(vehicles.items()):
            start = time.perf_counter()
            result = simulate(vehicle, track, progress=False)
            first = time.perf_counter() - start
            median, times, result = _median_time(lambda: simulate(vehicle, track, progress=False), args.runs)
            travel = float(result.time[-1])
            factor = travel / median
            self.simulate_medians[name] = (median, result)
            label = "first call (incl. Numba compile)" if index == 0 else "first call (kernels compiled)"
            print(f"{name:16s} n={vehicle.n} DOFs, {result.time.size - 1} steps, travel {travel:.2f} s at "
                  f"{vehicle.speed * 3.6:.0f} km/h")
            print(f"{'':16s} {label}: {first:.3f} s -> compile/first-call overhead {first - median:.3f} s")
            print(f"{'':16s} simulate() median {median * 1e3:.2f} ms {_fmt_times(times)}; "
                  f"realtime factor {factor:.0f} (target >= {REALTIME_TARGET:.0f}; "
                  f"{travel / min(times):.0f} for the fastest run)")
            peaks = result.max_abs()
            print(f"{'':16s} peak |Q1| {peaks['Q1'] / 1e3:.2f} kN, |Q2| {peaks['Q2'] / 1e3:.2f} kN, "
                  + (f"theta_L1 {peaks['theta_L1']:.4f} rad, " if "theta_L1" in peaks else "")
                  + f"psi_TW1 {peaks['psi_TW1'] * 1e3:.3f} mrad")
            if index == 0:
                self.realtime_factor = factor
                status = self.check(factor >= REALTIME_TARGET, f"realtime factor {factor:.0f} < {REALTIME_TARGET:.0f}")
                self.lines.append(f"curving run ({name}): {median * 1e3:.2f} ms, realtime factor {factor:.0f} "
                                  f"(target >= {REALTIME_TARGET:.0f}: {status})")
                # where the time goes (informative)
                v = vehicle.speed
                a = vehicle.state_matrix(v)
                t_exp, _, _ = _median_time(lambda: discretize(a, 0.005), args.runs)
                t_inp, _, _ = _median_time(lambda: track_inputs(vehicle, track, result.distance, v), args.runs)
                print(f"{'':16s} of which discretize (expm, {2 * vehicle.n}x{2 * vehicle.n} -> "
                      f"{6 * vehicle.n}x{6 * vehicle.n} block) {t_exp * 1e3:.2f} ms, "
                      f"track_inputs {t_inp * 1e3:.2f} ms")
            else:
                self.lines.append(f"curving run ({name}): {median * 1e3:.2f} ms, realtime factor {factor:.0f}")

    # ------------------------------------------------------------------ 2. solve_ivp
    def solve_ivp_baseline(self, name, vehicle, track):
        from scipy.integrate import solve_ivp

        from express.analysis.time.simulate import continuous_rhs, derived_outputs, simulate, track_inputs

        args = self.args
        end = 100.0 if args.quick else track.length
        span = "first 100 m" if args.quick else f"whole {track.length:.0f} m"
        print(f"\n== 2. baseline: solve_ivp RK45 (rtol 1e-6, atol 1e-9) on continuous_rhs, {name}, {span}")
        if args.quick or name not in self.simulate_medians:
            median, times, result = _median_time(lambda: simulate(vehicle, track, end=end, progress=False), args.runs)
        else:
            median, result = self.simulate_medians[name]
            times = None
        rhs = continuous_rhs(vehicle, track)
        x0 = np.zeros(2 * vehicle.n)
        ivp_times = []
        solution = None
        for _ in range(args.ivp_runs):
            start = time.perf_counter()
            solution = solve_ivp(rhs, (0.0, float(result.time[-1])), x0, method="RK45", rtol=1e-6, atol=1e-9,
                                 t_eval=result.time)
            ivp_times.append(time.perf_counter() - start)
        if not solution.success:
            print(f"solve_ivp failed: {solution.message}")
        ivp_time = statistics.median(ivp_times)
        n = vehicle.n
        states = solution.y.T
        inputs = track_inputs(vehicle, track, result.distance, vehicle.speed)
        reference = derived_outputs(vehicle, states[:, :n], states[:, n:], inputs, vehicle.speed)
        peak_ivp = float(np.max(np.abs(reference["Y1"])))
        peak_sim = float(np.max(np.abs(result.outputs["Y1"])))
        q1_rel_diff = abs(peak_sim - peak_ivp) / peak_ivp
        history = float(np.max(np.abs(result.outputs["Y1"] - reference["Y1"]))) / peak_ivp
        state_diff = float(np.max(np.abs(result.q - states[:, :n])))
        speedup = ivp_time / median
        print(f"solve_ivp: {ivp_time:.2f} s ({len(ivp_times)} run{'s' if len(ivp_times) > 1 else ''}: "
              + ", ".join(f"{t:.2f}" for t in ivp_times) + f" s), {solution.nfev} RHS evaluations")
        print(f"simulate(): {median * 1e3:.2f} ms over the same span"
              + (f" {_fmt_times(times)}" if times else " (median of section 1)"))
        print(f"speedup {speedup:.0f} (target >= {SPEEDUP_TARGET:.0f})")
        print(f"peak |Q1|: simulate {peak_sim:.1f} N, solve_ivp {peak_ivp:.1f} N, q1_rel_diff {q1_rel_diff:.2e} "
              f"(target <= {Q1_TOLERANCE:.0%}); max |Q1 difference| / peak {history:.2e}; "
              f"max |q difference| {state_diff:.2e} (m, rad)")
        self.speedup, self.q1_rel_diff = speedup, q1_rel_diff
        s1 = self.check(speedup >= SPEEDUP_TARGET, f"speedup vs solve_ivp {speedup:.0f} < {SPEEDUP_TARGET:.0f}")
        s2 = self.check(q1_rel_diff <= Q1_TOLERANCE, f"q1_rel_diff {q1_rel_diff:.2e} > {Q1_TOLERANCE}")
        self.lines.append(f"solve_ivp baseline ({span}): {ivp_time:.2f} s, speedup {speedup:.0f} "
                          f"(target >= {SPEEDUP_TARGET:.0f}: {s1}), q1_rel_diff {q1_rel_diff:.2e} (<= 1 %: {s2})")

    # ------------------------------------------------------------------ 3. critical speed
    def critical_speed(self, stability, vehicles, models):
        from express.model.parameters import with_values
        from express.numeric.statespace import vehicle_model

        args = self.args
        conicities = np.linspace(*CONICITIES)
        print(f"\n== 3. critical speed against conicity: 2 vehicles x {conicities.size} conicities in "
              f"{conicities[0]:g}..{conicities[-1]:g}, medians of {args.runs} runs")
        if stability is None or not hasattr(stability, "critical_speed_vs_conicity"):
            print("SKIPPED: express.analysis.stability.stability.critical_speed_vs_conicity is not available")
            self.lines.append("critical speed vs conicity: SKIPPED (no express.analysis.stability.stability)")
            return

        def both():
            return {name: stability.critical_speed_vs_conicity(vehicle, conicities) for name, vehicle in vehicles.items()}

        start = time.perf_counter()
        both()
        first = time.perf_counter() - start
        median, times, results = _median_time(both, args.runs)
        speeds = {name: _critical_speeds(result, conicities.size) for name, result in results.items()}
        print(f"critical_speed_vs_conicity, both vehicles: first call {first:.3f} s, median {median:.3f} s "
              f"{_fmt_times(times)} (target < {CRITICAL_TARGET_S:g} s)")
        for name, values in speeds.items():
            if values is not None:
                shown = ", ".join(f"{g:.3f}: {s * 3.6:.0f}" for g, s in zip(conicities[::8], values[::8]))
                at_min = sum(bool(getattr(item, "unstable_at_min", False)) for item in results[name])
                print(f"  {name:16s} km/h at conicity {shown}; unstable at the lowest speed for {at_min}, "
                      f"stable over the range for {int(np.isnan(values).sum())} of {values.size} conicities")
            else:
                print(f"  {name:16s} result of type {type(results[name]).__name__} (not compared)")
        # naive baseline on a few conicities
        picks = [conicities[i] for i in ((20,) if args.quick else (4, 20, 36))]
        scan = np.arange(SCAN_KMH[0], SCAN_KMH[1] + 0.5, 1.0)
        naive_times = []
        agreement = []
        for name, model in models.items():
            for index, g in enumerate(picks):
                start = time.perf_counter()
                vehicle = vehicle_model(with_values(model, {"Gamma": float(g)}))
                critical = _scan_critical(vehicle, scan / 3.6)
                naive_times.append(time.perf_counter() - start)
                fast = speeds.get(name)
                fast_value = float(fast[list(conicities).index(g)]) if fast is not None else float("nan")
                compared = np.isfinite(critical) and critical > scan[0] / 3.6  # not unstable at the lowest speed
                agreement.append(abs(fast_value - critical) * 3.6 if compared else float("nan"))
                print(f"  naive {name:16s} conicity {g:.3f}: {critical * 3.6:.0f} km/h "
                      f"(fast {fast_value * 3.6:.1f} km/h) in {naive_times[-1]:.2f} s")
        per = statistics.median(naive_times)
        extrapolated = per * 2 * conicities.size
        print(f"naive baseline: regenerate + 1 km/h scan {scan[0]:.0f}..{scan[-1]:.0f} km/h: {per:.2f} s per conicity "
              f"(median of {len(naive_times)}), EXTRAPOLATED to 2 x {conicities.size}: {extrapolated:.0f} s "
              f"-> speedup ~{extrapolated / median:.0f}")
        finite = [a for a in agreement if np.isfinite(a)]
        if finite:
            print(f"largest |fast - naive| at the checked conicities: {max(finite):.2f} km/h (scan step 1 km/h)")
        status = self.check(median < CRITICAL_TARGET_S, f"critical speed sweep {median:.2f} s >= {CRITICAL_TARGET_S} s")
        self.lines.append(f"critical speed 2 x {conicities.size} conicities: {median:.3f} s (target < "
                          f"{CRITICAL_TARGET_S:g} s: {status}); naive extrapolated {extrapolated:.0f} s")

    # ------------------------------------------------------------------ 4. root locus
    def root_locus(self, stability, vehicle):
        import scipy.linalg

        args = self.args
        speeds = np.linspace(*LOCUS_SPEEDS_KMH[:2], LOCUS_SPEEDS_KMH[2]) / 3.6
        print(f"\n== 4. root locus: {speeds.size} speeds {LOCUS_SPEEDS_KMH[0]:g}..{LOCUS_SPEEDS_KMH[1]:g} km/h, "
              f"{vehicle.n}-DOF model ({2 * vehicle.n} states), medians of {args.runs} runs")
        if stability is None or not hasattr(stability, "root_locus"):
            print("SKIPPED: express.analysis.stability.stability.root_locus is not available")
            self.lines.append("root locus: SKIPPED (no express.analysis.stability.stability)")
            return
        start = time.perf_counter()
        stability.root_locus(vehicle, speeds)
        first = time.perf_counter() - start
        median, times, result = _median_time(lambda: stability.root_locus(vehicle, speeds), args.runs)
        print(f"root_locus: first call {first:.3f} s, median {median:.3f} s {_fmt_times(times)} "
              f"(target < {ROOT_LOCUS_TARGET_S:g} s)")

        n = vehicle.n
        mass, stiffness, c0, c1 = vehicle.mass, vehicle.stiffness, vehicle.damping_base, vehicle.damping_creep

        def naive(v):
            m_inv = np.linalg.inv(mass)
            a = np.zeros((2 * n, 2 * n))
            a[:n, n:] = np.eye(n)
            a[n:, :n] = -m_inv @ stiffness
            a[n:, n:] = -m_inv @ (c0 + c1 / v)
            return scipy.linalg.eig(a, right=False)

        count = 200 if args.quick else speeds.size
        start = time.perf_counter()
        reference = [naive(v) for v in speeds[:count]]
        naive_time = (time.perf_counter() - start) * speeds.size / count
        label = f"EXTRAPOLATED from {count} speeds" if count < speeds.size else "measured once"
        print(f"naive loop (inv(M), A(v), scipy.linalg.eig): {naive_time:.2f} s for {speeds.size} speeds ({label}) "
              f"-> speedup {naive_time / median:.1f}")
        eigenvalues = _locus_eigenvalues(result, speeds.size)
        if eigenvalues is not None:
            worst = 0.0
            for k in np.linspace(0, count - 1, 7).astype(int):
                ours = np.asarray(eigenvalues[k])
                theirs = reference[k]
                distance = np.abs(theirs[:, None] - ours[None, :]).min(axis=1)
                worst = max(worst, float(np.max(distance / np.maximum(np.abs(theirs), 1.0))))
            print(f"agreement with scipy.linalg.eig at 7 speeds: max |d lambda| / max(|lambda|, 1) = {worst:.1e}")
        else:
            print(f"root_locus returned {type(result).__name__}: eigenvalues not compared")
        status = self.check(median < ROOT_LOCUS_TARGET_S, f"root locus {median:.2f} s >= {ROOT_LOCUS_TARGET_S} s")
        self.lines.append(f"root locus {speeds.size} speeds: {median:.3f} s (target < {ROOT_LOCUS_TARGET_S:g} s: "
                          f"{status}); naive {naive_time:.2f} s")

    # ------------------------------------------------------------------ 5. library against CLI
    def library_against_cli(self):
        """``simulate()`` called from Python against the CLI's, in a child process whose
        BLAS keeps its default threads (this script pins its own to one)."""
        args = self.args
        runs = max(args.runs, 5)
        print(f"\n== 5. the library's simulate() against the CLI's: forced-steering, paper_curve(), fresh process with "
              f"the default BLAS threads, medians of {runs} runs (library and CLI taking turns)")
        env = {k: v for k, v in os.environ.items() if not k.endswith("_NUM_THREADS") and k != "EXPRESS_BLAS_THREADS"}
        env["PYTHONPATH"] = os.pathsep.join([str(ROOT / "src"), env.get("PYTHONPATH", "")]).rstrip(os.pathsep)
        done = subprocess.run([sys.executable, "-c", _LIBRARY_AGAINST_CLI, str(ROOT / MODELS["forced-steering"]),
                               str(runs)], env=env, capture_output=True, text=True, timeout=900)
        if done.returncode != 0:
            print(f"FAILED: {done.stderr.strip().splitlines()[-1] if done.stderr.strip() else done.returncode}")
            self.missed.append("library against CLI could not run")
            return
        figures = json.loads(done.stdout.strip().splitlines()[-1])
        library, cli, unlimited, command = (figures[k] for k in ("library", "cli", "unlimited", "command"))
        ratio = library / cli
        print(f"BLAS libraries in the child: {figures['blas']}")
        print(f"simulate() from Python (the library limits its threads): {library * 1e3:.2f} ms")
        print(f"simulate() under the CLI's thread setting (baseline):     {cli * 1e3:.2f} ms -> ratio {ratio:.2f}")
        print(f"simulate() with the limit switched off (EXPRESS_BLAS_THREADS=none, as before): "
              f"{unlimited * 1e3:.2f} ms ({unlimited / cli:.1f}x the CLI's)")
        print(f"whole command in-process, main(['simulate', model, '-o', run.npz]) (generation cached): "
              f"{command * 1e3:.1f} ms")
        status = self.check(ratio <= 1.25, f"library simulate {ratio:.2f}x the CLI's")
        self.lines.append(f"library simulate() against the CLI's: {library * 1e3:.2f} ms vs {cli * 1e3:.2f} ms, "
                          f"ratio {ratio:.2f} ({status}); without the library's limit {unlimited * 1e3:.1f} ms")


#: Child script of section 5: argv = model, runs; prints one JSON line of medians [s].
_LIBRARY_AGAINST_CLI = """
import json, random, statistics, sys, tempfile, time
from pathlib import Path
from threadpoolctl import threadpool_info
from express.analysis.time.simulate import simulate
from express.cli import _one_blas_thread, main
from express.rail.track import paper_curve
from express.numeric.statespace import load_vehicle
from express.base.threads import blas_threads

model, runs = sys.argv[1], int(sys.argv[2])
vehicle, track = load_vehicle(model), paper_curve()
folder = tempfile.mkdtemp()

def library():
    simulate(vehicle, track, progress=False)

def cli():
    with _one_blas_thread(True):
        simulate(vehicle, track, progress=False)

def unlimited():
    with blas_threads(None):
        simulate(vehicle, track, progress=False)

def command():
    assert main(["simulate", model, "-o", str(Path(folder) / "run.npz")]) == 0

def medians(functions):  # medians [s]; the functions take turns, in a random order every round
    times = {name: [] for name in functions}
    for function in functions.values():
        function()
    names = list(functions)
    for _ in range(runs):
        random.shuffle(names)
        for name in names:
            start = time.perf_counter()
            functions[name]()
            times[name].append(time.perf_counter() - start)
    return {name: statistics.median(values) for name, values in times.items()}

figures = medians({"library": library, "cli": cli})
# apart: two BLAS threads left spinning, or a command's file work, slow whatever runs next
figures.update(medians({"unlimited": unlimited}))
figures.update(medians({"command": command}))
figures["blas"] = ", ".join(f"{p['internal_api']} {p['num_threads']} threads"
                            for p in threadpool_info() if p["user_api"] == "blas")
print(json.dumps(figures))
"""


def _scan_critical(vehicle, speeds) -> float:
    """Lowest speed of the scan at which the largest real part is positive (nan: none)."""
    for v in speeds:
        if np.linalg.eigvals(vehicle.state_matrix(v)).real.max() > 0.0:
            return float(v)
    return float("nan")


def _critical_speeds(result, count: int):
    """The critical speeds [m/s] from what ``critical_speed_vs_conicity`` returns: a list
    of ``CriticalSpeed`` (``.speed`` [m/s]) or ``None`` (stable over the range: nan)."""
    try:
        items = list(result)
    except TypeError:
        return None
    if len(items) != count:
        return None
    speeds = []
    for item in items:
        if item is None:
            speeds.append(float("nan"))
        elif hasattr(item, "speed"):
            speeds.append(float(item.speed))
        else:
            try:
                speeds.append(float(item))
            except (TypeError, ValueError):
                return None
    return np.array(speeds)


def _locus_eigenvalues(result, count: int):
    """The eigenvalues per speed from whatever ``root_locus`` returns (None if unknown)."""
    for attribute in ("eigenvalues", "roots", "values"):
        if hasattr(result, attribute) and not callable(getattr(result, attribute)):
            result = getattr(result, attribute)
            break
    if isinstance(result, dict):
        for key in ("eigenvalues", "roots"):
            if key in result:
                result = result[key]
                break
    if isinstance(result, tuple):
        result = next((item for item in result if np.iscomplexobj(np.asarray(item))), result[-1])
    try:
        array = np.asarray(result)
    except (TypeError, ValueError):
        return None
    if array.ndim == 2 and array.shape[0] == count:
        return array
    if array.ndim == 2 and array.shape[1] == count:
        return array.T
    return None


def machine_info() -> str:
    import numba
    import scipy

    cpu = cpu_name()
    usable = usable_cores()
    try:
        load = ", ".join(f"{x:.2f}" for x in os.getloadavg())
    except OSError:
        load = "?"
    threads = " ".join(f"{k}={os.environ.get(k)}" for k in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS"))
    return (
        f"date        {datetime.datetime.now().isoformat(timespec='seconds')}\n"
        f"python      {platform.python_version()} on {platform.platform()}\n"
        f"numpy {np.__version__}, scipy {scipy.__version__}, numba {numba.__version__}\n"
        f"cpu         {cpu}; cpu_count={os.cpu_count()}, usable={usable}; load average {load}\n"
        f"threads     {threads}; numba cache {os.environ.get('NUMBA_CACHE_DIR', 'project __pycache__')}"
    )


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true",
                        help="fewer repetitions, solve_ivp reference over the first 100 m only (smoke test)")
    parser.add_argument("--runs", type=int, default=None, help="timed runs per figure (default 7, --quick 3)")
    parser.add_argument("--ivp-runs", type=int, default=1, help="solve_ivp runs (default 1)")
    parser.add_argument("--numba-cache", choices=("fresh", "project"), default="fresh",
                        help="'fresh': compile the Numba kernels into a temporary cache (real compile time, "
                             "default); 'project': use the project's cache")
    args = parser.parse_args(argv)
    if args.runs is None:
        args.runs = 3 if args.quick else 7
    if args.runs < 1 or args.ivp_runs < 1:
        parser.error("--runs and --ivp-runs must be at least 1")

    with tempfile.TemporaryDirectory(prefix="express-numba-") as cache:
        if args.numba_cache == "fresh":
            os.environ["NUMBA_CACHE_DIR"] = cache
        return _run(args)


def _run(args) -> int:
    from express.io import load_model
    from express.numeric.statespace import vehicle_model
    from express.rail.track import paper_curve

    try:
        from express.analysis.stability import stability
    except ImportError:
        stability = None

    print("EXPRESS simulation benchmark" + (" (--quick)" if args.quick else ""))
    print(machine_info())
    start = time.perf_counter()
    models = {name: load_model(ROOT / path) for name, path in MODELS.items()}
    vehicles = {name: vehicle_model(model) for name, model in models.items()}
    print(f"models loaded and evaluated in {time.perf_counter() - start:.2f} s (not timed below)")
    track = paper_curve()

    bench = Bench(args)
    bench.curving(vehicles, track)
    bench.solve_ivp_baseline("forced-steering", vehicles["forced-steering"], track)
    bench.critical_speed(stability, vehicles, models)
    bench.root_locus(stability, vehicles["forced-steering"])
    bench.library_against_cli()

    print("\n== summary")
    for line in bench.lines:
        print(line)
    if bench.missed:
        print("TARGET MISSED: " + "; ".join(bench.missed))
    else:
        print("all targets met")
    print(f"realtime_factor={bench.realtime_factor:.0f} speedup_vs_solve_ivp={bench.speedup:.0f} "
          f"q1_rel_diff={bench.q1_rel_diff:.2e}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
