"""The force-element layer (express.forces, issue 31 item 7): every element's compiled law
against its NumPy forces, the stack's places, the linearisations against closed forms, and
a new kind of element written in one place (this file) that the march runs unchanged."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from express.analysis.time.force_elements import run_forces
from express.analysis.time.integrator import discretize
from express.analysis.time.simulate import simulate
from express.analysis.time.track_inputs import track_inputs
from express.forces.bump_stops import BumpStopElement
from express.forces.deadband import DeadbandElement
from express.forces.element import ForceSet
from express.forces.law import stacked_forces
from express.io import load_model
from express.numeric.statespace import vehicle_model
from express.rail.track import paper_curve
from test_elements_clearance import with_lateral_bump_stops

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def stopped():
    """The conventional car with secondary lateral bump stops (2 mm gap: they touch)."""
    return vehicle_model(with_lateral_bump_stops(load_model(ROOT / "examples" / "conventional.toml"), 0.002))


@pytest.fixture(scope="module")
def run(stopped):
    """Its force elements on the paper's curve at 60 km/h, and states to evaluate them at."""
    speed = 60 / 3.6
    distance = np.linspace(0.0, 300.0, 61)
    inputs = track_inputs(stopped, paper_curve(), distance, speed)
    forces = run_forces(stopped, inputs, speed, tables=None, flange=True, saturation=True, clearances=True).forces
    rng = np.random.default_rng(7)
    scale = np.r_[np.full(stopped.n, 0.01), np.full(stopped.form.size - stopped.n, 0.2)]
    states = rng.uniform(-1, 1, (len(distance), stopped.form.size)) * scale
    return forces, states


def _compiled(forces: ForceSet, x: np.ndarray, k: int) -> np.ndarray:
    z = np.zeros(forces.width)
    record = forces.history(0)[0]
    stacked_forces(np.ascontiguousarray(x), k, forces.laws(), z, record, False)
    return z


def test_the_stack_is_the_wheel_rail_forces_then_the_stops(run, stopped):
    forces, _ = run
    assert [type(e) for e in forces.elements] == [DeadbandElement, BumpStopElement]
    count = len(stopped.wheelsets)
    assert forces.width == 2 * count + 2
    assert forces.names[-2:] == ("stop_T1_stop", "stop_T2_stop")
    selector = forces.selector()
    assert selector.shape == (stopped.form.size, forces.width)
    np.testing.assert_array_equal(selector[:, 0], stopped.form.force[:, stopped.wheelsets[0].y])
    np.testing.assert_array_equal(selector[:, count], stopped.form.force[:, stopped.wheelsets[0].psi])


def test_the_compiled_laws_are_the_numpy_forces(run):
    """The march's compiled stack and the steady solver's NumPy forces, at 61 random states
    with the stops engaged: 1e-14 of the largest force (achieved 1.2e-15)."""
    forces, states = run
    worst = 0.0
    for k, x in enumerate(states):
        compiled, numpy_forces = _compiled(forces, x, k), forces.forces(x, k)
        scale = max(1.0, float(np.max(np.abs(numpy_forces))))
        worst = max(worst, float(np.max(np.abs(compiled - numpy_forces))) / scale)
    assert worst < 1e-14
    stops = forces.elements[1]
    assert np.any(stops.forces(states[10], 10) != 0.0)  # some stops are engaged


def test_a_bump_stops_slope_is_its_tangent_stiffness(run):
    """Beyond the gap dF/d(delta) = k + 3 k3 e^2, inside it zero: the forward difference
    within 2e-6 relative (achieved 8.1e-7: the step 1e-8 m on a cubic term)."""
    forces, states = run
    stops: BumpStopElement = forces.elements[1]  # type: ignore[assignment]
    d = stops.data
    for k, x in enumerate(states[:20]):
        delta = stops.deflections(x, k)
        e = np.where(delta > d.gap, delta - d.gap, np.where(delta < -d.gap, delta + d.gap, 0.0))
        tangent = np.where(e != 0.0, d.stiffness + 3 * d.progressive * e**2, 0.0)
        slopes = stops.slopes(x, k, stops.forces(x, k))
        np.testing.assert_allclose(slopes, -tangent[:, None] * stops.rows, rtol=2e-6, atol=1e-6)


def test_the_stop_outputs_are_the_forces_with_their_sign(run):
    forces, states = run
    history = forces.history(states.shape[0] - 1)
    outputs = forces.outputs(states, history)
    assert set(outputs) == {"stop_T1_stop", "stop_T2_stop"}
    assert forces.output_units() == {"stop_T1_stop": "N", "stop_T2_stop": "N"}
    for k in (0, 10, 30):
        np.testing.assert_allclose([outputs["stop_T1_stop"][k], outputs["stop_T2_stop"][k]],
                                   -forces.elements[1].forces(states[k], k), rtol=1e-14)  # the sums' order differs


# --------------------------------------------------- a new kind, written in one place


def test_a_new_kind_of_element_runs_in_the_march_as_its_linear_equivalent(tmp_path):
    """A spring written as a force element (tests/forces_toy.py alone) marches as the same
    spring put into A: the feedback's first-order hold with Heun's predictor is second
    order in the step, so at dt = 2 ms the two agree to 1e-7 of the largest displacement
    (achieved 3.2e-8), and the error falls fourfold when the step is halved (achieved 4.01).

    It runs in its own process with its own Numba cache: a law type from outside the
    package must not enter the package's kernel cache, whose index every later process
    reads (``docs/analyses.md``, "Nonlinear force elements")."""
    import json
    import os
    import subprocess
    import sys

    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "numba"),
           "PYTHONPATH": os.pathsep.join([str(Path(__file__).parent), os.environ.get("PYTHONPATH", "")])}
    run = subprocess.run([sys.executable, "-c", "import forces_toy, json; print(json.dumps(forces_toy.gaps()))"],
                         capture_output=True, text=True, env=env, timeout=900, check=False)
    assert run.returncode == 0, run.stderr
    coarse, fine = json.loads(run.stdout.splitlines()[-1])
    assert coarse < 1e-7
    assert 3.6 < coarse / fine < 4.4


def test_simulate_sees_only_the_stack(stopped):
    """A run's options and outputs come from its elements: the stops' forces are columns,
    ``clearances`` is said, and the discretisation helper is the one the march used."""
    result = simulate(stopped, paper_curve(), end=120.0, progress=False)
    assert result.options["clearances"] is True and "stop_T1_stop" in result.outputs
    phi, _, _ = discretize(stopped.state_matrix(result.speed), result.options["dt"])
    assert phi.shape == (stopped.form.size, stopped.form.size)


def test_a_series_damper_without_damping_leaves_its_stroke_out_of_the_stops_too():
    """Issue 35 item 8: the yaw dampers in series with their bushes at cyaw = 0 carry no
    force and the vehicle leaves their strokes out (24 -> 20 coordinates); the bump stops
    (written over the equations' 24) crashed simulate and steady curving.  Now both run, and
    give the car without those dampers at all: to 1e-12 of the largest displacement
    (achieved 3e-16 in the run, 0 in the steady state)."""
    import dataclasses as dc

    from express.analysis.curving.steady import SteadyCurve, SteadyCurvingSolver

    model = with_lateral_bump_stops(load_model(ROOT / "examples" / "conventional-yaw-bush.toml"), 0.002)
    zero = vehicle_model(model).with_values({"cyaw": 0.0})
    without = vehicle_model(dc.replace(model, elements=tuple(e for e in model.elements if not e.series)))
    assert zero.dofs == without.dofs
    a, b = (simulate(v, paper_curve(), end=150.0, progress=False) for v in (zero, without))
    scale = float(np.max(np.abs(b.q)))
    assert np.max(np.abs(a.q - b.q)) <= 1e-12 * scale
    assert np.max(np.abs(a.outputs["stop_T1_stop"] - b.outputs["stop_T1_stop"])) <= 1e-6 * max(
        1.0, float(np.max(np.abs(b.outputs["stop_T1_stop"]))))
    curve = SteadyCurve(400.0, 0.1)
    first, second = (SteadyCurvingSolver(v, 20.0).solve(curve) for v in (zero, without))
    np.testing.assert_allclose(first.q, second.q, rtol=0, atol=1e-12 * float(np.max(np.abs(second.q))))
