#!/usr/bin/env python3
"""Flexible car body benchmark (issue 34): the coach with 6 flexible modes against the
same coach with its car body rigid.

Run from the repository root::

    PYTHONPATH=src python3 benchmarks/bench_flexible.py            # ~1 min
    PYTHONPATH=src python3 benchmarks/bench_flexible.py --runs 1   # smoke test

The coach is ``examples/manchester-flexible.toml`` with 4 vertical bending and 2 torsion
modes (6 modes), and the same file without its ``[flexible]`` section (rigid).  Everything
runs on ONE core (BLAS/OpenMP thread counts set to 1 before NumPy is imported, unless set).
Medians of ``--runs`` runs after one warm-up, in one process, the rigid and the flexible
coach's runs alternating (so that a change of the shared machine's load hits both):

1. the symbolic generation (``generate_vehicle``): readable (factored, as ``express
   generate`` writes it) and expanded (``readable=False``, what every numerical command
   derives); target: flexible <= 1.5 x rigid;
2. the spectral ride (``ride_response`` of ERRI-high at 160 km/h, 2000 frequencies
   0.1-50 Hz, on a loaded vehicle); target: flexible <= 1.2 x rigid.

The last line is ``generate_ratio=<x> expanded_ratio=<y> ride_ratio=<z>``.
"""

from __future__ import annotations

import os

for _variable in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_variable, "1")

import argparse  # noqa: E402
import statistics  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "examples" / "manchester-flexible.toml"


def variants(folder: Path) -> dict[str, Path]:
    """The rigid and the 6-mode coach as files in ``folder``."""
    text = EXAMPLE.read_text(encoding="utf-8")
    start = text.index("# The car body's modes")
    end = text.index("# ------------------------------------------------------------------------------------\n# The bogie")
    files = {"rigid": text[:start] + text[end:], "flexible": text.replace("vertical = 2\ntorsion = 1",
                                                                          "vertical = 4\ntorsion = 2")}
    paths = {}
    for name, content in files.items():
        paths[name] = folder / f"{name}.toml"
        paths[name].write_text(content, encoding="utf-8")
    return paths


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=5)
    args = parser.parse_args(argv)
    os.environ["EXPRESS_NO_CACHE"] = "1"
    from express.analysis.ride.vehicle import ride_response, track_class_spectra
    from express.io.toml_model import read_toml_model
    from express.numeric.statespace import load_vehicle
    from express.rail.build import generate_vehicle

    spectra = track_class_spectra("ERRI-high")
    frequencies = np.logspace(-1, np.log10(50), 2000)
    with tempfile.TemporaryDirectory() as folder:
        paths = variants(Path(folder))
        models = {name: read_toml_model(path) for name, path in paths.items()}
        vehicles = {name: load_vehicle(path) for name, path in paths.items()}
        tasks = {
            "generate": lambda name: generate_vehicle(models[name]),
            "expanded": lambda name: generate_vehicle(models[name], readable=False),
            "ride": lambda name: ride_response(vehicles[name], spectra, 160 / 3.6, frequencies),
        }
        samples: dict[str, dict[str, list[float]]] = {name: {task: [] for task in tasks} for name in paths}
        for task, function in tasks.items():  # rigid and flexible alternate: a change of load hits both
            for name in paths:
                function(name)  # warm-up
            for _ in range(args.runs):
                for name in paths:
                    start = time.perf_counter()
                    function(name)
                    samples[name][task].append(time.perf_counter() - start)
    times = {name: {task: statistics.median(values) for task, values in by_task.items()} for name, by_task in samples.items()}
    for name in paths:
        print(f"{name:9s} {len(vehicles[name].dofs):3d} coordinates: generate {times[name]['generate']:.3f} s "
              f"(expanded {times[name]['expanded']:.3f} s), ride {times[name]['ride']:.3f} s")
    generate_ratio = times["flexible"]["generate"] / times["rigid"]["generate"]
    expanded_ratio = times["flexible"]["expanded"] / times["rigid"]["expanded"]
    ride_ratio = times["flexible"]["ride"] / times["rigid"]["ride"]
    print(f"targets: generate <= 1.5 x rigid ({'met' if generate_ratio <= 1.5 else 'MISSED'}; expanded "
          f"{'met' if expanded_ratio <= 1.5 else 'MISSED'}), "
          f"ride <= 1.2 x rigid ({'met' if ride_ratio <= 1.2 else 'MISSED'})")
    print(f"generate_ratio={generate_ratio:.3f} expanded_ratio={expanded_ratio:.3f} ride_ratio={ride_ratio:.3f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
