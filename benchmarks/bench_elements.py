#!/usr/bin/env python3
"""Cost of the issue-11 model features (bump stops, series elements, gravity) against
the same models without them, measured in the same run (medians).

Run from the repository root::

    PYTHONPATH=src python3 benchmarks/bench_elements.py [--runs N]

1. The compiled time march (``express.analysis.time.integrator.march``) on the paper's curve
   (460 m at 120 km/h, 2761 steps) for the conventional car: plain (baseline), with two
   lateral bump stops that never engage (gap 1 m), and with two that engage (gap 20 mm).
   Two stops add two feedback channels to the eight of the wheelsets and their
   deflections at every evaluation, engaged or not.  Target: ratio < 1.5.  (A model
   without stops runs the same kernel as before issue 11: the stops have their own.)
2. The critical speed of the conventional car with pure yaw dampers (baseline, state
   size 2n = 40) and with yaw dampers in series with their bushes (4 first-order
   coordinates, state size 44).  Target: ratio < 1.5.
3. Symbolic generation of the conventional car with ``[gravity]`` (static equilibrium of
   the 3-D model solved exactly, geometric stiffness) against without.  Target: < 5 s.

Everything runs on one core.  The last line is
``stop_ratio=<x> series_ratio=<y> gravity_s=<z>``.
"""

from __future__ import annotations

import os

for _variable in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ.setdefault(_variable, "1")

import argparse  # noqa: E402
import dataclasses  # noqa: E402
import gc  # noqa: E402
import statistics  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

from machine import cpu_name, usable_cores  # noqa: E402  (benchmarks/machine.py)

ROOT = Path(__file__).resolve().parents[1]
if str(ROOT / "src") not in sys.path:
    sys.path.insert(0, str(ROOT / "src"))


def _median(function, runs: int) -> float:
    times = []
    for _ in range(runs):
        gc.collect()
        gc.disable()
        try:
            start = time.perf_counter()
            function()
            times.append(time.perf_counter() - start)
        finally:
            gc.enable()
    return statistics.median(times)


def _with_stops(model, gap: float):
    import sympy as sp

    from express.model.records import Element, ElementKind, Parameter

    dampers = {e.id: e for e in model.elements}
    stops = tuple(
        Element(f"T{t}_stop", sp.Symbol("kstop"), sp.S.Zero, dampers[f"T{t}_dy"].s_end, dampers[f"T{t}_dy"].t_end, 1,
                kind=ElementKind.CLEARANCE, gap=sp.Symbol("ystop"), progressive=sp.Symbol("kstop3"))
        for t in (1, 2)
    )
    parameters = {**model.parameters, "kstop": Parameter("kstop", 1e6), "kstop3": Parameter("kstop3", 1e10),
                  "ystop": Parameter("ystop", gap)}
    return dataclasses.replace(model, elements=model.elements + stops, parameters=parameters)


def _march_call(vehicle, track):
    """The arguments of the march of one simulate() call, and a function repeating it."""
    import express.analysis.time.simulate as simulation

    captured = {}
    real = simulation.march

    def spy(*args, **kwargs):
        captured["call"] = (args, kwargs)
        return real(*args, **kwargs)

    simulation.march = spy
    try:
        simulation.simulate(vehicle, track, progress=False)
    finally:
        simulation.march = real
    args, kwargs = captured["call"]
    return lambda: real(*args, **kwargs)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=21)
    args = parser.parse_args()
    from express.analysis.stability.stability import critical_speed
    from express.io import load_model
    from express.numeric.statespace import vehicle_model
    from express.rail.build import generate_vehicle
    from express.rail.track import paper_curve

    print(f"machine: {cpu_name()}, {usable_cores()} usable cores; one thread")
    model = load_model(ROOT / "examples" / "conventional.toml")
    track = paper_curve()
    calls = [_march_call(vehicle_model(m), track) for m in (model, _with_stops(model, 1.0), _with_stops(model, 0.02))]
    rounds = [[_median(call, 1) for call in calls] for _ in range(args.runs)]  # interleaved: same load for all
    plain, idle, engaged = (statistics.median(r[i] for r in rounds) for i in range(3))
    overhead = idle / plain
    print(f"1. march, paper curve, conventional car: plain {plain * 1e3:.2f} ms (baseline), two stops never "
          f"engaged {idle * 1e3:.2f} ms (ratio {overhead:.2f}, target < 1.5: {'ok' if overhead < 1.5 else 'MISSED'}), "
          f"engaged {engaged * 1e3:.2f} ms ({engaged / plain:.2f})")

    parallel = vehicle_model(model)
    series = vehicle_model(load_model(ROOT / "examples" / "conventional-yaw-bush.toml"))
    runs = max(3, args.runs // 4)
    base = _median(lambda: critical_speed(parallel), runs)
    bush = _median(lambda: critical_speed(series), runs)
    ratio = bush / base
    print(f"2. critical speed: pure yaw dampers {base * 1e3:.0f} ms (baseline, {parallel.form.size} states), "
          f"series yaw dampers {bush * 1e3:.0f} ms ({series.form.size} states), ratio {ratio:.2f} "
          f"(target < 1.5: {'ok' if ratio < 1.5 else 'MISSED'})")

    heavy = dataclasses.replace(model, gravity=__import__("sympy").Symbol("g"))
    runs = 3
    without = _median(lambda: generate_vehicle(model), runs)
    with_gravity = _median(lambda: generate_vehicle(heavy), runs)
    print(f"3. generation, conventional car: without gravity {without:.2f} s (baseline), with gravity "
          f"{with_gravity:.2f} s ({with_gravity / without:.1f}x; target < 5 s: {'ok' if with_gravity < 5 else 'MISSED'})")
    print(f"stop_ratio={overhead:.2f} series_ratio={ratio:.2f} gravity_s={with_gravity:.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
