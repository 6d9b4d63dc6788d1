"""The force-element layer's cost in the time march (issue 31, items 1 and 7).

Times ``express.simulate`` of the conventional car along the paper's curve (460 m at
120 km/h, dt 5 ms: the dead-band wheel/rail element alone) against the same car with
friction elements (a centre-bowl friction torque at each bogie: pre-slip spring and
slider), in the same run, medians of ``--repeat`` runs after a warm-up (the compiled
kernels loaded); prints each median, the ratio and the real-time factor (simulated
seconds per second of wall time).  With ``--base DIR`` it also times the dead-band run
with another checkout's ``src`` (e.g. the commit before the layer) in a subprocess.

    PYTHONPATH=src python3 benchmarks/bench_forces.py [--repeat 7] [--base /tmp/base]
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
import warnings
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
FRICTION = """
[elements.T{t}_centre_bowl]
from = "{a}"
to = "{b}"
direction = "rz"
stiffness = "kbowl"
friction = "Tbowl"
"""
TIMING = """
import json, statistics, sys, time, warnings
warnings.simplefilter("ignore")
import express
vehicle = express.load_vehicle(sys.argv[1])
track = express.paper_curve()
express.simulate(vehicle, track, progress=False)
times = []
for _ in range(int(sys.argv[2])):
    start = time.perf_counter()
    express.simulate(vehicle, track, progress=False)
    times.append(time.perf_counter() - start)
print(json.dumps(statistics.median(times)))
"""


def friction_car(folder: Path) -> Path:
    """The conventional car with a centre-bowl friction torque at each bogie."""
    from express.io import parse_toml_model

    text = (ROOT / "examples" / "conventional.toml").read_text()
    model = parse_toml_model(text, "conventional.toml")
    extra = ""
    for t in (1, 2):
        body = next(p.id for p in model.points if p.host == "CB")
        bogie = next(p.id for p in model.points if p.host == f"T{t}")
        extra += FRICTION.format(t=t, a=body, b=bogie)
    path = folder / "conventional-friction.toml"
    path.write_text(text.replace("[parameters]\n", '[parameters]\nkbowl = "2 MN*m/rad"\nTbowl = "5 kN*m"\n', 1) + extra)
    return path


def median_time(path: Path, repeat: int, source: Path) -> float:
    environment = {**os.environ, "PYTHONPATH": str(source)}
    run = subprocess.run([sys.executable, "-c", TIMING, str(path), str(repeat)], capture_output=True, text=True,
                         env=environment, check=True)
    return float(json.loads(run.stdout.splitlines()[-1]))


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=7)
    parser.add_argument("--base", type=Path, help="another checkout whose src/ is timed on the dead-band car")
    arguments = parser.parse_args()
    warnings.simplefilter("ignore")
    import express

    with tempfile.TemporaryDirectory() as folder:
        car = friction_car(Path(folder))
        plain = ROOT / "examples" / "conventional.toml"
        simulated = express.paper_curve().length / (120 / 3.6)
        results = {"dead-band only": median_time(plain, arguments.repeat, ROOT / "src"),
                   "with friction": median_time(car, arguments.repeat, ROOT / "src")}
        if arguments.base is not None:
            results["dead-band only, base"] = median_time(plain, arguments.repeat, arguments.base / "src")
    print(f"load average {os.getloadavg()[0]:.2f}; {arguments.repeat} runs each, medians; {simulated:.2f} s simulated")
    for name, seconds in results.items():
        print(f"  {name:<24} {seconds * 1e3:8.1f} ms   {simulated / seconds:7.0f}x real time")
    print(f"  ratio with friction / dead-band only: {results['with friction'] / results['dead-band only']:.2f}")
    if "dead-band only, base" in results:
        print(f"  ratio dead-band only / base: {results['dead-band only'] / results['dead-band only, base']:.2f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
