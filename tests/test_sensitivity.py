"""Exact sensitivities (express.analysis.study.sensitivity, ``express sensitivity``)
against central finite differences of the exact crossing and of the eigenvalues."""

from __future__ import annotations

import contextlib
import io
import json
from pathlib import Path

import numpy as np
import pytest

from express.analysis.study.critical import CriticalOptions, fast_critical_speed
from express.analysis.study.sensitivity import (
    critical_speed_sensitivity,
    eigenvalue_derivatives,
    parameter_rates,
    sensitivity_parameters,
)
from express.cli import main
from express.statespace import load_vehicle

ROOT = Path(__file__).resolve().parents[1]
STEERED = ROOT / "examples" / "forced-steering.toml"
EXACT = CriticalOptions(tolerance=0.0)

#: Parameters entering the matrices directly (stiffness, damping, conicity, geometry),
#: through a derived expression (the masses and g: P0), and only through the creep
#: derivation (Kalker: rail-head radius, Young's modulus).
PARAMETERS = ["kx1", "cyaw", "Gamma", "a", "bL", "lLL", "mw", "mc", "g", "r0", "Rrail", "Emod"]


@pytest.fixture(scope="module")
def steered():
    return load_vehicle(STEERED)


@pytest.fixture(scope="module")
def exact(steered):
    return critical_speed_sensitivity(steered, PARAMETERS)


def _crossing(vehicle) -> float:
    return fast_critical_speed(vehicle, EXACT).crossing.speed


@pytest.mark.parametrize("name", PARAMETERS)
def test_critical_speed_derivative_against_finite_difference(steered, exact, name) -> None:
    record = next(s for s in exact.sensitivities if s.name == name)
    value = record.value
    step = 1e-4 * abs(value)
    difference = (_crossing(steered.with_values({name: value + step}))
                  - _crossing(steered.with_values({name: value - step}))) / (2 * step)
    assert difference != 0
    assert record.derivative == pytest.approx(difference, rel=0.01)
    assert record.elasticity == pytest.approx(value / exact.critical_speed * record.derivative)


def test_derived_parameters_follow_exactly(steered) -> None:
    rates = parameter_rates(steered, "mc")
    assert rates["P0"] == pytest.approx(steered.values["g"] / 8, rel=1e-12)  # P0 = (mc + 2 mt + 4 mw) g / 8
    # f1 through Kalker's table: f ~ P0^(2/3) for the same radii
    f1 = steered.values["f1"]
    assert rates["f1"] == pytest.approx(2 / 3 * f1 / steered.values["P0"] * rates["P0"], rel=1e-6)
    assert set(parameter_rates(steered, "kx1")) == {"kx1"}


def test_sensitivity_parameters_are_the_given_ones(steered) -> None:
    names = sensitivity_parameters(steered)
    assert "kx1" in names and "mc" in names
    assert "P0" not in names and "f1" not in names and "v" not in names


def test_eigenvalue_derivatives_against_finite_difference(steered) -> None:
    speed = 30.0
    names = ["kx1", "mc", "Gamma"]
    eigenvalues, derivatives = eigenvalue_derivatives(steered, speed, names)
    for name in names:
        value = steered.values[name]
        step = 1e-5 * value
        plus = np.linalg.eigvals(steered.with_values({name: value + step}).state_matrix(speed))
        minus = np.linalg.eigvals(steered.with_values({name: value - step}).state_matrix(speed))
        for k in (0, 4, 10):  # a few modes, least stable first
            lam = eigenvalues[k]
            difference = (plus[np.argmin(abs(plus - lam))] - minus[np.argmin(abs(minus - lam))]) / (2 * step)
            scale = max(abs(difference), 1e-3 * abs(lam) / value)
            assert abs(derivatives[name][k] - difference) <= 0.01 * scale


def test_cli_json_and_tornado(tmp_path: Path) -> None:
    buffer = io.StringIO()
    plot = tmp_path / "tornado.png"
    with contextlib.redirect_stdout(buffer):
        status = main(["sensitivity", str(STEERED), "--output", "critical-speed", "--json", "--plot", str(plot),
                       "--parameter", "kx1", "--parameter", "mc"])
    assert status == 0
    summary = json.loads(buffer.getvalue())
    assert set(summary["sensitivities"]) == {"kx1", "mc"}
    assert summary["critical_speed"] == pytest.approx(_crossing(load_vehicle(STEERED)), rel=1e-9)
    assert plot.read_bytes().startswith(b"\x89PNG")


def test_cli_eigenvalue_and_mistakes(tmp_path: Path, capsys) -> None:
    assert main(["sensitivity", str(STEERED), "--output", "eigenvalue", "--speed", "100", "--parameter", "kx1", "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["speed"] == pytest.approx(100 / 3.6) and len(summary["sensitivities"]["kx1"]) == 2
    assert main(["sensitivity", str(STEERED), "--parameter", "kx9"]) == 2
    assert "kx9" in capsys.readouterr().err
    assert main(["sensitivity", str(STEERED), "--vmax", "100"]) == 1  # stable up to 100 km/h: nothing to differentiate
    assert "stable" in capsys.readouterr().err
