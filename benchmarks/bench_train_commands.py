#!/usr/bin/env python3
"""``simulate`` and ``draw`` on long trains (issue 24), each against its old route in the
same run.

Run from the repository root::

    PYTHONPATH=src python3 benchmarks/bench_train_commands.py                   # 20 and 100 cars
    PYTHONPATH=src python3 benchmarks/bench_train_commands.py --cars 20 --runs 3
    PYTHONPATH=src python3 benchmarks/bench_train_commands.py --dense-100        # + the dense route on 100 cars (~5 min)

The trains are ``examples/make_vehicles.py --cars N`` (24 N DOFs, 48 N states), loaded
through a private derivation cache that the script fills first (the cold load is not
timed).  Measured, each the median of ``--runs`` runs after one warm-up, in one process
(BLAS on one thread, as the library runs):

1. ``simulate()`` through the paper's curve (460 m, 120 km/h, dt = 5 ms, 2761 steps),
   linear (``--linear``) and with flange contact and creep saturation: the sparse route
   (:mod:`express.analysis.time.sparse_march`, chosen by ``route="auto"``) against the dense
   route (``route="dense"``: ``expm`` of the 48 N x 48 N matrix, dense products every
   step) -- the baseline; on 100 cars the dense route takes minutes and runs once, only
   with ``--dense-100``.  The largest difference of ``q`` between the routes, relative
   to its largest value, is printed with it.
2. ``figure_model()`` + PNG of the drawing: the label placement of today against the
   rule as first written (every candidate offset measured, every placed label compared,
   the layout painted) -- the baseline; the same labels placed (checked).

Timings on a machine shared with other jobs are noisy; the ratio against the baseline
of the same run is the figure to read.  The last line is
``simulate_speedup=<x> draw_speedup=<y>`` (the largest train measured).
"""

from __future__ import annotations

import os

for _variable in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_variable, "1")

import argparse  # noqa: E402
import importlib.util  # noqa: E402
import statistics  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))


def _median(function, runs: int) -> tuple[float, object]:
    result = function()  # warm-up (and the compile of any kernel)
    times = []
    for _ in range(runs):
        start = time.perf_counter()
        result = function()
        times.append(time.perf_counter() - start)
    return statistics.median(times), result


def _train(cars: int, folder: Path) -> Path:
    spec = importlib.util.spec_from_file_location("make_vehicles", ROOT / "examples" / "make_vehicles.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)  # type: ignore[union-attr]
    path = folder / f"train{cars}.toml"
    path.write_text(module.vehicle_toml(True, cars=cars), encoding="utf-8")
    return path


def bench_simulate(vehicle, cars: int, runs: int, dense: bool) -> float | None:
    import numpy as np

    from express.analysis.time.simulate import simulate
    from express.rail.track import paper_curve

    track = paper_curve()
    speedup = None
    for label, nonlinear in (("linear", False), ("flange+saturation", True)):
        def run(route, nonlinear=nonlinear):
            return simulate(vehicle, track, flange=nonlinear, saturation=nonlinear, progress=False, route=route)

        sparse_s, sparse = _median(lambda: run("auto"), runs)
        line = f"  simulate {label:<18} route auto {sparse_s:8.2f} s ({sparse.options.get('route', 'dense')})"
        if dense:
            dense_runs = runs if cars <= 40 else 1
            start = time.perf_counter()
            reference = run("dense")
            dense_s = time.perf_counter() - start
            if dense_runs > 1:
                dense_s, reference = _median(lambda: run("dense"), dense_runs)
            difference = float(np.abs(sparse.q - reference.q).max() / np.abs(reference.q).max())
            line += f"   dense route (baseline) {dense_s:8.2f} s   speedup {dense_s / sparse_s:6.1f}x   max|dq|/max|q| {difference:.1e}"
            if not nonlinear:
                speedup = dense_s / sparse_s
        else:
            line += "   dense route: not run (--dense-100)"
        print(line, flush=True)
    return speedup


def _old_place_labels(figure) -> list[str]:
    """The label placement as first written (the baseline)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    from express.drawing import views

    if not isinstance(figure.canvas, FigureCanvasAgg):
        FigureCanvasAgg(figure)
    figure.canvas.draw()
    figure.set_layout_engine("none")
    renderer = figure.canvas.get_renderer()
    hidden: list[str] = []
    for axis in figure.axes:
        placed: list = []
        texts = [t for t in axis.texts if str(t.get_gid() or "").startswith("label:")]
        texts.sort(key=lambda t: t.get_fontsize(), reverse=True)
        for text in texts:
            frame = axis.get_window_extent(renderer)
            offsets = views._BODY_CANDIDATES if text.get_fontsize() >= 6 else views._CANDIDATES
            for offset in offsets:
                text.xyann = offset
                box = text.get_window_extent(renderer)
                inside = frame.x0 <= box.x0 and box.x1 <= frame.x1 and frame.y0 <= box.y0 and box.y1 <= frame.y1
                if inside and not any(box.overlaps(other) for other in placed):
                    placed.append(box)
                    break
            else:
                text.set_visible(False)
                name = str(text.get_gid())[6:]
                if name not in hidden:
                    hidden.append(name)
    return hidden


def bench_draw(path: Path, runs: int, folder: Path) -> float:
    from express.analysis.plots import save_figure
    from express.cli.draw import _geometry
    from express.drawing import views

    geometry = _geometry(path, {})

    def draw():
        figure = views.figure_model(geometry)
        save_figure(figure, folder / "drawing.png")
        return [(t.get_visible(), tuple(t.xyann)) for axis in figure.axes for t in axis.texts]

    new_s, new_labels = _median(draw, runs)
    today = views.place_labels
    views.place_labels = _old_place_labels
    try:
        old_s, old_labels = _median(draw, max(1, runs // 2))
    finally:
        views.place_labels = today
    same = "the same labels" if new_labels == old_labels else "LABELS DIFFER"
    print(f"  draw (figure + PNG)           today {new_s:8.2f} s   first rule (baseline) {old_s:8.2f} s   "
          f"speedup {old_s / new_s:6.1f}x   ({len(geometry.bodies)} bodies; {same})", flush=True)
    return old_s / new_s


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cars", type=int, action="append", help="train length (repeatable; default 20 and 100)")
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--dense-100", action="store_true", help="also run the dense route on trains over 40 cars")
    args = parser.parse_args(argv)
    from machine import cpu_name, usable_cores

    print(f"machine: {cpu_name()}, {usable_cores()} usable cores, load average {os.getloadavg()[0]:.1f}")
    with tempfile.TemporaryDirectory(prefix="bench-train-") as name:  # the trains, their cache, the drawing
        folder = Path(name)
        os.environ.setdefault("EXPRESS_CACHE_DIR", str(folder / "cache"))
        from express.numeric.statespace import load_vehicle

        simulate_speedup = draw_speedup = float("nan")
        for cars in args.cars or [20, 100]:
            path = _train(cars, folder)
            start = time.perf_counter()
            vehicle = load_vehicle(path)
            print(f"{cars} cars: {vehicle.form.size} states (load {time.perf_counter() - start:.1f} s, not timed below)",
                  flush=True)
            speedup = bench_simulate(vehicle, cars, args.runs, cars <= 40 or args.dense_100)
            simulate_speedup = speedup if speedup is not None else simulate_speedup
            draw_speedup = bench_draw(path, args.runs, folder)
    print(f"simulate_speedup={simulate_speedup:.1f} draw_speedup={draw_speedup:.1f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
