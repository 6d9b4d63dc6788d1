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

Then the **one-car commands** a script calls (``--one-car`` runs only these): ``express
generate examples/forced-steering.toml --format json -o <temporary file>``, ``express
eigen`` and ``express critical-speed`` of the same car, fresh processes, medians of
``--runs`` starts taking turns, against ``python -c "import numpy, sympy"`` (what the
symbolic model needs at least), with the heavy modules each leaves in ``sys.modules``
among Numba, Matplotlib and the profile-contact modules (none is needed by a car without
wheel and rail profiles) and ``scipy.optimize`` (one root finder, ``brentq``, of the
Kalker creep coefficients in ``express.rail.contact``: needed, and some 0.2-0.4 s).

The last line is ``help_s=<x> import_numpy_s=<y> ratio=<x/y> generate_s=<z>``.  Exit
code 0 even when the target is missed (``TARGET MISSED``).
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
#: Heavy modules a one-car command might load; each found loaded is printed.
NEEDLESS = ("numba", "scipy.optimize", "scipy.integrate", "scipy.interpolate", "scipy.signal", "matplotlib",
            "express.rail.profile_contact", "express.rail.contact_tables", "express.analysis.time.simulate")
CAR = ROOT / "examples" / "forced-steering.toml"


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


def one_car_commands(output: Path) -> dict[str, list[str]]:
    script = Path(sys.executable).with_name("express")
    express = [str(script)] if script.is_file() else [sys.executable, "-m", "express"]
    return {
        "express generate car --format json": [*express, "generate", str(CAR), "--format", "json", "-o", str(output)],
        "express eigen car": [*express, "eigen", str(CAR)],
        "express critical-speed car": [*express, "critical-speed", str(CAR)],
        "python -c 'import numpy, sympy' (baseline)": [sys.executable, "-c", "import numpy, sympy"],
    }


def needless_modules(arguments: list[str]) -> list[str]:
    """The modules of :data:`NEEDLESS` loaded by ``express <arguments>`` in a fresh interpreter."""
    code = ("import sys, contextlib, io\nfrom express.cli import main\n"
            f"with contextlib.redirect_stdout(io.StringIO()):\n    main({arguments!r})\n"
            f"print(','.join(m for m in {NEEDLESS!r} if m in sys.modules))")
    done = subprocess.run([sys.executable, "-c", code], env=environment(), capture_output=True, text=True, check=True)
    return [m for m in done.stdout.strip().splitlines()[-1].split(",") if m]


def one_car(runs: int) -> float:
    """Print the one-car section; return the median of the generate command [s]."""
    import tempfile

    with tempfile.TemporaryDirectory(prefix="express-cli-") as folder:
        output = Path(folder) / "car.json"
        named = one_car_commands(output)
        medians = time_starts(named, runs)
        baseline = medians["python -c 'import numpy, sympy' (baseline)"]
        print(f"\none-car commands (examples/forced-steering.toml), wall time of a fresh start, medians of {runs}:")
        for name, value in medians.items():
            print(f"  {name:44s} {value:6.3f} s   ratio to import numpy, sympy {value / baseline:.2f}")
        for name, arguments in (("generate", ["generate", str(CAR), "--format", "json", "-o", str(output)]),
                                ("eigen", ["eigen", str(CAR)]), ("critical-speed", ["critical-speed", str(CAR)])):
            print(f"  heavy modules loaded by {name}: {', '.join(needless_modules(arguments)) or 'none'}")
    return medians["express generate car --format json"]


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=15, help="starts per command (default 15)")
    parser.add_argument("--one-car", action="store_true", help="only the one-car commands")
    args = parser.parse_args(argv)
    try:
        load = ", ".join(f"{x:.2f}" for x in os.getloadavg())
    except OSError:
        load = "?"
    print("EXPRESS CLI start-up benchmark")
    print(f"date        {datetime.datetime.now().isoformat(timespec='seconds')}")
    print(f"python      {platform.python_version()} ({sys.executable})")
    print(f"cpu         {cpu_name()}; usable cores {usable_cores()}; load average {load}")
    if args.one_car:
        generate_s = one_car(args.runs)
        print(f"\ngenerate_s={generate_s:.3f}")
        return 0
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
    generate_s = one_car(args.runs)
    if help_s > TARGET_S:
        print(f"\nTARGET MISSED: express --help {help_s:.3f} s > {TARGET_S} s")
    print(f"\nhelp_s={help_s:.3f} import_numpy_s={baseline:.3f} ratio={help_s / baseline:.2f} generate_s={generate_s:.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
