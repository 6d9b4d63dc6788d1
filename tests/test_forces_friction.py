"""Friction elements (express.forces.friction, issue 31 item 1): reading and its errors,
the stuck linearisation in K, the spring–slider's hysteresis loop against its closed form,
free decay with Coulomb friction, Den Hartog's exact steady forced response, the step's
convergence, and a vehicle run through the command line with friction in the model.

The march is driven directly on a one-mass model (a spring to a ground that moves, the
input ``G.x``, and the friction element to a fixed ground): base motion ``U cos(w t)``
through the spring is the force ``k U cos(w t)`` on the mass, Den Hartog's problem."""

from __future__ import annotations

import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from express.analysis.time.integrator import march
from express.analysis.time.simulate import _dense_steps
from express.analysis.time.track_inputs import TrackInputs
from express.base.diagnostics import ModelError
from express.forces.element import ForceSet
from express.forces.friction import friction_elements_of, return_mapping
from express.io import parse_toml_model
from express.numeric.statespace import vehicle_model

ROOT = Path(__file__).resolve().parents[1]

MODEL = """
[model]
name = "slider"
[parameters]
m = "100 kg"
k = "40 kN/m"
ks = "{ks}"
F = "200 N"
[bodies.M]
mass = "m"
dofs = ["x"]
[grounds.G]
[grounds.W]
[points.M1]
body = "M"
offset = [0, 0, 0]
[points.G1]
body = "G"
offset = [0, 0, 0]
[points.W1]
body = "W"
offset = [0, 0, 0]
[elements.spring]
from = "M1"
to = "G1"
direction = "x"
stiffness = "k"
[elements.slider]
from = "M1"
to = "W1"
direction = "x"
stiffness = "ks"
friction = "F"
"""
M, K, F = 100.0, 40e3, 200.0
OMEGA_N = math.sqrt(K / M)


def _vehicle(ks: str = "40 MN/m"):
    return vehicle_model(parse_toml_model(MODEL.format(ks=ks), "slider.toml"))


def _run(vehicle, u: np.ndarray, dt: float, x0=None) -> tuple[np.ndarray, object]:
    steps = u.shape[0]
    empty = np.zeros((steps, 0))
    inputs = TrackInputs(u, np.gradient(u, dt, axis=0), empty, empty, empty)
    element = friction_elements_of(vehicle, u)
    forces = ForceSet((element,), vehicle.form.size)
    a = vehicle.state_matrix(1.0)
    linear = _dense_steps(vehicle, a, 1.0, dt, inputs, forces.selector())
    states, _ = march(linear, np.zeros(2) if x0 is None else np.asarray(x0, float), forces)
    return states, element


# ------------------------------------------------------------------ reading


def test_a_friction_element_is_read_and_is_stuck_in_the_linear_matrices():
    vehicle = _vehicle()
    (term,) = vehicle.equations.element_terms
    assert term.kind == "friction" and term.element == "slider"
    assert str(term.values["friction"]) == "F" and str(term.values["stiffness"]) == "ks"
    assert vehicle.stiffness[0, 0] == 40e3 + 40e6  # the spring and the stuck pre-slip spring


@pytest.mark.parametrize("old, new, message", [
    ('stiffness = "ks"\nfriction = "F"', 'friction = "F"', "a friction element needs its pre-slip stiffness"),
    ('friction = "F"', 'friction = "F"\ngap = "1 mm"', "a friction element cannot be a series or clearance element"),
    ('F = "200 N"', 'F = "-200 N"', "a friction element needs a positive friction limit"),
    ('F = "200 N"', 'F = "200 m"', "used as a force (TSD slider friction limit)"),
])
def test_bad_friction_elements_are_refused_with_the_line(old, new, message):
    text = MODEL.format(ks="40 MN/m")
    assert old in text
    with pytest.raises(ModelError) as error:
        parse_toml_model(text.replace(old, new), "slider.toml")
    problems = [str(p) for p in error.value.problems]
    assert any(p.startswith("slider.toml:") and message in p for p in problems), problems


# ------------------------------------------------------------------ the law


def test_the_hysteresis_loop_has_the_area_of_the_closed_form():
    """A deflection cycle of amplitude X through the spring–slider: the loop is the
    elastoplastic parallelogram, energy per cycle 4 L (X - L/k); the trapezoidal sum
    over 200 000 points per cycle within 1e-9 (achieved 2.3e-10), for three amplitudes."""
    stiffness, limit = 4e7, 200.0
    for amplitude in (2 * limit / stiffness, 1e-4, 3e-3):
        delta = amplitude * np.sin(np.linspace(0, 4 * math.pi, 400_001))
        slider, forces = 0.0, []
        for d in delta:
            slider = return_mapping(d, slider, stiffness, limit)
            forces.append(stiffness * (d - slider))
        second = len(delta) // 2  # the second cycle: the loop settled
        f, d = np.array(forces[second:]), delta[second:]
        area = float(np.sum(0.5 * (f[1:] + f[:-1]) * np.diff(d)))
        expected = 4 * limit * (amplitude - limit / stiffness)
        assert abs(area - expected) <= 1e-9 * expected
        assert max(abs(x) for x in forces) <= limit * (1 + 1e-12)


def test_nothing_slips_below_the_limit_and_the_run_is_the_linear_one():
    """A base motion whose force never reaches the limit: the slider never moves, the
    feedback is exactly zero and the states are the linear run's, bit for bit."""
    vehicle = _vehicle()
    dt = 1e-4
    t = np.arange(0, 0.5, dt)
    u = np.zeros((t.size, 2))
    u[:, 0] = 1e-5 * np.sin(2 * math.pi * 3 * t)  # 0.4 N through the spring
    states, element = _run(vehicle, u, dt)
    sliders, _ = element.history_of(states)
    assert not np.any(sliders)
    empty = np.zeros((t.size, 0))
    inputs = TrackInputs(u, np.gradient(u, dt, axis=0), empty, empty, empty)
    a = vehicle.state_matrix(1.0)
    alone = ForceSet((), vehicle.form.size)
    linear, _ = march(_dense_steps(vehicle, a, 1.0, dt, inputs, alone.selector()), np.zeros(2), alone)
    np.testing.assert_array_equal(states, linear)


def test_free_decay_falls_4F_over_k_per_cycle_and_stops_inside_F_over_k():
    """From x0 = 20 F/k at rest: each cycle the amplitude falls by 4 F/k (Coulomb's free
    decay), to 5e-4 of 4 F/k (achieved 1.5e-4 with the pre-slip spring at 1000 k and
    dt = T/16000; at T/4000 it is 4.5e-3: the slip phase feeds the pre-slip stiffness back
    explicitly, so the step must resolve sqrt(ks/m), here 0.2 of it per step), and the
    mass stops within F/k (+ F/ks) of the centre."""
    vehicle = _vehicle()
    period = 2 * math.pi / OMEGA_N
    dt = period / 16000
    t = np.arange(0, 8 * period, dt)
    x0 = 20 * F / K
    states, element = _run(vehicle, np.zeros((t.size, 2)), dt, x0=[x0, 0.0])
    x = states[:, 0]
    peaks = [x[(t > (c - 0.25) * period) & (t < (c + 0.25) * period)].max() for c in range(1, 5)]
    drops = -np.diff([x0, *peaks])
    np.testing.assert_allclose(drops, 4 * F / K, rtol=5e-4)
    late = t > 6 * period
    sliders, _ = element.history_of(states)
    assert np.ptp(sliders[late]) < 1e-12  # stuck for good (to rounding): the pre-slip spring vibrates alone
    assert np.max(np.abs(x[late])) <= F / K + F / 40e6


# ------------------------------------------------------------------ Den Hartog


def _den_hartog(r: float, force_ratio: float) -> float:
    """Den Hartog's (1930) exact amplitude of non-stop motion, over P0/k:
    sqrt(V^2 - (F/P0)^2 U^2), V = 1/(1 - r^2), U = sin(pi/r) / (r (1 + cos(pi/r)))."""
    v = 1 / (1 - r * r)
    u = math.sin(math.pi / r) / (r * (1 + math.cos(math.pi / r)))
    return math.sqrt(v * v - force_ratio**2 * u * u)


def test_den_hartogs_formula_is_the_periodic_solution_by_hand():
    """The formula above against the non-stop periodic solution written out (free and
    forced parts over a half period, four conditions) and solved here: to 1e-12."""
    from scipy.optimize import brentq

    for r, f in ((0.8, 0.25), (1.5, 0.25), (2.5, 0.25)):
        v, half = 1 / (1 - r * r), math.pi / r

        def residual(phi, r=r, f=f, v=v, half=half):
            matrix = np.array([[1, 0, -1], [0, 1, 0], [math.cos(half), math.sin(half), 1]])
            rhs = np.array([-f - v * math.cos(phi), v * r * math.sin(phi), -f - v * math.cos(r * half + phi)])
            a, b, amplitude = np.linalg.solve(matrix, rhs)
            return -a * math.sin(half) + b * math.cos(half) - v * r * math.sin(r * half + phi), amplitude

        grid = np.linspace(-math.pi, math.pi, 721)
        values = [residual(p)[0] for p in grid]
        roots = [brentq(lambda p: residual(p)[0], grid[i], grid[i + 1])
                 for i in range(720) if values[i] * values[i + 1] < 0]
        assert roots
        for root in roots:
            assert abs(abs(residual(root)[1]) - _den_hartog(r, f)) < 1e-12


def _steady_amplitude(ks: str, r: float, per_period: int, periods: int = 40) -> float:
    """The steady amplitude [m] forced at r = w/w_n with F/P0 = 0.25 (U = 20 mm)."""
    vehicle = _vehicle(ks)
    omega = r * OMEGA_N
    period = 2 * math.pi / omega
    dt = period / per_period
    t = np.arange(0, periods * period, dt)
    u = np.zeros((t.size, 2))
    u[:, 0] = 0.02 * np.cos(omega * t)
    x = _run(vehicle, u, dt)[0][:, 0]
    last = x[t > (periods - 8) * period]
    return 0.5 * float(last.max() - last.min())


@pytest.mark.slow
@pytest.mark.parametrize("r", [0.8, 1.5, 2.5])
def test_the_steady_forced_response_is_den_hartogs(r):
    """Forced at r with F/P0 = 0.25, after 32 periods: the amplitude within 1 % of Den
    Hartog's rigid–plastic Coulomb result (achieved -0.23, +0.33, +0.74 % at r = 0.8, 1.5,
    2.5) with the pre-slip spring at 1e4 k and T/16000 steps, converged in the step
    (T/32000 within 0.1 %; achieved 0.09 %)."""
    exact = 0.02 * _den_hartog(r, F / (K * 0.02))
    fine, finer = _steady_amplitude("400 MN/m", r, 16000), _steady_amplitude("400 MN/m", r, 32000)
    assert abs(fine / exact - 1) < 0.01
    assert abs(finer / fine - 1) < 0.001


@pytest.mark.slow
def test_the_rest_is_the_finite_pre_slip_stiffness():
    """What is left against Den Hartog is the pre-slip spring's own stick near each
    reversal, which shrinks as sqrt(k/ks): at r = 1.5 the error is 1.02 % at ks = 1e3 k and
    0.33 % at 1e4 k (ratio 3.1; sqrt(10) = 3.16), both converged in the step."""
    exact = 0.02 * _den_hartog(1.5, F / (K * 0.02))
    soft = _steady_amplitude("40 MN/m", 1.5, 16000) / exact - 1
    stiff = _steady_amplitude("400 MN/m", 1.5, 16000) / exact - 1
    assert 0.008 < soft < 0.012 and 2.7 < soft / stiff < 3.6


# ------------------------------------------------------------------ a vehicle


FRICTION_YAW = """
[elements.T1_yaw_friction]
from = "{a}"
to = "{b}"
direction = "rz"
stiffness = "kbowl"
friction = "Tbowl"
label = "centre-bowl friction torque"
"""


def _friction_car(tmp_path: Path) -> Path:
    """The conventional car with a centre-bowl friction torque between car body and bogie 1."""
    text = (ROOT / "examples" / "conventional.toml").read_text()
    model = parse_toml_model(text, "conventional.toml")
    body_point = next(p.id for p in model.points if p.host == "CB")
    bogie_point = next(p.id for p in model.points if p.host == "T1")
    path = tmp_path / "friction.toml"
    parameters = '[parameters]\nkbowl = "2 MN*m/rad"\nTbowl = "5 kN*m"\n'
    path.write_text(text.replace("[parameters]\n", parameters, 1) + FRICTION_YAW.format(a=body_point, b=bogie_point))
    return path


@pytest.mark.parametrize("command", ["eigen", "critical-speed"])
def test_the_linear_analyses_say_they_see_the_friction_stuck(tmp_path, command):
    """Issue 31 item 6: every linear output says how it saw the nonlinear elements — here
    the friction element stuck, its pre-slip spring in K — on standard error and in the
    JSON (``linearisation``), and the model without friction says nothing."""
    import json

    path = _friction_car(tmp_path)
    for model, expected in ((path, {"T1_yaw_friction"}), (ROOT / "examples" / "conventional.toml", set())):
        run = subprocess.run([sys.executable, "-m", "express", command, str(model), "--json"], capture_output=True,
                             text=True, timeout=600)
        assert run.returncode == 0, run.stderr
        assert set(json.loads(run.stdout)["linearisation"]) == expected
        assert ("seen stuck by this linear analysis" in run.stderr) == bool(expected)


def test_a_vehicle_with_friction_runs_on_the_command_line(tmp_path):
    """The conventional car with a friction torque between car body and bogie 1 (a
    centre bowl): `express simulate` writes its torque and slip with units, the torque
    never beyond the limit; at the default 5 ms step it warns that the pre-slip spring is
    not resolved, at a step that resolves it it does not."""
    path = _friction_car(tmp_path)
    out = tmp_path / "run.csv"
    run = subprocess.run([sys.executable, "-m", "express", "simulate", str(path), "--track", "R400", "-o", str(out)],
                         capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stderr
    header = out.read_text().splitlines()[0].split(",")
    assert "friction_T1_yaw_friction_Nm" in header and "slip_T1_yaw_friction_rad" in header
    column = header.index("friction_T1_yaw_friction_Nm")
    torque = np.array([float(line.split(",")[column]) for line in out.read_text().splitlines()[1:]])
    assert np.max(np.abs(torque)) <= 5e3 * (1 + 1e-9) and np.max(np.abs(torque)) > 0
    assert "does not resolve the friction elements' pre-slip springs" in run.stderr
    fine = subprocess.run([sys.executable, "-m", "express", "simulate", str(path), "--track", "R400", "--dt", "0.2 ms",
                           "-o", str(tmp_path / "fine.csv")], capture_output=True, text=True, timeout=600)
    assert fine.returncode == 0, fine.stderr
    assert "does not resolve" not in fine.stderr
