#!/usr/bin/env python3
"""Export benchmark: writers that follow the non-zero entries against the old dense ones.

Run from the repository root::

    PYTHONPATH=src python3 benchmarks/bench_export.py               # 5, 10, 20 cars (~3 min)
    PYTHONPATH=src python3 benchmarks/bench_export.py --quick       # 2 and 5 cars, 1 run
    PYTHONPATH=src python3 benchmarks/bench_export.py --cars 5,10,20,40 --runs 5

Models: N-car trains of the forced-steering vehicle written by
``examples/make_vehicles.py`` (``vehicle_toml(True, cars=N)``, the same text as
``make_vehicles.py --cars N``), loaded and generated once, untimed
(``generate_vehicle``).  Then every export format of ``express.export`` is timed on the
same equations record, and, in the same run, the baseline: copies, kept below, of the
dense writers the exports used before they followed the non-zero entries:

* ``dense_json``: the JSON contract version 1, every entry of every matrix printed with
  ``sympy.sstr`` as rows of strings (``"0"`` included);
* ``dense_matlab``: the MATLAB matrix assignments, visiting all ``n x n`` (``n x m``)
  positions with ``mat[i, j]`` and printing each non-zero entry.

Every timing is the median of ``--runs`` runs after one untimed warm-up, with SymPy's
cache cleared before each run, for both sides.  Agreement: the version 2 document, read
back with ``dense_rows``, holds exactly the entry texts of the dense document, and the
MATLAB assignment lines of both writers are the same.  The fitted exponent is the
least-squares slope of ``log(time)`` against ``log(cars)``.

Exit code 0 even when a check fails (``CHECK FAILED`` is printed then).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import platform
import re
import statistics
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
for _extra in (ROOT / "examples", ROOT / "src"):
    if str(_extra) not in sys.path:
        sys.path.insert(0, str(_extra))

import sympy as sp  # noqa: E402
from make_vehicles import vehicle_toml  # noqa: E402
from sympy.core.cache import clear_cache  # noqa: E402
from sympy.printing.octave import OctaveCodePrinter  # noqa: E402

from express.export import FORMATS  # noqa: E402
from express.export.json_export import dense_rows, matrix_items, parameter_symbols  # noqa: E402
from express.export.matlab import matlab_local_names, symbol_renaming, to_matlab  # noqa: E402
from express.io import load_model  # noqa: E402
from express.rail.build import generate_vehicle  # noqa: E402
from machine import cpu_name, usable_cores  # noqa: E402  (benchmarks/machine.py)

# --------------------------------------------------------------------------- baselines
# Copies of the writers as they were before the exports followed the non-zero entries
# (src/express/export/json_export.py and matlab.py of commit 0a9c427): the work they do
# per matrix is what is measured, so they are kept as they were, not improved.


def _dense_rows(mat: sp.ImmutableMatrix) -> list[list[str]]:
    return [[sp.sstr(mat[i, j]) for j in range(mat.cols)] for i in range(mat.rows)]


def dense_json(eom) -> str:
    """The JSON contract version 1: every entry of every matrix as a string."""
    items = matrix_items(eom)
    parameter_symbols(eom, items)
    doc = {"dofs": list(eom.dofs), "eliminated": list(eom.eliminated), "parameters": list(eom.parameters)}
    for key, mat in items:
        if key not in ("M", "C", "K") and eom.inputs and "inputs" not in doc:
            doc["inputs"] = list(eom.inputs)
        doc[key] = _dense_rows(mat)
    if eom.inputs and "inputs" not in doc:
        doc["inputs"] = list(eom.inputs)
    doc["values"] = {name: float(eom.values[name]) for name in sorted(eom.values)}
    doc["units"] = {name: str(eom.units[name]) for name in sorted(eom.units)}
    return json.dumps(doc, indent=2, ensure_ascii=False, allow_nan=False) + "\n"


class _OctavePrinter(OctaveCodePrinter):
    def _print_Float(self, expr):  # noqa: N802
        return repr(float(expr))


def dense_matlab(eom) -> str:
    """The MATLAB matrix assignments of the old writer: all n x n positions visited."""
    items = matrix_items(eom)
    outputs = [key for key, _ in items]
    locals_ = matlab_local_names(eom.parameters, outputs)
    rename = symbol_renaming(eom, items, locals_)
    printer = _OctavePrinter({"strict": True})
    out = []
    for key, mat in items:
        out.append(f"{key} = zeros({mat.rows}, {mat.cols});")
        for i in range(mat.rows):
            for j in range(mat.cols):
                entry = mat[i, j]
                if entry == 0:
                    continue
                if j < i and j < mat.rows and i < mat.cols and entry == mat[j, i]:
                    out.append(f"{key}({i + 1}, {j + 1}) = {key}({j + 1}, {i + 1});")
                else:
                    out.append(f"{key}({i + 1}, {j + 1}) = {printer.doprint(entry.xreplace(rename) if rename else entry)};")
    return "\n".join(out) + "\n"


BASELINES = {"json": dense_json, "matlab": dense_matlab}

# --------------------------------------------------------------------------- timing


def median_time(function, argument, runs: int) -> tuple[float, object]:
    """Median wall time of ``function(argument)`` over ``runs`` runs after a warm-up."""
    result = function(argument)
    times = []
    for _ in range(runs):
        clear_cache()
        start = time.perf_counter()
        function(argument)
        times.append(time.perf_counter() - start)
    return statistics.median(times), result


def exponent(cars: list[int], times: list[float]) -> float:
    """Least-squares slope of log(time) against log(cars)."""
    xs, ys = [math.log(c) for c in cars], [math.log(t) for t in times]
    mx, my = statistics.fmean(xs), statistics.fmean(ys)
    return sum((x - mx) * (y - my) for x, y in zip(xs, ys, strict=True)) / sum((x - mx) ** 2 for x in xs)


def agree(fmt: str, new: str, old: str) -> bool:
    if fmt == "json":
        doc_new, doc_old = json.loads(new), json.loads(old)
        keys = [key for key, value in doc_old.items() if isinstance(value, list) and value and isinstance(value[0], list)]
        return bool(keys) and all(dense_rows(doc_new[key]) == doc_old[key] for key in keys)
    pattern = re.compile(r"^\w+(\(\d+, \d+\) = | = zeros\()")
    return [ln for ln in new.splitlines() if pattern.match(ln)] == [ln for ln in old.splitlines() if pattern.match(ln)]


def load_train(cars: int):
    with tempfile.TemporaryDirectory(prefix="express-bench-") as tmp:
        path = Path(tmp) / f"train{cars}.toml"
        path.write_text(vehicle_toml(True, cars=cars), encoding="utf-8")
        model = load_model(path)
    start = time.perf_counter()
    equations = generate_vehicle(model).equations
    return equations, time.perf_counter() - start


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--cars", default="5,10,20", help="train sizes, comma-separated (default 5,10,20)")
    parser.add_argument("--runs", type=int, default=3, help="timed runs per measurement (default 3)")
    parser.add_argument("--quick", action="store_true", help="2 and 5 cars, one run (smoke test)")
    args = parser.parse_args(argv)
    sizes = [2, 5] if args.quick else [int(c) for c in args.cars.split(",")]
    runs = 1 if args.quick else args.runs
    print(f"machine: {cpu_name()}, {usable_cores()} usable cores, Python {platform.python_version()}, "
          f"SymPy {sp.__version__}; load average {os.getloadavg()[0]:.2f} at start")
    print(f"medians of {runs} run(s) after a warm-up; SymPy cache cleared before each run")
    table: dict[str, dict[str, list[float]]] = {fmt: {"new": [], "old": []} for fmt in FORMATS}
    failed = False
    for cars in sizes:
        equations, generation = load_train(cars)
        nnz = sum(len(mat.todok()) for mat in equations.matrices.values())
        size = sum(mat.rows * mat.cols for mat in equations.matrices.values())
        print(f"\ncars={cars} dofs={len(equations.dofs)} inputs={len(equations.inputs)} "
              f"non_zero={nnz} of {size} ({100.0 * nnz / size:.2f} %) generate_s={generation:.2f}")
        for fmt, exporter in FORMATS.items():
            new_s, new_text = median_time(exporter if fmt != "matlab" else to_matlab, equations, runs)
            table[fmt]["new"].append(new_s)
            line = f"  format={fmt:<6} express_s={new_s:.3f} bytes={len(new_text.encode())}"
            if fmt in BASELINES:
                old_s, old_text = median_time(BASELINES[fmt], equations, runs)
                table[fmt]["old"].append(old_s)
                same = agree(fmt, new_text, old_text)
                failed |= not same
                line += f" dense_s={old_s:.3f} ratio={old_s / new_s:.1f} dense_bytes={len(old_text.encode())} agree={same}"
            print(line + ("" if line.endswith("True") or fmt not in BASELINES else "  CHECK FAILED"))
    if len(sizes) > 1:
        print(f"\nfitted exponent of time vs cars ({sizes[0]}-{sizes[-1]} cars):")
        for fmt, columns in table.items():
            line = f"  format={fmt:<6} express={exponent(sizes, columns['new']):.2f}"
            if columns["old"]:
                line += f" dense={exponent(sizes, columns['old']):.2f}"
            print(line)
    print(f"\nload average {os.getloadavg()[0]:.2f} at the end")
    if failed:
        print("CHECK FAILED")
    return 0


if __name__ == "__main__":
    sys.exit(main())
