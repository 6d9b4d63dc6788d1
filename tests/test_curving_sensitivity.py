"""Sensitivities of steady curving (issue 35 item 3, :mod:`express.analysis.study.curving_sensitivity`):
the implicit-function-theorem derivatives of the leading wheelset's angle of attack, the
largest Y/Q and the largest |SY| against central differences of the whole steady-curving
solve, on a dead-band model in flange contact and on a profile-contact model, and the
``express sensitivity --output steady-curving`` command."""

from __future__ import annotations

import contextlib
import io
import json
from pathlib import Path

import numpy as np
import pytest

from express.analysis.curving.measure import wheel_rail_outputs
from express.analysis.curving.steady import SteadyCurve, SteadyCurvingSolver, steady_curving
from express.analysis.study.curving_sensitivity import OUTPUTS, linear_derivatives, steady_curving_sensitivity
from express.base.diagnostics import ArgumentError
from express.cli import main
from express.numeric.statespace import load_vehicle

ROOT = Path(__file__).resolve().parents[1]
DEADBAND = ROOT / "examples" / "manchester.toml"
PROFILES = ROOT / "examples" / "manchester-s1002.toml"
CURVE = SteadyCurve(600.0, 0.1)
SPEED = 25.0  # m/s: 0.39 m/s^2 of cant deficiency in R 600 m with 100 mm cant


@pytest.fixture(scope="module")
def deadband():
    return load_vehicle(DEADBAND)


@pytest.fixture(scope="module")
def profiles():
    return load_vehicle(PROFILES)


def _solved_outputs(vehicle, start, wheel: int, wheelset: int, sign: float, polish: bool) -> np.ndarray:
    """The three outputs (at the wheel and wheelset of the maxima at the point) of the
    steady state of ``vehicle`` solved by :class:`SteadyCurvingSolver` from ``start``;
    with ``polish``, carried on by Newton steps of the same equations to rounding level
    (the solver stops at a relative residual of 1e-11, which would limit a difference)."""
    solver = SteadyCurvingSolver(vehicle, SPEED)
    steady = solver.solve(CURVE, start)
    x = steady.state
    inputs = solver.inputs(CURVE)
    if polish:
        forces = solver.force_set(inputs)
        forcing = solver.b @ inputs.u[0]
        for _ in range(4):
            residual = solver.a @ x + forcing + solver.selector @ forces.forces(x, 0)
            x = x - np.linalg.solve(solver.a + solver.selector @ forces.slopes(x, 0), residual)
        residual = solver.a @ x + forcing + solver.selector @ forces.forces(x, 0)
        assert np.linalg.norm(residual) < 1e-13 * np.linalg.norm(forcing)
    q_dot = vehicle.form.velocities(x[None, :], inputs.u, inputs.u_rate)
    w = wheel_rail_outputs(vehicle, x[None, : vehicle.n], q_dot, inputs, SPEED, contact=solver.tables)
    return np.array([w.angle_of_attack[0, 0], np.ravel(w.y_over_q[0])[wheel], sign * w.track_shift_force[0, wheelset]])


def _differences(vehicle, result, names, step: float, polish: bool) -> np.ndarray:
    wheel = int(np.argmax(np.ravel(result.steady.wheel_rail.y_over_q[0])))
    shift = result.steady.wheel_rail.track_shift_force[0]
    wheelset = int(np.argmax(np.abs(shift)))
    sign = float(np.sign(shift[wheelset]))
    rows = []
    for name in names:
        value = float(vehicle.values[name])
        h = step * abs(value) or step
        up, down = (_solved_outputs(vehicle.with_values({name: value + d}), result.steady.state, wheel, wheelset,
                                    sign, polish) for d in (h, -h))
        rows.append((up - down) / (2 * h))
    return np.array(rows)


def _compare(vehicle, result, names, reference) -> tuple[float, float]:
    """The largest relative difference of the derivatives with an elasticity above 0.01,
    and the largest difference of the elasticities (``p / y dy/dp``) of all."""
    outputs = np.array([result.values[o] for o in OUTPUTS])
    rows = [result.parameters.index(n) for n in names]
    exact = result.derivatives[rows]
    values = result.parameter_values[rows]
    elasticity = np.abs(values[:, None] * exact / outputs)
    relative = np.where(elasticity > 1e-2, np.abs(reference - exact) / np.maximum(np.abs(exact), 1e-300), 0.0)
    elasticity_error = np.abs(values[:, None] * (reference - exact) / outputs)
    return float(relative.max()), float(elasticity_error.max())


def test_values_are_the_study_outputs(deadband) -> None:
    """The outputs differentiated are the study's ``steady_aoa``, ``steady_YQ`` and
    ``steady_SY`` of the same steady state, exactly (the same computation)."""
    result = steady_curving_sensitivity(deadband, CURVE, speed=SPEED, parameters=["kx1"])
    steady = steady_curving(deadband, CURVE, speeds=SPEED)[0].wheel_rail
    assert result.values == {"steady_aoa": float(steady.angle_of_attack[0, 0]),
                             "steady_YQ": float(np.max(steady.y_over_q)),
                             "steady_SY": float(np.max(np.abs(steady.track_shift_force)))}


def test_symbolic_part_against_differences_of_the_compiled_matrices(deadband) -> None:
    """``-(dK/dp) q + (dP/dp) u`` from the compiled symbolic derivatives (chained through
    the parameter graph) against central differences (relative step 1e-5) of the vehicle's
    own K and P(v) re-evaluated by ``with_values``: to 1e-8 of the terms' size (achieved
    7e-10; the differences' truncation and the creep derivation's own difference)."""
    from express.analysis.study.derivatives import graph_rates

    result = steady_curving_sensitivity(deadband, CURVE, speed=SPEED, parameters=["kx1"])
    q = result.steady.q
    u = SteadyCurvingSolver(deadband, SPEED).inputs(CURVE).u[0]
    names = ["kx1", "ky1", "mc", "Gamma", "r0", "a", "b", "g", "G", "mu"]
    values = dict(deadband.values)
    values["v"] = SPEED
    linear = linear_derivatives(deadband.equations)
    per_symbol = linear.force_rates(values, q, u)
    rates = graph_rates(deadband.model, deadband.equations).rates(deadband.values, names)
    for k, name in enumerate(names):
        exact = sum(per_symbol[i] * rates[s][k] for i, s in enumerate(linear.parameters) if s in rates)
        value = float(deadband.values[name])
        h = 1e-5 * abs(value)
        ends = [deadband.with_values({name: value + d}) for d in (h, -h)]
        terms = [-e.stiffness @ q + e.forcing(SPEED) @ u for e in ends]
        difference = (terms[0] - terms[1]) / (2 * h)
        size = np.abs(deadband.stiffness @ q).max() / abs(value)
        assert np.abs(exact - difference).max() < 1e-8 * size, name


def test_deadband_in_flange_contact_against_the_whole_solve(deadband) -> None:
    """The Manchester car (dead-band contact), R 600 m, 100 mm cant, 90 km/h, two wheels
    in flange contact: every parameter's derivatives against central differences of the
    steady state solved again at p (1 +- 1e-4) and Newton-polished to rounding level:
    within 1e-6 relative where the elasticity is above 0.01 and 1e-7 in every elasticity
    (achieved 2.8e-8 and 1.0e-8).  Against the solver's own stopping point (relative
    residual up to 1e-11) the differences at p (1 +- 1e-3) of six parameters agree to 1e-4
    (achieved 2.3e-5; at p (1 +- 1e-5) that noise reaches 1e-2 for some parameters: it is
    the solver's, not the derivatives')."""
    result = steady_curving_sensitivity(deadband, CURVE, speed=SPEED)
    assert any("flange contact at wheelset 1 left" in note for note in result.notes)
    assert {"delta", "kR", "mu", "Gamma"} <= set(result.differenced) and "kx1" not in result.differenced
    names = list(result.parameters)
    relative, elasticity = _compare(deadband, result, names, _differences(deadband, result, names, 1e-4, True))
    assert relative < 1e-6 and elasticity < 1e-7
    few = ["delta", "mu", "r0", "a", "kx1", "mc"]
    relative, _ = _compare(deadband, result, few, _differences(deadband, result, few, 1e-3, False))
    assert relative < 1e-4


def test_profile_contact_against_the_whole_solve(profiles) -> None:
    """The Manchester car on S1002/UIC60 contact tables, the same curve: the derivatives
    of the parameters that move the tables, the loads and the suspension against central
    differences (p (1 +- 1e-4)) of the Newton-polished whole solve: within 5e-5 relative
    where the elasticity is above 0.01 and 1e-5 in every elasticity (achieved 9.3e-6 and
    1.4e-6: the reference's own limit, which is 2.5e-4 with steps of 1e-3 and 6e-4 with
    1e-5, the tables being piecewise interpolations re-derived from the profiles)."""
    names = ["a", "b1", "kx1", "kx2", "mc", "mu", "G", "r0"]
    result = steady_curving_sensitivity(profiles, CURVE, speed=SPEED, parameters=names)
    assert result.steady.contact.startswith("tables")
    assert {"mu", "r0", "mc", "G"} <= set(result.differenced)
    relative, elasticity = _compare(profiles, result, names, _differences(profiles, result, names, 1e-4, True))
    assert relative < 5e-5 and elasticity < 1e-5


def test_bad_arguments(deadband) -> None:
    with pytest.raises(ArgumentError, match=r"kx9: not a given parameter.*did you mean"):
        steady_curving_sensitivity(deadband, CURVE, speed=SPEED, parameters=["kx9"])
    with pytest.raises(ArgumentError, match="curve must be a SteadyCurve"):
        steady_curving_sensitivity(deadband, 600.0, speed=SPEED)  # type: ignore[arg-type]


def _cli(arguments: list[str]) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        status = main(arguments)
    return status, out.getvalue(), err.getvalue()


def test_cli_steady_curving(deadband) -> None:
    """``--output steady-curving --radius 600 --cant 100 --speed 90 --json``: the library's
    numbers (bare cant in mm and speed in km/h, as ``express curving``); the table prints."""
    status, out, _ = _cli(["sensitivity", str(DEADBAND), "--output", "steady-curving", "--radius", "600", "--cant", "100",
                           "--speed", "90", "--parameter", "kx1", "--parameter", "delta", "--json"])
    assert status == 0
    summary = json.loads(out)
    result = steady_curving_sensitivity(deadband, CURVE, speed=SPEED, parameters=["kx1", "delta"])
    assert summary["output"] == "steady_curving" and summary["radius"] == 600.0 and summary["cant"] == 0.1
    assert summary["speed"] == pytest.approx(SPEED, rel=1e-15) and summary["values"] == result.values
    for name in ("kx1", "delta"):
        for output in OUTPUTS:
            assert summary["sensitivities"][name][output] == pytest.approx(result.derivative(output, name), rel=1e-12)
    assert summary["differenced"] == ["delta"] and summary["units"]["steady_SY"] == "N"
    status, out, err = _cli(["sensitivity", str(DEADBAND), "--output", "steady-curving", "--radius", "600 m",
                             "--cant", "0.1 m", "--speed", "25 m/s", "--parameter", "kx1"])
    assert status == 0 and "steady curving in R = 600 m, cant 100 mm, 90.0 km/h" in out and "kx1" in out
    assert "flange contact" in err


def test_cli_steady_curving_mistakes(tmp_path: Path) -> None:
    """Bad input is exit status 2 with a message naming the option, nothing computed."""
    cases = [
        (["--output", "steady-curving"], "give the curve's --radius"),
        (["--radius", "600"], "--radius: the curve of --output steady-curving"),
        (["--output", "critical-speed", "--cant", "100"], "--cant: the curve of --output steady-curving"),
        (["--output", "steady-curving", "--radius", "600", "--linearisation", "equivalent"], "steady curving runs"),
        (["--output", "steady-curving", "--radius", "-5"], "--radius"),
        (["--output", "steady-curving", "--radius", "600", "--speed", "300"], "unbalanced acceleration"),
    ]
    for arguments, message in cases:
        status, _, err = _cli(["sensitivity", str(DEADBAND), *arguments])
        assert status == 2 and message in err, (arguments, err)
