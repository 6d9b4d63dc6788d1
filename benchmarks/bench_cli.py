#!/usr/bin/env python3
"""CLI start-up benchmark: ``express --help`` against ``python -c "import numpy"``.

Run from the repository root::

    PYTHONPATH=src python3 benchmarks/bench_cli.py            # ~30 s
    PYTHONPATH=src python3 benchmarks/bench_cli.py --runs 5   # quicker

Every command is started as a fresh process, as a user starts it, and timed wall clock
(medians of ``--runs`` starts, the commands taking turns so that a change of load hits
them alike):

* ``express --help``, ``express --version`` and ``express simulate --help`` through the
  installed console script when there is one next to this interpreter (otherwise, and
  in any case also, ``python -m express --help``);
* baselines: ``python -c "import numpy"`` (the named baseline) and ``python -c pass``
  (the interpreter alone, the floor nothing can go below).

Also printed: the heavy libraries (SymPy, SciPy, Matplotlib, Numba, NumPy) found in
``sys.modules`` after ``express --help`` in a fresh interpreter, and the import time of
``express.cli`` (``python -X importtime``).  Target: ``express --help`` <= 0.3 s wall.
The last line is ``help_s=<x> import_numpy_s=<y> ratio=<x/y>``.  Exit code 0 even when
the target is missed (``TARGET MISSED``).
"""

from __future__ import annotations

import argparse
import datetime
import os
import platform
import re
import statistics
import subprocess
import sys
import time
from pathlib import Path

from machine import cpu_name, usable_cores  # benchmarks/machine.py

ROOT = Path(__file__).resolve().parents[1]
TARGET_S = 0.3
HEAVY = ("sympy", "scipy", "matplotlib", "numba", "numpy")


def environment() -> dict[str, str]:
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([str(ROOT / "src"), env.get("PYTHONPATH", "")]).rstrip(os.pathsep)
    return env


def commands() -> dict[str, list[str]]:
    python = sys.executable
    found = {}
    script = Path(python).with_name("express")
    if script.is_file():  # the console script pip installed (not a shell shim)
        found["express --help"] = [str(script), "--help"]
        found["express --version"] = [str(script), "--version"]
        found["express simulate --help"] = [str(script), "simulate", "--help"]
    found["python -m express --help"] = [python, "-m", "express", "--help"]
    found["python -c 'import numpy' (baseline)"] = [python, "-c", "import numpy"]
    found["python -c pass (floor)"] = [python, "-c", "pass"]
    return found


def time_starts(named: dict[str, list[str]], runs: int) -> dict[str, float]:
    env = environment()
    times: dict[str, list[float]] = {name: [] for name in named}
    for argv in named.values():  # warm the file cache
        subprocess.run(argv, env=env, capture_output=True, check=True)
    for _ in range(runs):
        for name, argv in named.items():
            start = time.perf_counter()
            subprocess.run(argv, env=env, capture_output=True, check=True)
            times[name].append(time.perf_counter() - start)
    return {name: statistics.median(values) for name, values in times.items()}


def heavy_modules() -> list[str]:
    code = ("import sys, contextlib, io\nfrom express.cli import main\n"
            "with contextlib.redirect_stdout(io.StringIO()):\n    main(['--help'])\n"
            f"print(','.join(m for m in {HEAVY!r} if m in sys.modules))")
    done = subprocess.run([sys.executable, "-c", code], env=environment(), capture_output=True, text=True, check=True)
    return [m for m in done.stdout.strip().split(",") if m]


def cli_import_ms() -> float:
    done = subprocess.run([sys.executable, "-X", "importtime", "-c", "import express.cli"], env=environment(),
                          capture_output=True, text=True, check=True)
    for line in done.stderr.splitlines():
        match = re.match(r"import time:\s+\d+ \|\s+(\d+) \| express\.cli$", line)
        if match:
            return int(match.group(1)) / 1e3
    return float("nan")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=15, help="starts per command (default 15)")
    args = parser.parse_args(argv)
    try:
        load = ", ".join(f"{x:.2f}" for x in os.getloadavg())
    except OSError:
        load = "?"
    print("EXPRESS CLI start-up benchmark")
    print(f"date        {datetime.datetime.now().isoformat(timespec='seconds')}")
    print(f"python      {platform.python_version()} ({sys.executable})")
    print(f"cpu         {cpu_name()}; usable cores {usable_cores()}; load average {load}")
    named = commands()
    medians = time_starts(named, args.runs)
    baseline = medians["python -c 'import numpy' (baseline)"]
    print(f"\nwall time of a fresh start, medians of {args.runs}:")
    for name, value in medians.items():
        print(f"  {name:40s} {value:6.3f} s   ratio to import numpy {value / baseline:.2f}")
    heavy = heavy_modules()
    print(f"\nheavy modules after express --help: {', '.join(heavy) or 'none'} (of {', '.join(HEAVY)})")
    print(f"import time of express.cli (cumulative, -X importtime): {cli_import_ms():.1f} ms")
    help_s = medians.get("express --help", medians["python -m express --help"])
    if help_s > TARGET_S:
        print(f"\nTARGET MISSED: express --help {help_s:.3f} s > {TARGET_S} s")
    print(f"\nhelp_s={help_s:.3f} import_numpy_s={baseline:.3f} ratio={help_s / baseline:.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
