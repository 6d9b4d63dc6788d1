"""Simulation with the contact tables (express.analysis.contact_march through
express.analysis.simulate.simulate).

* Linear limit: with smooth profiles (a circular tread on the 60E1 crown), rigid rails
  and a tiny disturbance the contact run equals the linear model's run: the fed-back
  difference between the contact forces and the model's linear wheel/rail terms vanishes
  to second order.
* Reference: scipy's LSODA on the same equations (contact_rhs) agrees with the march.
* Outputs and options.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from express.analysis.contact_march import contact_rhs, linear_coefficients
from express.analysis.simulate import simulate
from express.io.toml_model import parse_toml_model
from express.numeric.statespace import vehicle_model
from express.rail.profile_contact import wheelset_contacts
from express.rail.track import Straight, Track
from test_contact_geometry import arc_wheel
from test_profile_contact import WHEELSET

TRACK = Track((Straight(5000.0),))


@pytest.fixture(scope="module")
def s1002():
    return vehicle_model(parse_toml_model(WHEELSET, "wheelset.toml"))


def smooth_model(tmp_path):
    wheel = arc_wheel(0.5, math.atan(0.01))
    (tmp_path / "arc.csv").write_text("y_mm,z_mm\n" + "".join(
        f"{a * 1e3:.9f},{b * 1e3:.9f}\n" for a, b in zip(wheel.y, wheel.z, strict=True)))
    text = (WHEELSET.replace('wheel = "S1002"', 'wheel = "arc.csv"').replace('inclination = "1:40"', 'inclination = 0')
            .replace('A = { value = 3, unit = "mm" }', 'A = { value = 0.05, unit = "mm" }')
            .replace('kR = { value = 20, unit = "MN/m" }', 'kR = { value = 1e12, unit = "N/m" }'))
    path = tmp_path / "smooth.toml"
    path.write_text(text)
    from express.io import load_model

    return vehicle_model(load_model(path))


def test_small_motion_runs_as_the_linear_model(tmp_path):
    vehicle = smooth_model(tmp_path)
    state = np.zeros(vehicle.form.size)
    state[0] = 2e-6  # 2 um
    speed = 40.0
    contact = simulate(vehicle, TRACK, speed=speed, dt=0.002, end=speed * 2, initial_state=state, progress=False)
    linear = simulate(vehicle, TRACK, speed=speed, dt=0.002, end=speed * 2, initial_state=state, progress=False,
                      flange=False, saturation=False)
    assert contact.options["contact"] == "tables (fastsim)" and "contact" not in linear.options
    scale = np.abs(linear.q).max(axis=0)
    assert np.abs(contact.q - linear.q).max(axis=0) == pytest.approx(0, abs=1e-3 * scale.max())
    assert np.abs(linear.q[:, 0]).max() > 1e-7  # it moved


@pytest.mark.slow
def test_march_agrees_with_a_reference_integration(s1002):
    speed = 60.0
    state = np.zeros(s1002.form.size)
    state[0] = 4e-3
    run = simulate(s1002, TRACK, speed=speed, dt=0.001, end=speed * 0.6, initial_state=state, progress=False,
                   clearances=False)
    contacts = wheelset_contacts(s1002.model, s1002.values, s1002.wheelsets)
    rhs = contact_rhs(s1002, TRACK, contacts, speed=speed)
    reference = solve_ivp(rhs, (0.0, run.time[-1]), state, method="LSODA", t_eval=run.time[::10], rtol=1e-8,
                          atol=1e-11, max_step=5e-4)
    assert reference.status == 0
    error = np.abs(run.q[::10, 0] - reference.y[0]).max()
    assert error < 0.03 * np.abs(reference.y[0]).max()


def test_outputs_and_options(s1002):
    state = np.zeros(s1002.form.size)
    state[0] = 9e-3  # on the flange, the rail pushed outward by 2.7 mm
    run = simulate(s1002, TRACK, speed=50.0, dt=0.005, end=50.0, initial_state=state, progress=False)
    for name in ("Q1", "QP1", "Qtot1", "flange1", "dy1", "NL1", "NR1"):
        assert run.outputs[name].shape == run.time.shape
    assert run.outputs["Q1"][0] < -30e3  # the left rail pushes the flange back
    # the rail gives way under Q tan(delta); the flange's normal-force component is that
    # less the friction's share (N = Q / (cos + kappa sin))
    assert 0.5 < -run.outputs["flange1"][0] / (20e6 * run.outputs["dy1"][0]) < 1.0
    assert run.outputs["NL1"][0] > 1.2 * 50e3  # the flange's normal force exceeds the wheel load
    assert run.units()["NL1"] == "N"
    polach = simulate(s1002, TRACK, speed=50.0, dt=0.005, end=50.0, initial_state=state, progress=False,
                      creep_law="polach")
    assert polach.options["contact"] == "tables (polach)"
    dead = simulate(s1002, TRACK, speed=50.0, dt=0.005, end=50.0, initial_state=state, progress=False,
                    contact="deadband")
    assert "contact" not in dead.options
    with pytest.raises(ValueError, match="contact must be"):
        simulate(s1002, TRACK, speed=50.0, end=50.0, progress=False, contact="rigid")
    with pytest.raises(ValueError, match="creep law"):
        simulate(s1002, TRACK, speed=50.0, end=50.0, progress=False, creep_law="coulomb")


def test_linear_coefficients_follow_the_speed(s1002):
    slow, fast = linear_coefficients(s1002, 20.0), linear_coefficients(s1002, 40.0)
    assert slow[0, 2] == pytest.approx(2 * fast[0, 2])  # C ~ 1/v
    assert slow[0, 0] == fast[0, 0]
    assert slow[0, 0] == pytest.approx(1e6 * 0 + s1002.values["Gamma_e_ky"])
