"""Issue 12, item 6 end to end: for the bundled standard-gauge vehicle on S1002/60E1
(``examples/manchester-s1002.toml``) ``express critical-speed --nonlinear`` reports the
linear critical speed (at the profiles' equivalent conicity) and the nonlinear one
(ramp-down with the contact tables) side by side, the figures quoted in
``docs/contact.md`` ("Nonlinear critical speed")."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import pytest

from express.cli import main
from express.numeric.statespace import load_vehicle

MODEL = Path(__file__).resolve().parents[1] / "examples" / "manchester-s1002.toml"


@pytest.mark.slow
def test_linear_and_nonlinear_critical_speed_side_by_side(tmp_path, capsys):
    out, fig = tmp_path / "cycles.csv", tmp_path / "cycles.png"
    assert main(["critical-speed", str(MODEL), "--nonlinear", "--json", "-o", str(out), "--plot", str(fig)]) == 0
    data = json.loads(capsys.readouterr().out)
    nonlinear = data["nonlinear"]
    assert data["critical_speed_kmh"] == pytest.approx(285.4, abs=0.5)  # linear, tan gamma_e(3 mm) = 0.177
    assert nonlinear["contact"] == "tables (fastsim)"
    assert nonlinear["critical_speed_kmh"] == pytest.approx(174.4, abs=1.0)
    assert nonlinear["critical_speed_kmh"] < data["critical_speed_kmh"]  # subcritical hunting bifurcation
    low, high = nonlinear["bracket"]
    assert 0 < (high - low) * 3.6 <= 0.5 + 1e-9
    rows = list(csv.DictReader(out.read_text().splitlines()))
    alive = [float(r["amplitude_m"]) for r in rows if r["limit_cycle"] == "1"]
    assert max(alive) > 8e-3 and min(alive) < 2e-3  # flange-contact branch, then the tread cycle
    assert fig.stat().st_size > 10_000


def test_the_model_takes_its_conicity_from_the_profiles():
    from express.rail.conicity import conicity_from_profiles
    from express.rail.contact_geometry import ContactSetup
    from express.rail.profiles import standard_profile

    values = load_vehicle(MODEL).values
    tan_gamma, _ = conicity_from_profiles(standard_profile("S1002"), standard_profile("60E1"), 3e-3, ContactSetup())
    assert values["Gamma_e"] == pytest.approx(float(tan_gamma), abs=2e-3) and values["Gamma_e"] == pytest.approx(0.177, abs=1e-3)
