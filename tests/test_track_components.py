"""The track's vertical level, cross level and gauge (``docs/track.md``, "Track components"):
the file format, the rail-ground inputs of a time run, a warning where a model cannot take
a component, the wheel loads of a time run against the closed-form response of the
exported matrices, and the quasi-static loads on a twist ramp (``express.analysis.twist``)."""

from __future__ import annotations

import re
import warnings

import numpy as np
import pytest

from cli_support import CONVENTIONAL, assert_input_error, run_json
from express.analysis.time.simulate import simulate
from express.analysis.time.track_inputs import track_inputs
from express.analysis.twist import quasi_static_loads, twist_ramp, twisted_track
from express.base.diagnostics import ArgumentError, ModelError, ModelWarning
from express.numeric.statespace import load_vehicle
from express.rail.track import NoIrregularity, SinusoidIrregularity, Straight, Track, load_track
from test_ride_vehicle import two_axle_toml

SPEED = 27.0  # m/s
KH, CH, B0, B1, KZ, A = 1.0e9, 2.0e5, 0.75, 1.0, 1.2e6, 4.0  # the two-axle model's numbers
STATION = {"W1": A, "W2": -A}


@pytest.fixture(scope="module")
def two_axle(tmp_path_factory):
    """Body on two wheelsets, each wheel on a contact spring kH, cH to its own rail
    ground W1_railL, W1_railR, ... (tests/test_ride_vehicle.py)."""
    path = tmp_path_factory.mktemp("components") / "two_axle.toml"
    path.write_text(two_axle_toml(contact_damping=CH), encoding="utf-8")
    return load_vehicle(path)


# --- files -------------------------------------------------------------------------------


def test_components_from_a_track_file(tmp_path):
    (tmp_path / "gauge.csv").write_text("distance,g\n0,0\n100,0.004\n", encoding="utf-8")
    (tmp_path / "t.toml").write_text(
        '[[segment]]\ntype = "straight"\nlength = 200.0\n'
        '[vertical]\ntype = "sinusoid"\namplitude = "2 mm"\nwavelength = "25 m"\n'
        '[cross_level]\ntype = "points"\npoints = [[50, 0], [56, 0.018], [100, 0.018]]\n'
        '[gauge]\ntype = "csv"\nfile = "gauge.csv"\n', encoding="utf-8")
    track = load_track(tmp_path / "t.toml")
    assert track.applied_components == ("vertical", "cross_level", "gauge")
    assert isinstance(track.irregularity, NoIrregularity)
    assert track.vertical.value(25 / 4) == pytest.approx(0.002)
    assert track.cross_level.value(53.0) == pytest.approx(0.009) and track.cross_level.rate(53.0) == pytest.approx(0.003)
    assert track.gauge.value(50.0) == pytest.approx(0.002)


def test_bad_component_tables_are_reported_by_line(tmp_path):
    (tmp_path / "bad.toml").write_text(
        '[[segment]]\ntype = "straight"\nlength = 200.0\n'
        '[vertical]\ntype = "spectrum"\n'
        '[cross_level]\ntype = "points"\npoints = [[1, 2]]\n'
        '[gauge]\ntype = "points"\npoints = "a ramp"\n', encoding="utf-8")
    with pytest.raises(ModelError) as info:
        load_track(tmp_path / "bad.toml")
    text = str(info.value)
    assert "bad.toml:4: vertical (spectrum): missing 'spectrum' (one of erri_low, erri_high" in text
    assert "bad.toml:8: cross_level (points): need at least two points, got 1" in text
    assert "bad.toml:11: gauge (points): 'points' must be an array of [distance, value] pairs" in text


def test_a_twist_beyond_the_geometry_is_refused():
    with pytest.raises(ArgumentError, match="reaches a cross level of 150 mm, more than 100 mm"):
        twist_ramp(0.005, 30.0)
    with pytest.raises(ArgumentError, match="length > 0"):
        twist_ramp(0.003, 0.0)


HEADER = "distance [m], alignment [mm], vertical [mm], cross_level [mm], gauge [mm]\n"


def _measured(tmp_path, rows, header=HEADER):
    (tmp_path / "m.csv").write_text(header + rows, encoding="utf-8")
    (tmp_path / "m.toml").write_text('[[segment]]\ntype = "straight"\nlength = 100.0\n[measured]\nfile = "m.csv"\n',
                                     encoding="utf-8")
    return tmp_path / "m.toml"


def test_a_measured_file_gives_the_four_components(tmp_path):
    track = load_track(_measured(tmp_path, "0, 0, 0, 0, 0\n10, 1.5, -2, 3, 1\n20, 0, 0, 0, 0\n"))
    assert track.applied_components == ("alignment", "vertical", "cross_level", "gauge")
    at = {name: track.component(name).value(5.0) for name in track.applied_components}
    assert at == pytest.approx({"alignment": 0.75e-3, "vertical": -1e-3, "cross_level": 1.5e-3, "gauge": 0.5e-3})
    # columns in any order, units of each its own
    other = load_track(_measured(tmp_path, "0, 0, 0, 0, 0\n1000, 3, 0.2, 0, 0\n",
                                 "distance [cm], gauge [mm], vertical [cm], alignment [m], cross_level [mm]\n"))
    assert other.gauge.value(10.0) == pytest.approx(3e-3) and other.vertical.value(10.0) == pytest.approx(2e-3)


@pytest.mark.parametrize("header, rows, message", [
    ("distance [m], alignment [mm], vertical [mm], gauge [mm]\n", "0,0,0,0\n", "m.csv:1: measured: missing column "
     "cross_level (every one of distance, alignment, vertical, cross_level, gauge is needed, with its unit)"),
    (HEADER.replace("vertical [mm]", "vertical [kg]"), "", "m.csv:1: measured: column 'vertical': unit kg is a mass"),
    (HEADER, "0,0,0,0,0\n10,1,x,0,0\n20,0,0\n", "m.csv:3: measured: not a number: '10,1,x,0,0'"),
    (HEADER, "0,0,0,0,0\n10,1,x,0,0\n20,0,0\n", "m.csv:4: measured: expected 5 columns"),
    (HEADER, "0,0,0,0,0\n10,0,0,200,0\n", "measured: cross_level: |cross_level| reaches 0.2 m"),
])
def test_bad_measured_files_are_refused(tmp_path, header, rows, message):
    with pytest.raises(ModelError, match=re.escape(message)):
        load_track(_measured(tmp_path, rows, header))


def test_a_measured_file_with_a_missing_column_exits_2_from_simulate(capsys, tmp_path):
    path = _measured(tmp_path, "0,0,0,0\n10,0,0,0\n", "distance [m], alignment [mm], vertical [mm], gauge [mm]\n")
    assert_input_error(capsys, "simulate", CONVENTIONAL, "--track", str(path), mentions="missing column cross_level")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["m.csv", "m.toml"]  # nothing written


# --- the inputs of a run -----------------------------------------------------------------


def test_rail_heights_and_rates_at_each_wheel(two_axle):
    vertical, cross = SinusoidIrregularity(0.002, 25.0), SinusoidIrregularity(0.001, 40.0, phase=0.3)
    track = Track((Straight(200.0),), vertical=vertical, cross_level=cross)
    distance = np.array([10.0, 23.7, 61.0])
    inputs = track_inputs(two_axle, track, distance, SPEED)
    for wheelset, x in STATION.items():
        s = distance - (A - x)  # the leading wheelset is at the distance
        for side, sign in (("L", -0.5), ("R", 0.5)):  # z_L = z_v - c/2, z_R = z_v + c/2
            column = two_axle.inputs.index(f"{wheelset}_rail{side}.z")
            np.testing.assert_allclose(inputs.u[:, column], vertical.value(s) + sign * cross.value(s), rtol=1e-14)
            np.testing.assert_allclose(inputs.u_rate[:, column], SPEED * (vertical.rate(s) + sign * cross.rate(s)),
                                       rtol=1e-14)


def test_a_component_the_model_cannot_take_is_named():
    lateral = load_vehicle(CONVENTIONAL)
    track = Track((Straight(100.0),), vertical=SinusoidIrregularity(0.001, 20.0))
    with pytest.warns(ModelWarning, match="the track's vertical is not applied: .* has no rail ground"):
        inputs = track_inputs(lateral, track, np.array([5.0]), SPEED)
    assert not np.any(inputs.u)
    manchester = load_vehicle("examples/manchester.toml")  # one ground under both wheels of each wheelset
    both = Track((Straight(100.0),), vertical=SinusoidIrregularity(0.001, 20.0),
                 cross_level=SinusoidIrregularity(0.001, 20.0), gauge=SinusoidIrregularity(0.001, 20.0))
    with pytest.warns(ModelWarning, match="the track's gauge is not applied"):
        inputs = track_inputs(manchester, both, np.array([5.0]), SPEED)
    assert inputs.u[0, manchester.inputs.index("T1_GF.z")] == pytest.approx(0.001 * np.sin(2 * np.pi * 5.0 / 20.0))
    # the cross level is taken at the wheels' contact springs (tests/test_time_rail_heights.py)
    assert inputs.rail is not None and inputs.rail.heights[0, :2] == pytest.approx(
        [-0.0005 * np.sin(2 * np.pi * 5.0 / 20.0), 0.0005 * np.sin(2 * np.pi * 5.0 / 20.0)])
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # vertical level and cross level: taken, no warning
        track_inputs(manchester, Track((Straight(100.0),), vertical=SinusoidIrregularity(0.001, 20.0),
                                       cross_level=SinusoidIrregularity(0.001, 20.0)), np.array([5.0]), SPEED)


# --- time runs against the closed form ---------------------------------------------------

WAVELENGTH, AMPLITUDE = 12.0, 0.002  # 2.25 Hz at 27 m/s, near the body bounce (2.5 Hz)


def _closed_form_loads(vehicle, component):
    """Complex amplitude of each wheel's load, ``dQ = -(kH + i w cH)(z + arm rx - z_rail)``,
    from ``(K - w^2 M + i w C) q = (P + i w Pd) u``, the rail input of a wheelset at ``x``
    being the leading one's delayed by ``(x_lead - x) / v``."""
    omega_s = 2 * np.pi / WAVELENGTH
    w = omega_s * SPEED
    u = np.zeros(len(vehicle.inputs), dtype=complex)
    for wheelset, x in STATION.items():
        for side, sign in (("L", -0.5), ("R", 0.5)):
            weight = 1.0 if component == "vertical" else sign
            u[vehicle.inputs.index(f"{wheelset}_rail{side}.z")] = weight * AMPLITUDE * np.exp(-1j * omega_s * (A - x))
    matrix = vehicle.stiffness - w**2 * vehicle.mass + 1j * w * vehicle.damping(SPEED)
    q = np.linalg.solve(matrix, (vehicle.forcing(SPEED) + 1j * w * vehicle.forcing_rate(SPEED)) @ u)
    loads = {}
    for wheelset in STATION:
        for side, arm in (("L", B0), ("R", -B0)):
            deflection = (q[vehicle.dof_index(f"{wheelset}.z")] + arm * q[vehicle.dof_index(f"{wheelset}.rx")]
                          - u[vehicle.inputs.index(f"{wheelset}_rail{side}.z")])
            loads[wheelset + side] = -(KH + 1j * w * CH) * deflection
    return loads


def _run_loads(vehicle, component, dt):
    """Complex amplitude ``Z`` (load = Re Z sin wt + Im Z cos wt + const) of each wheel's
    load in a linear run, fitted over the last 8 s of 14.8 s (transients decay in 0.5 s)."""
    track = Track((Straight(400.0),), **{component: SinusoidIrregularity(AMPLITUDE, WAVELENGTH)})
    result = simulate(vehicle, track, speed=SPEED, dt=dt, flange=False, saturation=False)
    inputs = track_inputs(vehicle, track, result.distance, SPEED)
    w = 2 * np.pi / WAVELENGTH * SPEED
    late = result.time > 6.0
    t = result.time[late]
    basis = np.column_stack([np.sin(w * t), np.cos(w * t), np.ones_like(t)])
    loads = {}
    for wheelset in STATION:
        for side, arm in (("L", B0), ("R", -B0)):
            rail = vehicle.inputs.index(f"{wheelset}_rail{side}.z")
            z, rx = vehicle.dof_index(f"{wheelset}.z"), vehicle.dof_index(f"{wheelset}.rx")
            deflection = result.q[:, z] + arm * result.q[:, rx] - inputs.u[:, rail]
            rate = result.q_dot[:, z] + arm * result.q_dot[:, rx] - inputs.u_rate[:, rail]
            coefficients = np.linalg.lstsq(basis, -(KH * deflection + CH * rate)[late], rcond=None)[0]
            loads[wheelset + side] = coefficients[0] + 1j * coefficients[1]
    return loads


@pytest.mark.parametrize("component", ["vertical", "cross_level"])
def test_wheel_loads_of_a_sine_match_the_closed_form_and_converge(two_axle, component):
    """Vertical level: both wheels of a wheelset alike (bounce and pitch); cross level:
    opposite (roll). The error is the step's, second order (the inputs are held linear over a
    step, and the load is the small difference of wheel and rail heights on a 1 GN/m
    contact): 0.65-1.2 % at 1 ms, 0.16-0.30 % at 0.5 ms (ratio 4.06-4.10), 3.5e-5-1.0e-4
    after Richardson extrapolation of the two (25-42 % at the default 5 ms)."""
    exact = _closed_form_loads(two_axle, component)
    coarse, fine = _run_loads(two_axle, component, 0.001), _run_loads(two_axle, component, 0.0005)
    for wheelset in STATION:
        left, right = exact[wheelset + "L"], exact[wheelset + "R"]
        assert left == pytest.approx(right if component == "vertical" else -right, rel=1e-9)
        assert np.sign(fine[wheelset + "L"].real) == np.sign(fine[wheelset + "R"].real) * (1 if component == "vertical" else -1)
    for wheel, value in exact.items():
        error_fine, error_coarse = abs(fine[wheel] - value) / abs(value), abs(coarse[wheel] - value) / abs(value)
        assert error_fine < 0.004  # achieved 0.16 ... 0.30 %
        assert 3.8 < error_coarse / error_fine < 4.3  # second order in the step
        extrapolated = (4 * fine[wheel] - coarse[wheel]) / 3
        assert abs(extrapolated - value) / abs(value) < 2e-4


# --- twist ---------------------------------------------------------------------------------


def test_quasi_static_twist_loads_match_the_static_solution_and_the_roll_chain(two_axle):
    """A 3 mm/m ramp over 30 m with both wheelsets on it (W1 20 m, W2 12 m into it): the
    tool's dQ against (a) ``K q = P u`` solved here with the ramp's rail heights and the
    contact springs written by hand, (b) the closed form of the roll chain: each
    wheelset's contact (2 kH b0^2) in series with its primary (2 kz b1^2), the rigid body
    between them; the twist moment ``k (phi1 - phi2) / 2`` over ``2 b0``."""
    into = 20.0
    loads = quasi_static_loads(two_axle, twisted_track(0.003, 30.0), 50.0 + into)
    cross = {"W1": 0.003 * into, "W2": 0.003 * (into - 2 * A)}
    u = np.zeros(len(two_axle.inputs))
    for wheelset, c in cross.items():
        u[two_axle.inputs.index(f"{wheelset}_railL.z")], u[two_axle.inputs.index(f"{wheelset}_railR.z")] = -c / 2, c / 2
    q = np.linalg.solve(two_axle.stiffness, two_axle.forcing(SPEED) @ u)
    for i, wheelset in enumerate(STATION):
        for side, (arm, sign) in enumerate(((B0, -0.5), (-B0, 0.5))):
            deflection = q[two_axle.dof_index(f"{wheelset}.z")] + arm * q[two_axle.dof_index(f"{wheelset}.rx")] - sign * cross[wheelset]
            assert loads.delta_q[i, side] == pytest.approx(-KH * deflection, rel=1e-6)  # achieved 1e-13
    chain = 1 / (1 / (2 * KH * B0**2) + 1 / (2 * KZ * B1**2))
    moment = chain * (cross["W2"] - cross["W1"]) / (2 * B0) / 2  # rail roll -c / (2 b0)
    expected = np.array([[moment, -moment], [-moment, moment]]) / (2 * B0)
    np.testing.assert_allclose(loads.delta_q, expected, rtol=1e-6)  # achieved 2e-13
    wheel_load = (20000.0 + 2 * 1500.0) * 9.81 / 4
    np.testing.assert_allclose(loads.ratio, expected / wheel_load, rtol=1e-6)
    assert loads.largest_unloading == pytest.approx(abs(moment) / (2 * B0) / wheel_load)


def test_the_twist_command(capsys, two_axle, tmp_path):
    """``express twist``: the largest unloading of each wheel over a 3 mm/m ramp, the
    diagonal pair (leading left, trailing right) at the roll-chain value; a model with one
    ground under both rails is twisted at its contact springs."""
    path = tmp_path / "two_axle.toml"
    path.write_text(two_axle_toml(contact_damping=CH), encoding="utf-8")
    data = run_json(capsys, "twist", str(path), "--twist", "3", "--length", "30 m")
    chain = 1 / (1 / (2 * KH * B0**2) + 1 / (2 * KZ * B1**2))
    expected = chain * 0.003 * 2 * A / (2 * B0) / 2 / (2 * B0) / ((20000.0 + 2 * 1500.0) * 9.81 / 4)
    unloading = {(row["wheelset"], row["wheel"]): row["unloading"] for row in data["wheels"]}
    assert unloading[("W1", "left")] == pytest.approx(expected, rel=1e-9)
    assert unloading[("W2", "right")] == pytest.approx(expected, rel=1e-9)
    assert unloading[("W1", "right")] < 1e-9 and unloading[("W2", "left")] < 1e-9  # rounding only
    assert data["largest_unloading"] == pytest.approx(expected, rel=1e-9) and data["limit"] is None
    # one ground under both rails of a wheelset: the rail heights are imposed at its contact springs
    manchester = run_json(capsys, "twist", "examples/manchester.toml", "--twist", "3", "--length", "30 m")
    assert manchester["largest_unloading"] > 0.01
    assert_input_error(capsys, "twist", str(path), "--twist", "0", mentions="non-zero")


def test_per_rail_grounds_are_found_by_side_whatever_their_names(two_axle, tmp_path):
    """The two-axle vehicle with its rail grounds renamed G1 ... G4 (no ``_railL`` names):
    each holds one wheelset with all its points on one side, so it is that wheel's rail
    and takes ``z_v -+ c/2`` as the named ones do; the twist loads are the same."""
    text = two_axle_toml(contact_damping=CH)
    for new, old in (("G1", "W1_railL"), ("G2", "W1_railR"), ("G3", "W2_railL"), ("G4", "W2_railR")):
        text = text.replace(old, new)
    path = tmp_path / "renamed.toml"
    path.write_text(text, encoding="utf-8")
    renamed = load_vehicle(path)
    track = Track((Straight(200.0),), vertical=SinusoidIrregularity(0.002, 25.0),
                  cross_level=SinusoidIrregularity(0.001, 40.0, phase=0.3))
    distance = np.array([10.0, 23.7, 61.0])
    named, other = track_inputs(two_axle, track, distance, SPEED), track_inputs(renamed, track, distance, SPEED)
    for new, old in (("G1", "W1_railL"), ("G2", "W1_railR"), ("G3", "W2_railL"), ("G4", "W2_railR")):
        np.testing.assert_array_equal(other.u[:, renamed.inputs.index(f"{new}.z")], named.u[:, two_axle.inputs.index(f"{old}.z")])
    twist = twisted_track(0.003, 30.0)
    np.testing.assert_allclose(quasi_static_loads(renamed, twist, 70.0).delta_q,
                               quasi_static_loads(two_axle, twist, 70.0).delta_q, rtol=1e-12)


def test_the_bundled_twist_file_is_the_twisted_track():
    from pathlib import Path

    example = load_track(Path("examples/tracks/twist_3mm_per_m.toml"))
    made = twisted_track(0.003, 30.0)
    s = np.linspace(-10.0, 140.0, 301)
    np.testing.assert_allclose(example.cross_level.value(s), made.cross_level.value(s), rtol=0, atol=1e-15)
    assert example.length == made.length
