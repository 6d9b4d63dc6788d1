"""Optimisation and Sobol indices as study kinds (express.analysis.study.optimise)."""

from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np
import pytest

from express.analysis.study import runner
from express.analysis.study.results import checkpoint_path, read_table
from express.analysis.study.run import run_study
from express.analysis.study.spec import read_study

ROOT = Path(__file__).resolve().parents[1]
MODEL = ROOT / "examples" / "forced-steering.toml"

OPTIMISE = f"""[study]
model = "{MODEL}"
kind = "optimise"
outputs = ["critical_speed", "least_damping_ratio"]
seed = 3
[study.parameters]
kx1 = {{ from = "0.5 MN/m", to = "8 MN/m", scale = "log" }}
cyaw = {{ from = "50 kN*s/m", to = "400 kN*s/m" }}
[study.objective]
maximise = "critical_speed"
[study.constraints]
least_damping_ratio = {{ min = 0.0003 }}
[study.optimiser]
population = 3
iterations = 2
[study.options]
speed = "300 km/h"
"""


def feasible_count(table) -> int:
    return int(np.sum(table["least_damping_ratio"] >= 0.0003))


def test_optimise_keeps_the_history_and_reports_the_best_feasible_point(tmp_path: Path) -> None:
    path = tmp_path / "opt.toml"
    path.write_text(OPTIMISE)
    spec = read_study(path)
    summary = run_study(spec, tmp_path / "history.csv", workers=2)
    table = read_table(tmp_path / "history.csv")
    count = summary.points
    assert count == summary.computed and 12 <= count <= 3 * 2 * 3  # population x parameters x (iterations + 1)
    assert 0 < feasible_count(table) < count
    speeds, damping = table["critical_speed"], table["least_damping_ratio"]
    feasible = damping >= 0.0003
    best = summary.extra["best"]
    assert best is not None and feasible[best["point"]]
    assert best["outputs"]["critical_speed"] == speeds[feasible].max()
    assert best["parameters"]["kx1"] == table["kx1_N_m"][best["point"]]
    assert table["kx1_N_m"].min() >= 5e5 and table["kx1_N_m"].max() <= 8e6
    # the history is the same on another run
    again = run_study(spec, tmp_path / "again.csv", workers=1)
    assert (tmp_path / "again.csv").read_bytes() == (tmp_path / "history.csv").read_bytes()
    assert again.extra["best"] == best


def test_optimise_resumes_by_replaying_the_checkpoint(tmp_path: Path, monkeypatch) -> None:
    path = tmp_path / "opt.toml"
    path.write_text(OPTIMISE)
    spec = read_study(path)
    run_study(spec, tmp_path / "reference.csv", workers=1)
    original = runner.Engine.run
    calls = {"batches": 0}

    def crash_in_the_second_generation(self, indices, vectors):
        calls["batches"] += 1
        if calls["batches"] == 2:
            raise KeyboardInterrupt
        yield from original(self, indices, vectors)

    monkeypatch.setattr(runner.Engine, "run", crash_in_the_second_generation)
    with pytest.raises(KeyboardInterrupt):
        run_study(spec, tmp_path / "out.csv", workers=1)
    done = checkpoint_path(tmp_path / "out.csv").read_text().count("\n") - 1
    monkeypatch.setattr(runner.Engine, "run", original)
    summary = run_study(spec, tmp_path / "out.csv", workers=1, resume=True)
    assert summary.computed == summary.points - done
    assert (tmp_path / "out.csv").read_bytes() == (tmp_path / "reference.csv").read_bytes()


def test_sobol_indices_of_a_parameter_that_does_nothing_are_zero(tmp_path: Path) -> None:
    path = tmp_path / "sobol.toml"
    path.write_text(f"""[study]
model = "{MODEL}"
kind = "sobol-indices"
samples = 16
outputs = ["least_damping_ratio"]
[study.parameters]
Gamma = {{ from = 0.05, to = 0.3 }}
hf = {{ from = "1 m", to = "1.4 m" }}
[study.options]
speed = "200 km/h"
""")
    output = tmp_path / "sobol.parquet"
    summary = run_study(read_study(path), output, workers=2)
    assert summary.points == 16 * (2 + 2)
    indices = summary.extra["indices"]["least_damping_ratio"]
    assert indices["parameters"] == ["Gamma", "hf"]
    assert indices["ST"][1] == 0.0 and abs(indices["S1"][1]) < 1e-12  # hf (floor height) is not in A
    assert indices["ST"][0] > 0.5  # Gamma does everything (the S1 estimate of 16 base samples is rough)
    with open(tmp_path / "sobol.parquet.indices.csv") as stream:
        rows = list(csv.DictReader(stream))
    assert [(r["output"], r["parameter"]) for r in rows] == [("least_damping_ratio", "Gamma"), ("least_damping_ratio", "hf")]
    assert math.isclose(float(rows[0]["ST"]), indices["ST"][0])
    assert np.isfinite(read_table(output)["least_damping_ratio"]).all()


def test_bundled_optimisation_under_a_QP_limit_in_the_paper_curve(tmp_path: Path) -> None:
    """examples/studies/optimise_critical_speed.toml, a short run: maximise the critical
    speed subject to max Q/P <= 0.5 in the paper's R = 400 m curve. The constraint binds
    (points beyond it are evaluated and set aside) and the best point is the fastest of
    the feasible ones; its outputs are those of the analyses at its values."""
    from express.analysis.study.critical import fast_critical_speed
    from express.analysis.study.outputs import OutputSettings, PointOutputs
    from express.numeric.statespace import load_vehicle

    bundled = ROOT / "examples" / "studies" / "optimise_critical_speed.toml"
    text = bundled.read_text().replace('"../forced-steering.toml"', f'"{MODEL}"')
    text = text.replace("population = 8", "population = 3").replace("iterations = 20", "iterations = 3")
    path = tmp_path / "optimise.toml"
    path.write_text(text)
    summary = run_study(read_study(path), tmp_path / "history.csv", workers=2)
    table = read_table(tmp_path / "history.csv")
    quotient, speeds = table["max_YQ"], table["critical_speed"]
    feasible = quotient <= 0.5
    assert feasible.any() and not feasible.all()  # the limit binds
    best = summary.extra["best"]
    assert feasible[best["point"]] and best["outputs"]["critical_speed"] == speeds[feasible].max()
    assert speeds[~feasible].max() > best["outputs"]["critical_speed"]  # faster designs broke the limit
    values = {"kx1": best["parameters"]["kx1"], "lLL": best["parameters"]["lLL"]}
    vehicle = load_vehicle(MODEL, values)
    again, _ = PointOutputs(["critical_speed", "max_YQ"], OutputSettings())(vehicle)
    assert again == best["outputs"]
    assert again["critical_speed"] == fast_critical_speed(vehicle).speed
