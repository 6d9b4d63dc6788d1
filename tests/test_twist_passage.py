"""The standard twist by a slow time run (:mod:`express.analysis.twist.passage`): the test
track puts every wheelset on its own cross level at the end, a car without friction gives
the linear static solution's loads, and the wagon's run converges in speed and step."""

from __future__ import annotations

import numpy as np
import pytest

from express.analysis.twist import rail_height_loads, standard_twist
from express.analysis.twist.passage import RUN_IN, standard_twist_track, twist_run_loads
from express.numeric.statespace import load_vehicle


@pytest.fixture(scope="module")
def car():
    return load_vehicle("examples/manchester-s1002.toml")


def test_the_test_track_puts_each_wheelset_on_its_standard_cross_level(car):
    """With the leading wheelset at the end, the cross level under each wheelset is the
    standard twist's (to 1e-15 m); the track is level a run-in before the trailing one."""
    twist = standard_twist(car)
    track, end = standard_twist_track(car, twist)
    stations = np.array([w.station for w in car.wheelsets])
    under = track.cross_level.value(end - (stations.max() - stations))
    np.testing.assert_allclose(under, twist.cross_level, rtol=0, atol=1e-15)
    trailing = end - (stations.max() - stations.min())
    assert track.cross_level.value(trailing - RUN_IN) == 0.0 and track.length >= end


@pytest.mark.slow
def test_a_car_without_friction_gets_the_static_loads(car):
    """The Manchester car (linear suspension): the time run's loads at the end against
    :func:`rail_height_loads`: within 1.5 % of the largest |dQ| (achieved 0.77 %: the
    dampers at 1 m/s and the contact's own lever arm on the rolled wheelsets)."""
    twist = standard_twist(car)
    static = rail_height_loads(car, twist.heights)[0]
    run = twist_run_loads(car, twist)
    scale = np.abs(static).max()
    assert scale > 5e3
    np.testing.assert_allclose(run.delta_q, static, rtol=0, atol=0.015 * scale)
    assert run.step_change < 2e-3


@pytest.mark.slow
def test_the_wagons_passage_converges_in_speed_and_step():
    """The Y25 wagon (Lenoir-link friction) at 2.5 ms: the assessed largest -dQ/Q0 0.7123
    at 1 m/s, 0.7145 at 0.5 m/s (0.7150 at 0.25 m/s: converging; asserted 0.005), every
    wheel's dQ/Q0 within 0.0098 (asserted 0.015), and the run's own step check (asserted
    0.005, achieved 0.0017); the friction slipping gives about a third of the linear
    static solution's unloading (0.71 against 2.07)."""
    wagon = load_vehicle("examples/y25-wagon.toml")
    twist = standard_twist(wagon)
    loads = np.array([w.wheel_load for w in wagon.wheelsets])[:, None]
    run, slower = twist_run_loads(wagon, twist), twist_run_loads(wagon, twist, speed=0.5)
    assert np.abs(run.delta_q - slower.delta_q).max() / loads.max() < 0.015
    assert abs((-run.delta_q / loads).max() - (-slower.delta_q / loads).max()) < 0.005
    assert run.step_change < 0.005
    static = rail_height_loads(wagon, twist.heights)[0]
    assert (-run.delta_q / loads).max() < 0.5 * (-static / loads).max()
    assert "2.5 ms" in run.method and "from 5 ms" in run.method


@pytest.mark.slow
def test_a_ramp_passage_by_time_run_gives_the_static_passage_on_a_car_without_friction(car):
    """``run_passage`` against ``twist_passage`` on a 3 mm/m ramp over 30 m: every wheel's
    dQ at every 0.5 m within 1.5 % of the largest |dQ| (achieved 1.27 %, the dampers at
    1 m/s and the contact's lever arm), and the step check's change small."""
    from express.analysis.twist import twist_passage, twisted_track
    from express.analysis.twist.passage import run_passage

    track = twisted_track(0.003, 30.0, lead_in=10.0, lead_out=10.0)
    distance, delta, loads = twist_passage(car, track, 0.5)
    timed, by_run, loads_run, run = run_passage(car, track, 0.5)
    np.testing.assert_array_equal(timed, distance)
    np.testing.assert_array_equal(loads_run, loads)
    scale = np.abs(delta).max()
    assert scale > 5e3
    np.testing.assert_allclose(by_run, delta, rtol=0, atol=0.015 * scale)
    assert run.step_change < 2e-3


def test_the_command_passes_a_friction_wagon_along_a_ramp_by_a_time_run(capsys):
    """``express twist`` with ``--twist`` on the Y25 wagon: the JSON says the loads came
    from the slow time run, and the largest unloading is one of the wheels'."""
    from cli_support import run_json

    data = run_json(capsys, "twist", "examples/y25-wagon.toml", "--twist", "3", "--length", "10 m")
    assert "friction slipping" in data["method"]
    assert data["largest_unloading"] == max(row["unloading"] for row in data["wheels"]) > 0.05


def test_a_run_without_contact_tables_reads_the_loads_of_its_springs(tmp_path):
    """The two-axle vehicle of ``tests/test_ride_vehicle.py`` (no profiles: the dead-band
    contact; wheels on damped contact springs to a ground under each rail) on a 3 mm/m ramp:
    ``run_passage``'s loads, from the springs as the contact march takes them, against the
    static ``twist_passage``: within 1 % of the largest |dQ| (12.8 kN) at 1 m/s (achieved
    0.76 %, after the ramp's kinks), first order in the speed (0.38 % at 0.5 m/s)."""
    from express.analysis.twist import twist_passage, twisted_track
    from express.analysis.twist.passage import run_passage
    from test_ride_vehicle import two_axle_toml

    path = tmp_path / "two_axle.toml"
    path.write_text(two_axle_toml(contact_damping=2.0e5), encoding="utf-8")
    vehicle = load_vehicle(path)
    track = twisted_track(0.003, 20.0, lead_in=10.0, lead_out=10.0)
    _, static, _ = twist_passage(vehicle, track, 0.5)
    scale = np.abs(static).max()
    assert scale > 1e4
    errors = {}
    for speed in (1.0, 0.5):
        _, timed, _, run = run_passage(vehicle, track, 0.5, speed=speed)
        errors[speed] = np.abs(timed - static).max() / scale
        assert run.step_change < 1e-3
    assert errors[1.0] < 0.01 and 1.9 < errors[1.0] / errors[0.5] < 2.1
