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
    chosen_parameters,
    critical_speed_sensitivity,
    eigenvalue_derivatives,
    parameter_rates,
    sensitivity_parameters,
)
from express.base.diagnostics import ArgumentError
from express.cli import main
from express.numeric.statespace import load_vehicle

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
    # achieved <= 4.7e-8 (Gamma; the others <= 5e-9): the central difference's own error, step 1e-4
    assert record.derivative == pytest.approx(difference, rel=1.5e-7)
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


# ------------------------------------------------------------------ compiled once per model


def test_matrix_derivatives_against_differences_of_the_compiled_matrices(steered) -> None:
    """dM/dq, dC/dq, dK/dq (compiled derivatives) against central differences of the
    compiled matrices themselves (express.numeric.compiled), at a speed."""
    from express.analysis.study.derivatives import matrix_derivatives
    from express.numeric.compiled import compile_matrices

    equations = steered.equations
    derivatives = matrix_derivatives(equations)
    compiled = compile_matrices(equations)
    values = dict(steered.values, v=40.0)
    exact = derivatives.matrices(values)
    for name in ("kx1", "cyaw", "Gamma", "a", "mc", "f1", "v"):
        step = 1e-6 * abs(values[name])
        plus = compiled(compiled.vector({**values, name: values[name] + step}))
        minus = compiled(compiled.vector({**values, name: values[name] - step}))
        for key in ("M", "C", "K"):
            difference = (plus[key] - minus[key]) / (2 * step)
            scale = max(np.abs(difference).max(), 1e-300)
            assert np.abs(exact[name][key] - difference).max() <= 1e-6 * scale, (name, key)
        assert any(np.abs(exact[name][key]).max() > 0 for key in ("M", "C", "K")), name
    assert "hf" not in derivatives.parameters  # the floor height is not in M, C, K


def test_no_symbolic_work_per_point(steered, monkeypatch) -> None:
    """Once compiled, a point's sensitivities and eigenvalue derivatives use no SymPy
    differentiation or code generation, and share the compiled derivatives."""
    import sympy

    from express.analysis.study.derivatives import graph_rates, matrix_derivatives

    critical_speed_sensitivity(steered, ["kx1"])  # compiles (or finds) the derivatives
    compiled = matrix_derivatives(steered.equations), graph_rates(steered.model, steered.equations)

    def refuse(*args, **kwargs):
        raise AssertionError("symbolic work per point")

    point = steered.with_values({"kx1": 3e6, "mc": 32e3})
    for name in ("diff", "lambdify", "cse"):
        monkeypatch.setattr(sympy, name, refuse)
    result = critical_speed_sensitivity(point, PARAMETERS)
    eigenvalue_derivatives(point, 30.0, ["kx1", "mc"])
    assert (matrix_derivatives(point.equations), graph_rates(point.model, point.equations)) == compiled
    assert result.critical_speed > 0 and result.critical_speed != pytest.approx(_crossing(steered), rel=1e-6)


def test_a_derived_parameter_given_a_value_leaves_the_graph(steered) -> None:
    """With P0 given (as --set P0=... does), the masses no longer move it, and P0 moves
    the creep coefficients through Kalker's table."""
    given = steered.with_values({"P0": steered.values["P0"] * 1.1})
    assert set(parameter_rates(given, "mc")) == {"mc"}
    rates = parameter_rates(given, "P0")
    assert set(rates) == {"P0", "f1", "f2"} and rates["f1"] == pytest.approx(2 / 3 * given.values["f1"] / given.values["P0"], rel=1e-6)
    assert set(parameter_rates(steered, "mc")) == {"mc", "P0", "f1", "f2"}  # the first graph is still right


@pytest.mark.slow
def test_through_the_profiles_derivation_against_finite_difference() -> None:
    """Manchester vehicle 1 on S1002/60E1: the conicity and the contact parameters come
    from the profiles derivation node (a function with text settings), r0 and nu reach
    the matrices through it and through Kalker's table."""
    options = CriticalOptions(v_max=150.0, tolerance=0.0)
    vehicle = load_vehicle(ROOT / "examples" / "manchester-s1002.toml")
    rates = parameter_rates(vehicle, "r0")
    assert rates["Gamma_e"] != 0 and rates["Gamma_e_f11"] != 0
    result = critical_speed_sensitivity(vehicle, ["r0", "nu", "kx1"], options)
    for record in result.sensitivities:
        step = 1e-4 * record.value
        plus = fast_critical_speed(vehicle.with_values({record.name: record.value + step}), options).crossing.speed
        minus = fast_critical_speed(vehicle.with_values({record.name: record.value - step}), options).crossing.speed
        # achieved <= 1.5e-8 (kx1; r0, nu <= 1e-9), the central difference's own error
        assert record.derivative == pytest.approx((plus - minus) / (2 * step), rel=5e-8)


def test_the_chosen_parameters_are_checked(steered):
    """Every given parameter for None, duplicates dropped in order, a bare string and
    unknown names refused (each named, with a suggestion)."""
    assert chosen_parameters(steered, None) == sensitivity_parameters(steered)
    assert chosen_parameters(steered, ["lLL", "kx1", "lLL"]) == ["lLL", "kx1"]
    with pytest.raises(ArgumentError, match="string 'kx1'"):
        chosen_parameters(steered, "kx1")
    with pytest.raises(ArgumentError, match=r"kx9: not a given parameter.*did you mean kx2") as caught:
        chosen_parameters(steered, ["kx9", "zz"])
    assert "zz: not a given parameter" in str(caught.value)
