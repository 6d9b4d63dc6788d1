#!/usr/bin/env python3
"""What an import of SciPy's sparse package costs a warm command (issue 35, item 7).

Three algorithms are written in EXPRESS although SciPy has them: the reverse
Cuthill-McKee order (``src/express/analysis/frequency/banded.py``, used by every ``frf``), the
θ_m table of the sparse time march (``src/express/analysis/time/sparse_march.py``) and a
row product (``src/express/analysis/modes/mode_energies.py``, SciPy's sparse product from 200
DOFs up).  They stay copies only where importing SciPy's module would decide a stated
target: each copy is tested against SciPy (``tests/test_banded.py``,
``tests/test_sparse_march.py``).  This script measures, in fresh interpreters, the
import times against the warm ``express frf`` of the conventional car (target ≤ 0.5 s,
``docs/benchmarks.md``, "Figures with the warm entry").

Run from the repository root::

    PYTHONPATH=src python3 benchmarks/bench_imports.py [--runs 7]

Printed: the median wall time of each import (its increment over ``import numpy``), the
warm ``frf``, and the ratio of each increment to the warm ``frf``.
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from machine import cpu_name, usable_cores  # benchmarks/machine.py

ROOT = Path(__file__).resolve().parents[1]
IMPORTS = {
    "numpy (baseline)": "import numpy",
    "scipy.linalg": "import numpy, scipy.linalg",
    "scipy.sparse": "import numpy, scipy.sparse",
    "scipy.sparse.csgraph (RCM)": "import numpy, scipy.sparse.csgraph",
    "scipy.sparse.linalg (expm_multiply)": "import numpy, scipy.sparse.linalg",
}


def _wall(command: list[str], env: dict[str, str], runs: int) -> float:
    times = []
    for _ in range(runs):
        start = time.perf_counter()
        subprocess.run(command, check=True, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=7)
    runs = parser.parse_args().runs
    env = dict(os.environ, PYTHONPATH=str(ROOT / "src"))
    print(f"# {cpu_name()}, {usable_cores()} usable cores, load {os.getloadavg()[0]:.2f}; medians of {runs} fresh processes")
    base = None
    increments = {}
    for name, code in IMPORTS.items():
        wall = _wall([sys.executable, "-c", code], env, runs)
        base = wall if base is None else base
        increments[name] = wall - base
        print(f"import {name:<38} {wall:6.3f} s  (+{wall - base:5.3f} s)")
    with tempfile.TemporaryDirectory() as folder:
        env["EXPRESS_CACHE_DIR"] = folder
        frf = [sys.executable, "-m", "express", "frf", str(ROOT / "examples" / "conventional.toml")]
        subprocess.run(frf, check=True, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)  # fills the cache
        warm = _wall(frf, env, runs)
    print(f"warm express frf (conventional car)      {warm:6.3f} s  (target 0.5 s)")
    for name, extra in increments.items():
        if extra > 0:
            print(f"ratio {name:<38} {extra / warm:5.2f} of the warm frf; with it {warm + extra:5.3f} s")
    print(f"csgraph_s={increments['scipy.sparse.csgraph (RCM)']:.3f} warm_frf_s={warm:.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
