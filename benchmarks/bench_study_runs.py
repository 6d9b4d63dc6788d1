#!/usr/bin/env python3
"""A 400-point critical-speed study against 20 single ``critical-speed`` runs, from the
command line (issue 16: "a 400-point critical-speed study costs no more than 20 single
``critical-speed`` runs").

Run from the repository root::

    PYTHONPATH=src python3 benchmarks/bench_study_runs.py              # 3 repeats (~4 minutes)
    PYTHONPATH=src python3 benchmarks/bench_study_runs.py --repeats 1  # one round

Both sides are measured as a user pays for them, in fresh processes
(``python -m express``, the ``express`` command), wall clock from start to exit:

- **study**: ``express study STUDY.toml -o x.csv`` over a 20 x 20 grid of the conicity
  ``Gamma`` (0.08 .. 0.4) and the primary longitudinal stiffness ``kx1`` (1 .. 8 MN/m,
  geometric) of the 24-DOF forced-steering car, output ``critical_speed`` with the
  default options (``check = "grid"``: the value of ``express critical-speed``), on the
  default workers (all local cores); also with ``--workers 1`` (one core, the fair
  comparison per core) and with ``check = "local"``;
- **baseline**: 20 runs of ``express critical-speed MODEL --set Gamma=... --set kx1=...
  --json`` one after the other (as a script would call them), for 20 points of the
  same grid; their values are checked against the study's rows (1e-9 relative).

The rounds alternate study and baseline, so that other load on the machine falls on
both; medians are printed, with the load average (``os.getloadavg``) and the CPU used
by other processes during the run. The last line is
``study_s=<a> runs20_s=<b> ratio=<a/b> workers1_ratio=<c> local_ratio=<d>``; target:
ratio <= 1. Exit code 0 even when the target is missed (``TARGET MISSED`` is printed).
"""

from __future__ import annotations

import argparse
import csv
import json
import os
import platform
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from bench_study import Contention  # benchmarks/bench_study.py (sets BLAS to one thread)
from machine import cpu_name, usable_cores  # benchmarks/machine.py

ROOT = Path(__file__).resolve().parents[1]
MODEL = ROOT / "examples" / "forced-steering.toml"
SIDE = 20  # 20 x 20 = 400 points
RUNS = 20


def _environment() -> dict[str, str]:
    return dict(os.environ, PYTHONPATH=str(ROOT / "src") + os.pathsep + os.environ.get("PYTHONPATH", ""))


def _express(arguments: list[str]) -> tuple[float, str]:
    """Wall seconds of one fresh ``express`` process, and its standard output."""
    start = time.perf_counter()
    done = subprocess.run([sys.executable, "-m", "express", *arguments], env=_environment(),
                          capture_output=True, text=True)
    wall = time.perf_counter() - start
    if done.returncode != 0:
        raise RuntimeError(f"express {' '.join(arguments)}: status {done.returncode}: {done.stderr.strip()}")
    return wall, done.stdout


def _study_file(folder: Path, check: str) -> Path:
    path = folder / f"study-{check}.toml"
    path.write_text(f"""[study]
model = "{MODEL}"
outputs = ["critical_speed"]
[study.parameters]
Gamma = {{ from = 0.08, to = 0.4, count = {SIDE} }}
kx1 = {{ from = "1 MN/m", to = "8 MN/m", count = {SIDE}, scale = "log" }}
[study.options]
check = "{check}"
""")
    return path


def _study(study: Path, output: Path, extra: list[str]) -> float:
    output.unlink(missing_ok=True)
    wall, _ = _express(["study", str(study), "-o", str(output), "--json", *extra])
    return wall


def _rows(output: Path) -> list[list[float]]:
    with open(output, newline="") as stream:
        rows = list(csv.reader(stream))[1:]
    return [[float(row[0]), float(row[1]), float(row[2])] for row in rows]


def _single_runs(points: list[list[float]]) -> tuple[float, list[float]]:
    """Wall seconds of the 20 runs one after the other, and their critical speeds."""
    total, speeds = 0.0, []
    for gamma, kx1, _speed in points:
        wall, out = _express(["critical-speed", str(MODEL), "--set", f"Gamma={gamma!r}", "--set", f"kx1={kx1!r}",
                              "--json"])
        total += wall
        speeds.append(json.loads(out)["critical_speed"])
    return total, speeds


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3, help="rounds (medians)")
    args = parser.parse_args(argv)
    contention = Contention()
    load = os.getloadavg()
    print(f"EXPRESS study against single runs, {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}")
    print(f"machine     {cpu_name()}; usable cores {usable_cores()}; Python {platform.python_version()}; "
          f"load average {load[0]:.2f} {load[1]:.2f} {load[2]:.2f}")
    times: dict[str, list[float]] = {"study": [], "study --workers 1": [], "study, local check": [], "20 runs": []}
    with tempfile.TemporaryDirectory() as name:
        folder = Path(name)
        grid, local = _study_file(folder, "grid"), _study_file(folder, "local")
        output = folder / "x.csv"
        _study(grid, output, [])  # warm-up (file caches, compiled Python files)
        rows = _rows(output)
        chosen = rows[:: len(rows) // RUNS][:RUNS]  # 20 points spread over the grid
        worst = 0.0
        for _ in range(args.repeats):
            times["study"].append(_study(grid, output, []))
            rows = _rows(output)
            times["study --workers 1"].append(_study(grid, output, ["--workers", "1"]))
            times["study, local check"].append(_study(local, folder / "local.csv", []))
            total, speeds = _single_runs(chosen)
            times["20 runs"].append(total)
            for (_gamma, _kx1, study_speed), single in zip(chosen, speeds, strict=True):
                worst = max(worst, abs(study_speed - single) / abs(single))
        assert [r[:2] for r in _rows(output)] == [r[:2] for r in rows] and len(rows) == SIDE * SIDE
    medians = {key: statistics.median(values) for key, values in times.items()}
    runs = medians["20 runs"]
    print(f"{SIDE * SIDE}-point critical-speed grid study (24-DOF car, Gamma x kx1) against {RUNS} single runs, "
          f"fresh processes, wall clock, {args.repeats} round(s) in turn:")
    for key, values in times.items():
        ratio = f"   {medians[key] / runs:.2f} x the 20 runs" if key != "20 runs" else f"   {runs / RUNS:.2f} s per run"
        print(f"   {key:24} median {medians[key]:6.2f} s (runs: {', '.join(f'{v:.2f}' for v in values)}){ratio}")
    ratio = medians["study"] / runs
    print(f"   ratio study / 20 runs = {ratio:.2f} (target <= 1){'' if ratio <= 1 else '   TARGET MISSED'}; "
          f"one core: {medians['study --workers 1'] / runs:.2f}; "
          f"the study's critical speeds equal the single runs' to {worst:.1e} relative (<= 1e-9: {worst <= 1e-9})")
    load = os.getloadavg()
    others = contention.cores()
    print(f"load average at the end {load[0]:.2f} {load[1]:.2f} {load[2]:.2f}; CPU used by other processes during "
          f"the run: {others:.2f} cores on average" if others is not None else "")
    print(f"study_s={medians['study']:.2f} runs20_s={runs:.2f} ratio={ratio:.2f} "
          f"workers1_ratio={medians['study --workers 1'] / runs:.2f} local_ratio={medians['study, local check'] / runs:.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
