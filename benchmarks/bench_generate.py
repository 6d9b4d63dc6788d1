#!/usr/bin/env python3
"""Generation benchmark: EXPRESS against naive SymPy baselines.

Run from the repository root::

    PYTHONPATH=src python3 benchmarks/bench_generate.py            # full run (~6.5 min)
    PYTHONPATH=src python3 benchmarks/bench_generate.py --quick    # smoke test (~1 min)
    PYTHONPATH=src python3 benchmarks/bench_generate.py --cars 5   # another train size

Models: the lever (``examples/lever.exp``), the forced-steering vehicle
(``examples/forced-steering.toml``; core matrices with ``generate(model)`` and, as a
second line, with the rail terms via ``generate_vehicle(model)``) and an N-car train of
that vehicle (``examples/make_vehicles.py``: ``vehicle_toml(True, cars=N)``).

Every timing is the median of several runs after one warm-up run; SymPy's cache is
cleared before every timed run, for EXPRESS and for the baselines alike.  Only the
generation is timed (the model is loaded once, beforehand).

Baselines, implemented here from the model records only (no generator internals):

1. naive SymPy Hessian: ``U = 1/2 sum k_i delta_i^2`` with ``delta_i = u_S[d] - u_T[d]``
   and ``u = t + theta x r`` over ALL DOFs (virtual ones included, no pin elimination,
   no simplification), ``K = hessian(U, q)``; likewise ``C = hessian(D, qdot)`` from the
   dissipation function and ``M = hessian(T, qdot)`` from the kinetic energy.
2. ``sympy.physics.mechanics.LagrangesMethod`` on the same ``T - U``:
   ``form_lagranges_equations()`` then the linearized system
   (``to_linearizer(...).linearize(simplify=False)``), from which M and K are read.

Agreement: the baseline matrices are reduced with the generator's transformation
``T`` (``T^T X T``) and compared with the generator's M, C, K after substituting the same
random positive values for every parameter (relative tolerance 1e-9 of the largest entry).

Exit code 0 even when a target is missed; ``TARGET MISSED`` is printed in that case.
"""

from __future__ import annotations

import argparse
import datetime
import gc
import math
import multiprocessing as mp
import os
import platform
import queue
import random
import resource
import statistics
import sys
import tempfile
import time
import tracemalloc
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
for _extra in (ROOT / "examples", ROOT / "src"):
    if str(_extra) not in sys.path:
        sys.path.insert(0, str(_extra))

import numpy as np  # noqa: E402
import scipy  # noqa: E402
import sympy as sp  # noqa: E402
import sympy.physics.mechanics  # noqa: E402,F401  (imported before any timing, also in child processes)
from make_vehicles import vehicle_toml  # noqa: E402
from sympy.core.cache import clear_cache  # noqa: E402

from express.assembly.generator import generate  # noqa: E402
from express.io import load_model  # noqa: E402
from express.rail.build import generate_vehicle  # noqa: E402
from machine import cpu_name, usable_cores  # noqa: E402  (benchmarks/machine.py)

VEHICLE_TARGET_S = 0.5
TRAIN_TARGET_S = 10.0  # for 10 cars; scaled linearly for larger trains
LINEAR_EXPONENT_LIMIT = 1.25  # "about linear": fitted exponent of time vs elements
AGREE_RTOL = 1e-9
SEED = 20240601
MB = 1024.0 * 1024.0

_DOF_NAMES = ("x", "y", "z", "rx", "ry", "rz")
_AXES = ("x", "y", "z")


# --------------------------------------------------------------------------- baselines


def _dof_inertia(body, dof: str):
    """Mass for a translation, principal moment of inertia for a rotation."""
    return body.mass if dof in _AXES else body.inertia[_AXES.index(dof[1])]


def _cp_motion(model, coordinates):
    """``motion(cp, axis)``: small-motion displacement ``u = t + theta x r`` of a CP.

    ``coordinates`` maps ``(body id, dof)`` to a SymPy symbol; DOFs a body lacks are
    zero and CPs on grounds do not move.
    """
    bodies = {body.id for body in model.bodies}
    points = {point.id: point for point in model.points}
    zero = sp.S.Zero

    def motion(point_id: str, axis: int):
        point = points[point_id]
        if point.host not in bodies:
            return zero
        x, y, z, rx, ry, rz = (coordinates.get((point.host, dof), zero) for dof in _DOF_NAMES)
        lx, ly, lz = point.offset
        return (x + ry * lz - rz * ly, y + rz * lx - rx * lz, z + rx * ly - ry * lx)[axis]

    return motion


def naive_hessian(model):
    """Baseline 1: plain energies over all DOFs, then ``sympy.hessian``; returns (names, M, C, K)."""
    half = sp.Rational(1, 2)
    names = [f"{body.id}.{dof}" for body in model.bodies for dof in body.dofs]
    q = {(b.id, d): sp.Symbol(f"{b.id}.{d}") for b in model.bodies for d in b.dofs}
    qd = {(b.id, d): sp.Symbol(f"{b.id}.{d}_dot") for b in model.bodies for d in b.dofs}
    coordinates = [q[b.id, d] for b in model.bodies for d in b.dofs]
    rates = [qd[b.id, d] for b in model.bodies for d in b.dofs]
    position, velocity = _cp_motion(model, q), _cp_motion(model, qd)
    potential = sp.Add(
        *[
            half * e.stiffness * (position(e.s_end, e.direction) - position(e.t_end, e.direction)) ** 2
            for e in model.elements
        ]
    )
    dissipation = sp.Add(
        *[
            half * e.damping * (velocity(e.s_end, e.direction) - velocity(e.t_end, e.direction)) ** 2
            for e in model.elements
        ]
    )
    kinetic = sp.Add(*[half * _dof_inertia(b, d) * qd[b.id, d] ** 2 for b in model.bodies for d in b.dofs])
    stiffness = sp.hessian(potential, coordinates)
    damping = sp.hessian(dissipation, rates)
    mass = sp.hessian(kinetic, rates)
    return names, {"M": mass, "C": damping, "K": stiffness}


def lagranges_method(model):
    """Baseline 2: ``LagrangesMethod`` on ``T - U``, linearized; returns (names, M, K)."""
    from sympy.physics.mechanics import LagrangesMethod, dynamicsymbols

    t = dynamicsymbols._t
    half = sp.Rational(1, 2)
    names = [f"{body.id}.{dof}" for body in model.bodies for dof in body.dofs]
    q = {(b.id, d): dynamicsymbols(f"{b.id}_{d}") for b in model.bodies for d in b.dofs}
    coordinates = [q[b.id, d] for b in model.bodies for d in b.dofs]
    position = _cp_motion(model, q)
    potential = sp.Add(
        *[
            half * e.stiffness * (position(e.s_end, e.direction) - position(e.t_end, e.direction)) ** 2
            for e in model.elements
        ]
    )
    kinetic = sp.Add(*[half * _dof_inertia(b, d) * q[b.id, d].diff(t) ** 2 for b in model.bodies for d in b.dofs])
    method = LagrangesMethod(kinetic - potential, coordinates)
    method.form_lagranges_equations()
    linearizer = method.to_linearizer(q_ind=coordinates, qd_ind=[c.diff(t) for c in coordinates])
    m_lin, a_lin, _ = linearizer.linearize(simplify=False)
    n = len(coordinates)
    # M_lin [q'; q''] = A [q; q'] with M_lin = diag(I, M) and A = [[0, I], [-K, 0]]
    return names, {"M": m_lin[n:, n:], "K": -a_lin[n:, :n]}


def _generate_only(model):
    """EXPRESS in the shape of the baselines, for the RSS measurement in a child."""
    generate(model)
    return [], {}


# --------------------------------------------------------------------------- numerics


def numeric(matrix, values: dict[str, float]) -> np.ndarray:
    """A symbolic matrix evaluated at ``values`` (parameter name -> float)."""
    out = np.zeros(matrix.shape)
    for (i, j), entry in matrix.todok().items():
        entry = sp.sympify(entry)
        out[i, j] = float(entry.xreplace({s: sp.Float(values[s.name]) for s in entry.free_symbols}))
    return out


def random_values(model, seed: int = SEED) -> dict[str, float]:
    """Random positive values in [0.5, 2] for every parameter symbol of ``model``."""
    names: set[str] = set()
    expressions = []
    for body in model.bodies:
        expressions += [body.mass, *body.inertia]
    for point in model.points:
        expressions += list(point.offset)
    for element in model.elements:
        expressions += [element.stiffness, element.damping]
    for expression in expressions:
        names |= {s.name for s in sp.sympify(expression).free_symbols}
    rng = random.Random(seed)
    return {name: rng.uniform(0.5, 2.0) for name in sorted(names)}


def reference_arrays(result, values):
    """The generator's T, M, C, K evaluated numerically."""
    eom = result.equations
    return {
        "T": numeric(result.transformation, values),
        **{key: numeric(eom.matrices[key], values) for key in ("M", "C", "K")},
        "full_dofs": list(result.full_dofs),
    }


def compare(reference, names, arrays) -> dict[str, float]:
    """Relative error of ``T^T X T`` against the generator, for each matrix X given."""
    index = [names.index(dof) for dof in reference["full_dofs"]]
    t = reference["T"]
    errors = {}
    for key, full in arrays.items():
        reduced = t.T @ full[np.ix_(index, index)] @ t
        expected = reference[key]
        scale = max(np.abs(expected).max(initial=0.0), np.abs(reduced).max(initial=0.0), 1e-300)
        errors[key] = float(np.abs(reduced - expected).max(initial=0.0) / scale)
    return errors


# --------------------------------------------------------------------------- running


def _rss_now() -> float:
    """Resident set size now, bytes (Linux /proc; 0 elsewhere)."""
    try:
        with open("/proc/self/statm") as handle:
            return int(handle.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")
    except (OSError, ValueError):
        return 0.0


def _peak_rss_of(pid: int):
    """Peak RSS (VmHWM) of a running process, bytes, or None."""
    try:
        with open(f"/proc/{pid}/status") as handle:
            for line in handle:
                if line.startswith("VmHWM:"):
                    return float(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    return None


def _max_rss(who=resource.RUSAGE_SELF) -> float:
    """Maximum resident set size, bytes (ru_maxrss is KiB on Linux, bytes on macOS)."""
    value = resource.getrusage(who).ru_maxrss
    return float(value if sys.platform == "darwin" else value * 1024)


def time_runs(function, runs: int, warmup: int = 1) -> list[float]:
    """Wall times of ``runs`` calls after ``warmup`` untimed ones (SymPy cache cleared each time)."""
    for _ in range(warmup):
        clear_cache()
        function()
    times = []
    for _ in range(runs):
        clear_cache()
        gc.collect()
        start = time.perf_counter()
        function()
        times.append(time.perf_counter() - start)
    return times


def traced_peak(function) -> float:
    """Peak Python allocation (tracemalloc) during one call, bytes."""
    clear_cache()
    gc.collect()
    tracemalloc.start()
    try:
        function()
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    return float(peak)


def _child(channel, function, model, values):
    try:
        clear_cache()
        gc.collect()
        rss_start = _rss_now()
        channel.put(("start", rss_start))
        start = time.perf_counter()
        names, matrices = function(model)
        elapsed = time.perf_counter() - start
        channel.put(("timed", elapsed, rss_start, _max_rss()))
        arrays = {key: numeric(matrix, values) for key, matrix in matrices.items()} if values else {}
        channel.put(("arrays", names, arrays))
    except BaseException as error:  # report, never hang the parent
        channel.put(("error", f"{type(error).__name__}: {error}"))


def run_in_child(function, model, values, timeout: float):
    """Run ``function(model)`` in a fresh (spawned) process with a time limit.

    A spawned interpreter starts with an empty heap and a cold SymPy cache, so its peak
    RSS minus its RSS once the model is unpickled is the memory the run needed.

    Returns a dict with ``seconds``, ``rss_growth`` (peak RSS minus RSS at start, bytes),
    and ``names``/``arrays`` (matrices evaluated at ``values``), or
    ``{"timeout": True, "rss_growth": peak so far}`` or ``{"error": message}``.
    """
    context = mp.get_context("spawn")
    channel = context.Queue()
    process = context.Process(target=_child, args=(channel, function, model, values), daemon=True)
    process.start()
    outcome: dict = {}
    rss_start = 0.0
    try:
        message = channel.get(timeout=120)  # interpreter start-up and imports
        if message[0] == "start":
            rss_start = message[1]
            message = channel.get(timeout=timeout)
        if message[0] == "error":
            outcome = {"error": message[1]}
        else:
            _, seconds, rss_start, rss_peak = message
            outcome = {"seconds": seconds, "rss_growth": max(rss_peak - rss_start, 0.0), "rss_peak": rss_peak}
            try:
                message = channel.get(timeout=max(300.0, timeout))
                if message[0] == "arrays":
                    outcome["names"], outcome["arrays"] = message[1], message[2]
            except queue.Empty:
                pass
    except queue.Empty:
        outcome = {"timeout": True}
        peak = _peak_rss_of(process.pid)
        if peak is not None:
            outcome["rss_growth"] = max(peak - rss_start, 0.0)
            outcome["rss_peak"] = peak
    finally:
        if process.is_alive():
            process.terminate()
        process.join(10)
        if process.is_alive():
            process.kill()
            process.join()
    return outcome


# --------------------------------------------------------------------------- reporting


def fmt_s(seconds) -> str:
    if seconds is None:
        return "-"
    return f"{seconds:.3g}"


def fmt_runs(times) -> str:
    if not times:
        return "-"
    return f"{len(times)} ({min(times):.3g}..{max(times):.3g})"


def fmt_mb(size) -> str:
    return "-" if size is None else f"{size / MB:.1f}"


def fmt_rss(outcome, lower_bound: bool = False) -> str:
    """``growth (peak N)`` of a child process, MB."""
    if not outcome or outcome.get("rss_growth") is None:
        return "-"
    prefix = ">" if lower_bound else ""
    text = f"{prefix}{outcome['rss_growth'] / MB:.1f}"
    if outcome.get("rss_peak") is not None:
        text += f" (peak {prefix}{outcome['rss_peak'] / MB:.0f})"
    return text


def table(headers, rows) -> str:
    cells = [[str(c) for c in headers]] + [[str(c) for c in row] for row in rows]
    widths = [max(len(row[i]) for row in cells) for i in range(len(headers))]
    lines = ["  " + "  ".join(c.ljust(w) for c, w in zip(row, widths)) for row in cells]
    lines.insert(1, "  " + "  ".join("-" * w for w in widths))
    return "\n".join(lines)


def summary_line(model, express_s, baseline, target_s, note=None) -> tuple[str, bool]:
    """``model=... express_s=... baseline_s=... ratio=... target_s=... ok=...``."""
    ok = target_s is None or express_s < target_s
    if baseline.get("seconds") is not None:
        base = f"baseline_s={baseline['seconds']:.3g}"
        ratio = f"ratio={baseline['seconds'] / express_s:.3g}"
    elif baseline.get("timeout"):
        base = f"baseline_s>{baseline['limit']:.0f} (timed out)"
        ratio = f"ratio>{baseline['limit'] / express_s:.3g}"
    else:
        base, ratio = f"baseline_s=n/a ({baseline.get('why', 'not run')})", "ratio=n/a"
    target = f"target_s={target_s:g}" if target_s is not None else "target_s=none"
    line = f"model={model} express_s={express_s:.3g} {base} {ratio} {target} ok={ok}"
    if note:
        line += f" note={note}"
    return line, ok


def fit_exponent(xs, ys):
    """Least-squares exponent p of ``y ~ c x^p`` and the constant c."""
    lx, ly = np.log(np.asarray(xs, float)), np.log(np.asarray(ys, float))
    p, logc = np.polyfit(lx, ly, 1)
    return float(p), float(math.exp(logc))


def machine_info() -> str:
    cpu = cpu_name()
    usable = usable_cores()
    try:
        from sympy.external.gmpy import GROUND_TYPES
    except ImportError:  # pragma: no cover
        GROUND_TYPES = "?"
    return (
        f"date        {datetime.datetime.now().isoformat(timespec='seconds')}\n"
        f"python      {platform.python_version()} ({platform.python_implementation()}) on {platform.platform()}\n"
        f"sympy       {sp.__version__} (ground types: {GROUND_TYPES}), numpy {np.__version__}, scipy {scipy.__version__}\n"
        f"cpu         {cpu}; cpu_count={os.cpu_count()}, usable={usable}\n"
        f"load        {load_text()}"
    )


def load_text() -> str:
    """The 1/5/15-minute load averages, flagged when other work competes for the CPUs."""
    try:
        one, five, fifteen = os.getloadavg()
    except OSError:
        return "unknown"
    return f"load average {one:.2f} {five:.2f} {fifteen:.2f}"


def _busy_cpu_seconds():
    """CPU seconds all processes spent busy since boot (Linux /proc/stat), or None."""
    try:
        with open("/proc/stat") as handle:
            fields = [int(v) for v in handle.readline().split()[1:]]
    except (OSError, ValueError):
        return None
    busy = sum(fields) - fields[3] - (fields[4] if len(fields) > 4 else 0)  # minus idle, iowait
    return busy / os.sysconf("SC_CLK_TCK")


def _own_cpu_seconds() -> float:
    total = 0.0
    for who in (resource.RUSAGE_SELF, resource.RUSAGE_CHILDREN):
        usage = resource.getrusage(who)
        total += usage.ru_utime + usage.ru_stime
    return total


class Contention:
    """CPU used by OTHER processes while the benchmark runs (they inflate the timings)."""

    def __init__(self):
        self.wall, self.busy, self.own = time.perf_counter(), _busy_cpu_seconds(), _own_cpu_seconds()

    def report(self) -> str:
        busy = _busy_cpu_seconds()
        if busy is None or self.busy is None:
            return "CPU used by other processes: unknown"
        wall = time.perf_counter() - self.wall
        others = max(busy - self.busy - (_own_cpu_seconds() - self.own), 0.0) / wall
        try:
            usable = len(os.sched_getaffinity(0))
        except AttributeError:
            usable = os.cpu_count() or 1
        text = f"CPU used by other processes during the run: {others:.2f} of {usable} cores on average"
        # the benchmark needs one core (its children never run alongside it)
        if others > max(0.25, usable - 1.0):
            text += " (WARNING: other work competed for the CPUs; timings are inflated)"
        return text


# --------------------------------------------------------------------------- benchmark


class Bench:
    def __init__(self, args):
        self.args = args
        self.lines: list[str] = []  # the summary lines
        self.missed: list[str] = []  # targets missed
        self.failed: list[str] = []  # agreement checks failed

    def record(self, line: str, ok: bool, what: str) -> None:
        print(line)
        self.lines.append(line)
        if not ok:
            self.missed.append(what)
            print(f"TARGET MISSED: {what}")

    def small_model(self, key: str, model, target_s, rail: bool) -> None:
        """Lever or vehicle: EXPRESS, naive Hessian (in process), LagrangesMethod (child)."""
        runs = self.args.runs
        n_dofs = sum(len(b.dofs) for b in model.bodies)
        print(f"\n== {key}: {model.name} ({len(model.bodies)} bodies, {n_dofs} DOFs, "
              f"{len(model.pins)} pins, {len(model.elements)} elements)")
        express = time_runs(lambda: generate(model), runs)
        express_peak = traced_peak(lambda: generate(model))
        result = generate(model)
        rail_times = rail_peak = None
        if rail and model.rail is not None:
            rail_times = time_runs(lambda: generate_vehicle(model), runs)
            rail_peak = traced_peak(lambda: generate_vehicle(model))

        naive_times = time_runs(lambda: naive_hessian(model), runs)
        naive_peak = traced_peak(lambda: naive_hessian(model))
        values = random_values(model)
        reference = reference_arrays(result, values)
        names, matrices = naive_hessian(model)
        errors = compare(reference, names, {k: numeric(m, values) for k, m in matrices.items()})
        agree = all(e <= AGREE_RTOL for e in errors.values())

        lagrange_times: list[float] = []
        lagrange_note = "skipped (--quick)"
        lagrange_rss: dict | None = None
        lagrange_errors = None
        if not self.args.quick:
            lagrange_note = ""
            for i in range(self.args.lagrange_runs):
                outcome = run_in_child(lagranges_method, model, values if i == 0 else None,
                                       self.args.lagrange_timeout)
                if "timeout" in outcome:
                    lagrange_note = f"timed out (>{self.args.lagrange_timeout:.0f} s)"
                    break
                if "error" in outcome:
                    lagrange_note = f"failed: {outcome['error']}"
                    break
                lagrange_times.append(outcome["seconds"])
                if lagrange_rss is None or outcome["rss_peak"] > lagrange_rss["rss_peak"]:
                    lagrange_rss = outcome
                if outcome.get("arrays"):
                    lagrange_errors = compare(reference, outcome["names"], outcome["arrays"])
        e_med = statistics.median(express)
        n_med = statistics.median(naive_times)
        rows = [
            ["EXPRESS generate(model)", fmt_s(e_med), fmt_runs(express), "1", fmt_mb(express_peak), "-"],
        ]
        if rail_times:
            r_med = statistics.median(rail_times)
            rows.append(["EXPRESS generate_vehicle(model)", fmt_s(r_med), fmt_runs(rail_times),
                         f"{r_med / e_med:.3g}", fmt_mb(rail_peak), "-"])
        rows.append(["naive SymPy Hessian (M, C, K)", fmt_s(n_med), fmt_runs(naive_times),
                     f"{n_med / e_med:.3g}", fmt_mb(naive_peak), "-"])
        if lagrange_times:
            l_med = statistics.median(lagrange_times)
            rows.append(["LagrangesMethod + linearize (M, K)", fmt_s(l_med), fmt_runs(lagrange_times),
                         f"{l_med / e_med:.3g}", "-", fmt_rss(lagrange_rss)])
        else:
            rows.append(["LagrangesMethod + linearize (M, K)", lagrange_note, "-", "-", "-", "-"])
        print(table(["method", "median_s", "runs (min..max)", "x EXPRESS", "tracemalloc_peak_MB",
                     "child_rss_growth_MB"], rows))
        detail = " ".join(f"{k}:{v:.1e}" for k, v in errors.items())
        print(f"  agreement naive Hessian vs EXPRESS (T^T X T, rel. error {detail}): agree={agree}")
        if lagrange_errors is not None:
            l_agree = all(e <= AGREE_RTOL for e in lagrange_errors.values())
            detail = " ".join(f"{k}:{v:.1e}" for k, v in lagrange_errors.items())
            print(f"  agreement LagrangesMethod vs EXPRESS (rel. error {detail}): agree={l_agree}")
        if not agree:
            self.failed.append(f"{key}: naive Hessian and EXPRESS disagree")
        if lagrange_errors is not None and not all(e <= AGREE_RTOL for e in lagrange_errors.values()):
            self.failed.append(f"{key}: LagrangesMethod and EXPRESS disagree")
        baseline = {"seconds": n_med}
        lagrange_part = (f" lagrange_s={statistics.median(lagrange_times):.3g}" if lagrange_times
                         else f" lagrange_s=n/a ({lagrange_note})")
        line, ok = summary_line(key, e_med, baseline, target_s)
        self.record(line + f" agree={agree}" + lagrange_part, ok, f"{key} generation >= {target_s} s")
        if rail_times:
            # the targets are for the core matrices; the rail terms are reported only
            line, _ = summary_line(f"{key}+rail", statistics.median(rail_times), baseline, None,
                                   note="baseline_has_no_rail_terms")
            self.record(line, True, "")

    def trains(self) -> None:
        """Train of N cars (target, baseline in a child with a limit) and the scaling table."""
        args = self.args
        n_cars = args.cars
        sizes = sorted({c for c in (1, 2, 5, 10) if c < n_cars} | {n_cars})
        baseline_sizes = [c for c in sizes if c != n_cars and c <= (2 if args.quick else 5)]
        rows = []
        measured: dict[int, dict] = {}
        with tempfile.TemporaryDirectory(prefix="express-bench-") as folder:
            for cars in sizes:
                path = Path(folder) / f"train{cars}.toml"
                path.write_text(vehicle_toml(True, cars=cars), encoding="utf-8")
                start = time.perf_counter()
                model = load_model(path)
                load_s = time.perf_counter() - start
                runs = args.train_runs if cars > 2 else args.runs
                times = time_runs(lambda: generate(model), runs)
                entry = {
                    "model": model,
                    "load_s": load_s,
                    "times": times,
                    "median": statistics.median(times),
                    "dofs": sum(len(b.dofs) for b in model.bodies),
                    "elements": len(model.elements),
                }
                if cars in baseline_sizes:
                    outcome = run_in_child(naive_hessian, model, None, args.baseline_timeout)
                    entry["baseline"] = outcome
                measured[cars] = entry
            train = measured[n_cars]
            model = train["model"]
            print(f"\n== train: {n_cars} cars, {model.name} ({len(model.bodies)} bodies, {train['dofs']} DOFs, "
                  f"{len(model.pins)} pins, {train['elements']} elements; load_model {train['load_s']:.3g} s, not timed)")
            result = generate(model)
            express_peak = traced_peak(lambda: generate(model))
            express_rss = run_in_child(_generate_only, model, None, 120)
            rail_times = time_runs(lambda: generate_vehicle(model), args.train_runs)
            if args.quick:
                baseline = {"why": "skipped (--quick)"}
            else:
                values = random_values(model)
                outcome = run_in_child(naive_hessian, model, values, args.baseline_timeout)
                if "timeout" in outcome:
                    baseline = {**outcome, "limit": args.baseline_timeout}
                elif "error" in outcome:
                    baseline = {"why": outcome["error"]}
                else:
                    baseline = outcome
                    if outcome.get("arrays"):
                        reference = reference_arrays(result, values)
                        baseline["errors"] = compare(reference, outcome["names"], outcome["arrays"])
        e_med = train["median"]
        rows = [["EXPRESS generate(model)", fmt_s(e_med), fmt_runs(train["times"]), "1",
                 fmt_mb(express_peak), fmt_rss(express_rss)]]
        r_med = statistics.median(rail_times)
        rows.append(["EXPRESS generate_vehicle(model)", fmt_s(r_med), fmt_runs(rail_times),
                     f"{r_med / e_med:.3g}", "-", "-"])
        if baseline.get("seconds") is not None:
            rows.append(["naive SymPy Hessian (M, C, K)", fmt_s(baseline["seconds"]), "1 (child)",
                         f"{baseline['seconds'] / e_med:.3g}", "-", fmt_rss(baseline)])
        elif baseline.get("timeout"):
            rows.append(["naive SymPy Hessian (M, C, K)", f">{args.baseline_timeout:.0f} (timed out)",
                         "1 (child)", f">{args.baseline_timeout / e_med:.3g}", "-",
                         fmt_rss(baseline, lower_bound=True)])
        else:
            rows.append(["naive SymPy Hessian (M, C, K)", baseline.get("why", "-"), "-", "-", "-", "-"])
        rows.append(["LagrangesMethod", "not run (lever and vehicle only)", "-", "-", "-", "-"])
        print(table(["method", "median_s", "runs (min..max)", "x EXPRESS", "tracemalloc_peak_MB",
                     "child_rss_growth_MB"], rows))
        if "errors" in baseline:
            agree = all(e <= AGREE_RTOL for e in baseline["errors"].values())
            detail = " ".join(f"{k}:{v:.1e}" for k, v in baseline["errors"].items())
            print(f"  agreement naive Hessian vs EXPRESS (T^T X T, rel. error {detail}): agree={agree}")
            if not agree:
                self.failed.append(f"train{n_cars}: naive Hessian and EXPRESS disagree")
        target = TRAIN_TARGET_S * max(1.0, n_cars / 10.0)
        line, ok = summary_line(f"train{n_cars}", e_med, baseline, target)
        if "errors" in baseline:
            line += f" agree={all(e <= AGREE_RTOL for e in baseline['errors'].values())}"
        self.record(line, ok, f"train{n_cars} generation >= {target:g} s")
        line, _ = summary_line(f"train{n_cars}+rail", r_med, baseline, None, note="baseline_has_no_rail_terms")
        self.record(line, True, "")

        # scaling
        print(f"\n== scaling with the number of cars (EXPRESS median of {args.train_runs}-{args.runs} runs; "
              f"naive Hessian 1 run in a child, limit {args.baseline_timeout:.0f} s)")
        rows = []
        base_points = []
        for cars in sizes:
            entry = measured[cars]
            b = entry.get("baseline") if cars != n_cars else baseline
            if b is None:
                b_text = "-"
            elif b.get("seconds") is not None:
                b_text = fmt_s(b["seconds"])
                if cars != n_cars:
                    base_points.append((entry["elements"], b["seconds"]))
            elif b.get("timeout"):
                b_text = f">{args.baseline_timeout:.0f}"
            else:
                b_text = "-"
            rows.append([cars, entry["dofs"], len(entry["model"].pins), entry["elements"], fmt_s(entry["median"]),
                         f"{1000 * entry['median'] / entry['elements']:.3g}", b_text])
        print(table(["cars", "DOFs", "pins", "elements", "express_s", "express_ms_per_element", "naive_hessian_s"],
                    rows))
        if len(sizes) < 2:
            print("  (one size only: no scaling fit)")
            return
        elements = [measured[c]["elements"] for c in sizes]
        exponent, _ = fit_exponent(elements, [measured[c]["median"] for c in sizes])
        per_element = [measured[c]["median"] / measured[c]["elements"] for c in sizes]
        linear_ok = exponent <= LINEAR_EXPONENT_LIMIT
        print(f"  EXPRESS time ~ elements^{exponent:.2f} (least-squares fit over {len(sizes)} sizes); "
              f"ms/element {1000 * per_element[0]:.3g} at {sizes[0]} car(s) -> {1000 * per_element[-1]:.3g} "
              f"at {sizes[-1]} cars")
        if len(base_points) >= 2 and baseline.get("seconds") is None:
            b_exp, b_c = fit_exponent([p[0] for p in base_points], [p[1] for p in base_points])
            estimate = b_c * train["elements"] ** b_exp
            print(f"  naive Hessian time ~ elements^{b_exp:.2f}; EXTRAPOLATED (not measured) to {n_cars} cars: "
                  f"~{estimate:.3g} s, ~{estimate / e_med:.3g} x EXPRESS")
        self.record(f"model=scaling express_exponent={exponent:.2f} limit={LINEAR_EXPONENT_LIMIT} ok={linear_ok}",
                    linear_ok, f"EXPRESS time grows faster than elements^{LINEAR_EXPONENT_LIMIT}")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true",
                        help="skip the train baseline and LagrangesMethod (smoke test)")
    parser.add_argument("--cars", type=int, default=10, help="number of cars of the train (default 10)")
    parser.add_argument("--runs", type=int, default=5, help="timed runs for the lever and the vehicle (default 5)")
    parser.add_argument("--train-runs", type=int, default=3, help="timed runs for trains (default 3)")
    parser.add_argument("--lagrange-runs", type=int, default=3, help="LagrangesMethod runs (default 3)")
    parser.add_argument("--baseline-timeout", type=float, default=240.0,
                        help="time limit of a naive-Hessian run on a train, s (default 240)")
    parser.add_argument("--lagrange-timeout", type=float, default=120.0,
                        help="time limit of a LagrangesMethod run, s (default 120)")
    args = parser.parse_args(argv)
    if args.cars < 1:
        parser.error("--cars must be at least 1")

    print("EXPRESS generation benchmark" + (" (--quick)" if args.quick else ""))
    print(machine_info())
    print(f"medians of {args.runs} runs (lever, vehicle) / {args.train_runs} runs (trains of 3+ cars) "
          f"after one warm-up; SymPy cache cleared before every run; only generation is timed")

    contention = Contention()
    bench = Bench(args)
    bench.small_model("lever", load_model(ROOT / "examples" / "lever.exp"), None, rail=False)
    bench.small_model("vehicle", load_model(ROOT / "examples" / "forced-steering.toml"), VEHICLE_TARGET_S,
                      rail=True)
    bench.trains()

    print("\n== summary")
    for line in bench.lines:
        print(line)
    print(contention.report())
    print(f"max RSS: benchmark process {_max_rss() / MB:.0f} MB, "
          f"largest child {_max_rss(resource.RUSAGE_CHILDREN) / MB:.0f} MB (whole processes)")
    if bench.failed:
        print("CHECK FAILED: " + "; ".join(bench.failed))
    if bench.missed:
        print("TARGET MISSED: " + "; ".join(bench.missed))
    else:
        print("all targets met")
    return 0


if __name__ == "__main__":
    sys.exit(main())
