"""The cross level at the contact springs of a model with one ground under both rails of a
wheelset (:mod:`express.analysis.time.rail_heights`): its forcing against the columns of the
same vehicle with a ground under each rail, the two vehicles' time runs against each other,
a slow twist passage against the quasi-static solution, and the sparse route."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from express.analysis.time.rail_heights import contact_springs
from express.analysis.time.simulate import simulate
from express.analysis.time.track_inputs import track_inputs
from express.analysis.twist import quasi_static_loads, twisted_track
from express.numeric.statespace import load_vehicle
from express.rail.track import SinusoidIrregularity, Straight, Track
from test_ride_vehicle import two_axle_toml

SPEED = 27.0  # m/s


def _one_ground_toml() -> str:
    """The two-axle vehicle of ``tests/test_ride_vehicle.py`` with its rail grounds
    ``W1_railL``, ``W1_railR`` merged into one ``W1_rail`` under both wheels (and W2's)."""
    text = two_axle_toml(contact_damping=2.0e5)
    for wheelset in ("W1", "W2"):
        text = text.replace(f"[grounds.{wheelset}_railR]\n", "")
        text = text.replace(f"[grounds.{wheelset}_railL]", f"[grounds.{wheelset}_rail]")
        text = text.replace(f'"{wheelset}_railL"', f'"{wheelset}_rail"').replace(f'"{wheelset}_railR"', f'"{wheelset}_rail"')
    return text


@pytest.fixture(scope="module")
def pair(tmp_path_factory):
    """(one ground per wheelset, a ground per rail): the same vehicle written both ways."""
    folder = tmp_path_factory.mktemp("rail_heights")
    (folder / "one.toml").write_text(_one_ground_toml(), encoding="utf-8")
    (folder / "rails.toml").write_text(two_axle_toml(contact_damping=2.0e5), encoding="utf-8")
    return load_vehicle(folder / "one.toml"), load_vehicle(folder / "rails.toml")


def test_the_springs_forcing_is_the_per_rail_vehicles_input_columns(pair):
    """``P_r = -d k_z kappa`` of each wheel equals the column of its rail ground's vertical
    input in the per-rail vehicle's ``P`` (and ``Pd_r`` in ``Pd``): the same equations."""
    one, rails = pair
    assert "W1_rail.z" in one.inputs and "W1_railL.z" not in one.inputs
    springs = contact_springs(one)
    assert springs is not None and np.all(springs.kappa == -1.0)
    columns = [rails.inputs.index(f"{w}_rail{side}.z") for w in ("W1", "W2") for side in "LR"]
    scale = np.abs(rails.forcing(SPEED)).max()
    np.testing.assert_allclose(springs.forcing, rails.forcing(SPEED)[:, columns], rtol=0, atol=1e-12 * scale)
    np.testing.assert_allclose(springs.forcing_rate, rails.forcing_rate(SPEED)[:, columns], rtol=0,
                               atol=1e-12 * np.abs(rails.forcing_rate(SPEED)).max())


@pytest.mark.parametrize("route", ["dense", "sparse"])
def test_a_cross_level_sine_runs_the_same_on_both_vehicles(pair, route):
    """Vertical level and cross level sines (1.5 and 2.5 Hz at 27 m/s) in a linear run at
    1 ms: the one-ground vehicle with its rail heights at the springs and the per-rail
    vehicle with ground inputs give the same coordinates and wheel loads to rounding
    (asserted 1e-9 of the largest; achieved 1.1e-15 and 2.3e-15), on either route."""
    track = Track((Straight(150.0),), vertical=SinusoidIrregularity(0.002, 18.0),
                  cross_level=SinusoidIrregularity(0.001, 10.8, phase=0.4))
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # both vehicles take both components: no warning
        runs = [simulate(v, track, speed=SPEED, dt=0.001, flange=False, saturation=False, route=route) for v in pair]
    assert runs[0].options.get("route") == ("sparse" if route == "sparse" else None)
    np.testing.assert_allclose(runs[0].q, runs[1].q, rtol=0, atol=1e-9 * np.abs(runs[1].q).max())
    loads = [_loads_by_hand(v, r, track, SPEED) for v, r in zip(pair, runs, strict=True)]
    np.testing.assert_allclose(loads[0], loads[1], rtol=0, atol=1e-9 * np.abs(loads[1]).max())
    late = runs[1].time > 1.0  # after the start's transient
    bounce, roll = 0.5 * (loads[1][late, 0] + loads[1][late, 1]), 0.5 * (loads[1][late, 0] - loads[1][late, 1])
    assert np.abs(bounce).max() > 500.0 and np.abs(roll).max() > 200.0  # both components load the wheels


@pytest.fixture(scope="module")
def manchester():
    return load_vehicle("examples/manchester-s1002.toml"), load_vehicle("examples/manchester-rails.toml")


@pytest.mark.slow
def test_the_bundled_car_with_a_ground_under_each_rail_runs_as_the_one_ground_car(manchester):
    """``examples/manchester-rails.toml`` and ``examples/manchester-s1002.toml`` on a 3 mm/m
    twist ramp and a cross-level sine, with the contact tables (FASTSIM) and dynamic wheel
    loads at 2 ms: coordinates and wheel loads agree to rounding (asserted 1e-9 of the
    largest; achieved 2.6e-15 and 7.7e-13)."""
    ramp = twisted_track(0.003, 6.0, lead_in=10.0, lead_out=30.0)
    track = Track(ramp.segments, irregularity=SinusoidIrregularity(0.002, 25.0), cross_level=ramp.cross_level)
    runs = [simulate(v, track, speed=10.0, dt=0.002) for v in manchester]
    np.testing.assert_allclose(runs[0].q, runs[1].q, rtol=0, atol=1e-9 * np.abs(runs[1].q).max())
    loads = [r.wheel_rail.vertical_load for r in runs]
    np.testing.assert_allclose(loads[0], loads[1], rtol=0, atol=1e-9 * np.abs(loads[1]).max())
    unloading = loads[0] - runs[0].wheel_rail.static_load[None, :, None]
    assert np.abs(unloading).max() > 3e3  # the twist unloads the wheels by kilonewtons


def _loads_by_hand(vehicle, result, track, speed):
    """``dQ = -(k_z (d q + e u) + c_z (d q' + e u'))`` of every wheel from the model's own
    contact springs, plus the rail heights' part where the cross level is imposed at them,
    shape (N, 2 n_wheelsets)."""
    from express.rail.vertical_contact import vertical_contacts

    inputs = track_inputs(vehicle, track, result.distance, speed)
    springs = vertical_contacts(vehicle.model, vehicle.values, [w.name for w in vehicle.wheelsets], vehicle.dofs,
                                vehicle.inputs)
    loads = np.column_stack([
        -(s.stiffness * (result.q @ s.dofs + inputs.u @ s.inputs) + s.damping * (result.q_dot @ s.dofs + inputs.u_rate @ s.inputs))
        for pair in springs for s in pair])
    if inputs.rail is not None:
        loads = loads + inputs.rail.load_changes().reshape(loads.shape)
    return loads


@pytest.mark.slow
def test_a_slow_twist_passage_gives_the_quasi_static_loads(manchester):
    """The one-ground car on a 1 mm/m ramp over 40 m (every wheelset on it from 19 m in),
    the leading wheelset 35 m into it: each wheel's load change in a linear time run (2 ms)
    against :func:`quasi_static_loads`, which imposes the rail heights by its own static
    solve (:func:`express.analysis.twist.rail_height_loads`). What remains is the dampers'
    share at the ramp's constant roll rates, first order in the speed: 0.070 % of the
    largest dQ (5763 N) at 1 m/s, 0.035 % at 0.5 m/s; their extrapolation to zero speed
    agrees to 2.3e-6 (asserted 2e-5). With the contact tables the wheels' rise on their
    rails joins the loads (``pressed_loads``: the contact's own lever arm on the rolled
    wheelset), which the linear static solution does not carry: 0.85 % at 1 m/s
    (asserted 1.5 %)."""
    one = manchester[0]
    track = twisted_track(0.001, 40.0, lead_in=10.0, lead_out=10.0)
    changes = {}
    for speed in (1.0, 0.5):
        run = simulate(one, track, speed=speed, dt=0.002, end=46.0, flange=False, saturation=False)
        k = int(np.argmin(np.abs(run.distance - 45.0)))
        changes[speed] = _loads_by_hand(one, run, track, speed)[k]
    expected = quasi_static_loads(one, track, 45.0).delta_q.ravel()
    scale = np.abs(expected).max()
    assert scale > 5000.0
    errors = {speed: np.abs(change - expected).max() / scale for speed, change in changes.items()}
    assert errors[1.0] < 1e-3 and 1.9 < errors[1.0] / errors[0.5] < 2.1  # first order in the speed
    assert np.abs(2 * changes[0.5] - changes[1.0] - expected).max() / scale < 2e-5
    run = simulate(one, track, speed=1.0, dt=0.002, end=46.0)
    k = int(np.argmin(np.abs(run.distance - 45.0)))
    got = (run.wheel_rail.vertical_load[k] - run.wheel_rail.static_load[:, None]).ravel()
    assert np.abs(got - expected).max() / scale < 0.015


def test_ride_takes_the_cross_level_at_the_springs_as_the_time_run_does(pair):
    """``ride_response`` of the one-ground vehicle (its rail heights as one more input per
    wheel) and of the per-rail vehicle (ground inputs) under ERRI-low vertical level and
    cross level: every output's PSD agrees (asserted 1e-9 of its largest; achieved about
    1e-13), and the one-ground ride says where the cross level is imposed."""
    from express.analysis.ride import ride_response, track_class_spectra

    spectra = {c: s for c, s in track_class_spectra("ERRI-low").items() if c in ("vertical", "cross_level")}
    f = np.geomspace(0.5, 30.0, 200)
    one, rails = (ride_response(v, spectra, SPEED, f) for v in pair)
    assert one.components == rails.components == ("vertical", "cross_level")
    assert any("contact springs" in note for note in one.notes)
    assert one.names == rails.names and "W1.dQL" in rails.names
    for name in rails.names:
        a, b = one.psd_of(name), rails.psd_of(name)
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-9 * b.max(), err_msg=name)
    roll = one.transfer[:, one.index("W1.dQL"), 1] + one.transfer[:, one.index("W1.dQR"), 1]
    assert np.abs(roll).max() < 1e-9 * np.abs(one.transfer[:, one.index("W1.dQL"), 1]).max()  # opposite on the wheels
