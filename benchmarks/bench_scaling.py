#!/usr/bin/env python3
"""Train scaling benchmark: generation and JSON export of 1 to 100 cars, time and memory.

Run from the repository root::

    PYTHONPATH=src python3 benchmarks/bench_scaling.py            # 1..100 cars, ~4 min
    PYTHONPATH=src python3 benchmarks/bench_scaling.py --quick    # 1..40 cars, ~1 min
    PYTHONPATH=src python3 benchmarks/bench_scaling.py --cars 1 10 20 40 100 200

Every train is written by ``examples/make_vehicles.py`` (``vehicle_toml(True, cars=N)``,
the forced-steering car coupled N times: 11 bodies, 28 DOFs and 54 elements per car)
and measured the way a new user meets it, in fresh processes:

1. **The command**: ``express generate train.toml --format json -o train.json``, wall
   clock from start to exit (interpreter start, imports, reading, generation, export,
   writing).  Median of ``--runs`` starts up to 20 cars, one start beyond.
2. **The phases**, in a fresh process per size (medians of as many processes as
   starts of the command): ``load_model``, ``generate_vehicle``
   (exact M, C, K, P, Pd with the pins eliminated), the JSON text (``to_json``) and
   the write; the peak resident memory (``ru_maxrss``) and its growth over the process
   once everything is imported (what the model itself costs).

The baseline is linear cost from the 10-car train, measured in the same run:
``ratio = t(N) / (t(10) N / 10)`` (1 = linear; above 1 = worse than linear).  The
exponents ``p`` of ``time ~ cars^p`` and ``memory growth ~ cars^p`` are least-squares fits
over 10, 20 and 40 cars.  Targets (issue 16): the 100-car train generated and exported
in <= 60 s, exponents <= 1.3.

The 100-car train (1 100 bodies, 5 598 elements, 11 196 connection points) is within
the readers' default limits (``express.base.limits``: 2 000 bodies, 10 000 elements, 20 000
points, up to 178 cars): no ``EXPRESS_MAX_*`` variable is set for the default sizes.
Only a size beyond the defaults (``--cars 200``) gets the limits it needs raised for
its own processes, and the script says so.  The last line is
``cars100_s=<x> time_exponent=<p> memory_exponent=<q>``.  Exit code 0 even when a target
is missed (``TARGET MISSED``).
"""

from __future__ import annotations

import argparse
import datetime
import importlib.util
import json
import math
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
TARGET_S = 60.0
TARGET_EXPONENT = 1.3
FIT = (10, 20, 40)
#: Items per car of the train, and the offset (the two ends have no couplers): count = per car x cars - offset.
PER_CAR = {"bodies": (11, 0), "elements": (56, 2), "points": (112, 4)}

#: The child of item 2: argv = model file, output file; prints one JSON line.
PHASES = """
import json, resource, sys, time
import express.io, express.rail.build, express.rail.contact, express.export  # everything imported before measuring
from express.export import to_json
from express.io.output import write_text

def rss_kib():
    with open("/proc/self/status") as status:
        return next(int(line.split()[1]) for line in status if line.startswith("VmRSS:"))

path, output = sys.argv[1], sys.argv[2]
figures = {"rss_imported_kib": rss_kib()}
start = time.perf_counter()
model = express.io.load_model(path)
figures["load_s"] = time.perf_counter() - start
start = time.perf_counter()
equations = express.rail.build.generate_vehicle(model).equations
figures["generate_s"] = time.perf_counter() - start
start = time.perf_counter()
text = to_json(equations)
figures["export_s"] = time.perf_counter() - start
start = time.perf_counter()
write_text(output, text)
figures["write_s"] = time.perf_counter() - start
figures["peak_rss_kib"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
figures["dofs"] = len(equations.dofs)
figures["inputs"] = len(equations.inputs)
figures["nonzeros"] = sum(len(m.todok()) for m in equations.matrices.values())
figures["json_bytes"] = len(text.encode())
print(json.dumps(figures))
"""


def make_vehicles():
    spec = importlib.util.spec_from_file_location("make_vehicles", ROOT / "examples" / "make_vehicles.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def environment(cars: int, notes: list[str]) -> dict[str, str]:
    """This checkout first on the path; the model limits raised only for a train beyond the defaults."""
    sys.path.insert(0, str(ROOT / "src"))
    from express.base.limits import LIMITS

    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([str(ROOT / "src"), env.get("PYTHONPATH", "")]).rstrip(os.pathsep)
    for name, (per_car, offset) in PER_CAR.items():
        limit = LIMITS[name]
        needed = per_car * cars - offset
        if limit.variable not in os.environ and needed > limit.default:
            env[limit.variable] = str(2 * needed)
            notes.append(f"{cars} cars: {limit.variable}={env[limit.variable]} ({needed} {limit.unit}; "
                         f"default limit {limit.default})")
    return env


def command_time(path: Path, output: Path, env: dict[str, str], runs: int) -> float:
    script = Path(sys.executable).with_name("express")
    argv = [str(script)] if script.is_file() else [sys.executable, "-m", "express"]
    times = []
    for _ in range(runs):
        start = time.perf_counter()
        done = subprocess.run([*argv, "generate", str(path), "--format", "json", "-o", str(output)], env=env,
                              capture_output=True, text=True)
        times.append(time.perf_counter() - start)
        if done.returncode != 0:
            raise RuntimeError(f"express generate failed ({done.returncode}): {done.stderr.strip()}")
    return statistics.median(times)


def phases(path: Path, output: Path, env: dict[str, str]) -> dict:
    done = subprocess.run([sys.executable, "-c", PHASES, str(path), str(output)], env=env, capture_output=True,
                          text=True)
    if done.returncode != 0:
        raise RuntimeError(f"phases failed: {done.stderr.strip()[-500:]}")
    return json.loads(done.stdout.strip().splitlines()[-1])


def exponent(cars: list[int], values: list[float]) -> float:
    """Least-squares slope of log(value) against log(cars)."""
    x = [math.log(c) for c in cars]
    y = [math.log(max(v, 1e-12)) for v in values]
    mx, my = sum(x) / len(x), sum(y) / len(y)
    return sum((a - mx) * (b - my) for a, b in zip(x, y, strict=True)) / sum((a - mx) ** 2 for a in x)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="1..40 cars")
    parser.add_argument("--cars", type=int, nargs="+", help="train sizes (default 1 2 5 10 20 40 100)")
    parser.add_argument("--runs", type=int, default=3, help="starts of the command up to 20 cars (default 3)")
    args = parser.parse_args(argv)
    sizes = sorted(set(args.cars or ((1, 2, 5, 10, 20, 40) if args.quick else (1, 2, 5, 10, 20, 40, 100))))
    try:
        load = ", ".join(f"{x:.2f}" for x in os.getloadavg())
    except OSError:
        load = "?"
    import sympy

    print("EXPRESS train scaling benchmark" + (" (--quick)" if args.quick else ""))
    print(f"date        {datetime.datetime.now().isoformat(timespec='seconds')}")
    print(f"python      {platform.python_version()}; sympy {sympy.__version__}")
    print(f"cpu         {cpu_name()}; usable cores {usable_cores()}; load average {load}")
    writer = make_vehicles()
    notes: list[str] = []
    rows = {}
    with tempfile.TemporaryDirectory(prefix="express-scaling-") as folder:
        for cars in sizes:
            path = Path(folder) / f"train{cars}.toml"
            path.write_text(writer.vehicle_toml(True, cars=cars), encoding="utf-8")
            env = environment(cars, notes)
            output = Path(folder) / f"train{cars}.json"
            runs = args.runs if cars <= 20 else 1
            wall = command_time(path, output, env, runs)
            measured = [phases(path, output, env) for _ in range(runs)]
            figures = {key: statistics.median(m[key] for m in measured) for key in measured[0]}
            figures["command_s"] = wall
            figures["file_bytes"] = path.stat().st_size
            rows[cars] = figures
            print(f"  {cars:4d} cars: command {wall:7.2f} s (load {figures['load_s']:.2f}, generate "
                  f"{figures['generate_s']:.2f}, JSON {figures['export_s']:.2f}, write {figures['write_s']:.2f}); "
                  f"peak RSS {figures['peak_rss_kib'] / 1024:.0f} MiB", flush=True)
    for note in notes:
        print(f"note: {note}")
    reference = rows.get(10)
    print("\ncars  DOFs  inputs  non-zeros  JSON MB | command s  ratio | load s  generate s  JSON s | "
          "peak RSS MiB  growth MiB")
    for cars, row in rows.items():
        ratio = row["command_s"] / (reference["command_s"] * cars / 10) if reference else float("nan")
        growth = (row["peak_rss_kib"] - row["rss_imported_kib"]) / 1024
        print(f"{cars:4d} {row['dofs']:5d} {row['inputs']:7d} {row['nonzeros']:10d} {row['json_bytes'] / 1e6:8.2f} | "
              f"{row['command_s']:9.2f} {ratio:6.2f} | {row['load_s']:6.2f} {row['generate_s']:11.2f} "
              f"{row['export_s']:7.2f} | {row['peak_rss_kib'] / 1024:12.0f} {growth:11.1f}")
    missed = []
    time_exponent = memory_exponent = float("nan")
    if all(c in rows for c in FIT):
        fits = {}
        for key in ("command_s", "load_s", "generate_s", "export_s"):
            fits[key] = exponent(list(FIT), [rows[c][key] for c in FIT])
        fits["memory growth"] = exponent(list(FIT), [rows[c]["peak_rss_kib"] - rows[c]["rss_imported_kib"] for c in FIT])
        fits["in-process total"] = exponent(list(FIT), [rows[c]["load_s"] + rows[c]["generate_s"] + rows[c]["export_s"]
                                                        for c in FIT])
        print(f"\nexponents p of cars^p over {', '.join(map(str, FIT))} cars (target <= {TARGET_EXPONENT}): "
              + ", ".join(f"{k} {v:.2f}" for k, v in fits.items()))
        time_exponent = max(fits["command_s"], fits["in-process total"])
        memory_exponent = fits["memory growth"]
        missed += [f"{k} exponent {v:.2f}" for k, v in fits.items() if v > TARGET_EXPONENT]
    cars100 = rows.get(100, {}).get("command_s", float("nan"))
    if 100 in rows and cars100 > TARGET_S:
        missed.append(f"100 cars took {cars100:.1f} s")
    if missed:
        print("TARGET MISSED: " + "; ".join(missed))
    print(f"cars100_s={cars100:.2f} time_exponent={time_exponent:.2f} memory_exponent={memory_exponent:.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
