"""Curving simulation (``express.analysis.time.simulate``): the paper's Fig. 9 qualitatively,
agreement with a reference ODE solver, step convergence, symmetry, linear frequency
response, determinism and result files.

The paper's run: ``paper_curve()`` (50 m straight, 95 m sine transition, 170 m curve
R = 400 m with 95 mm cant, 95 m transition, 50 m straight; curve to the LEFT, rho > 0)
at 120 km/h with flange contact and creep saturation.  ``d1`` is the leading wheelset's
distance along the track; the last wheelset (W4) is 2 (lT + a) = 16.7 m behind it.
"""

from __future__ import annotations

import csv
import os
from pathlib import Path

import numpy as np
import pytest

from express.analysis.time.simulate import continuous_rhs, derived_outputs, simulate, track_inputs
from express.base.diagnostics import OutputError
from express.io import load_model
from express.io.text_formats import column_name
from express.numeric.statespace import vehicle_model
from express.rail.track import SinusoidIrregularity, Straight, Track, paper_curve

ROOT = Path(__file__).resolve().parents[1]
RADIUS = 400.0
STEADY = (200.0, 300.0)  # d1 range with every station in the circular curve, transients gone
FIRST_TRANSITION = (50.0, 145.0)
SECOND_TRANSITION = (315.0, 410.0)


@pytest.fixture(scope="module")
def steered():
    return vehicle_model(load_model(ROOT / "examples" / "forced-steering.toml"))


@pytest.fixture(scope="module")
def conventional():
    return vehicle_model(load_model(ROOT / "examples" / "conventional.toml"))


@pytest.fixture(scope="module")
def track():
    return paper_curve()


@pytest.fixture(scope="module")
def run_steered(steered, track):
    return simulate(steered, track, progress=False)


@pytest.fixture(scope="module")
def run_conventional(conventional, track):
    return simulate(conventional, track, progress=False)


def window(result, lo, hi):
    return (result.distance >= lo) & (result.distance < hi)


def steady_mean(result, name):
    return float(np.mean(result.outputs[name][window(result, *STEADY)]))


# ---------------------------------------------------------------- the run itself


def test_run_covers_the_track_on_the_requested_grid(run_steered, steered, track):
    r = run_steered
    assert r.distance[0] == 0.0 and r.distance[-1] >= track.length - 1e-9
    np.testing.assert_allclose(np.diff(r.time), 0.005, rtol=1e-12)
    np.testing.assert_allclose(r.distance, r.speed * r.time, rtol=1e-12)
    assert r.speed == pytest.approx(120 / 3.6)
    assert r.q.shape == r.q_dot.shape == (r.time.size, steered.n)
    assert r.dofs == steered.dofs
    assert np.all(np.isfinite(r.q)) and np.all(np.isfinite(r.q_dot))
    for name in ("Y1", "Y4", "YQ1", "Ytot1", "flange1", "dy1", "psi_TW1", "psi_TW4", "theta_L1", "rho1", "S1"):
        assert r.outputs[name].shape == r.time.shape, name
    assert r.options == {"flange": True, "saturation": True, "dt": 0.005, "speed_from": "track"}
    # the track seen by the leading wheelset
    assert r.outputs["rho1"].max() == pytest.approx(1 / RADIUS)
    assert r.outputs["S1"].max() == pytest.approx(0.095)


def test_nothing_moves_on_the_first_straight(run_steered):
    r = run_steered
    before = r.distance < FIRST_TRANSITION[0]
    assert np.all(r.q[before] == 0.0) and np.all(r.q_dot[before] == 0.0)
    assert all(np.all(values[before] == 0.0) for values in r.outputs.values())


def test_simulate_rejects_bad_arguments(steered, track):
    with pytest.raises(ValueError):
        simulate(steered, track, start=100.0, end=50.0, progress=False)
    with pytest.raises(ValueError):
        simulate(steered, track, speed=0.0, progress=False)


# ---------------------------------------------------------------- Fig. 9, qualitatively


def test_lever_follows_the_curvature(run_steered, steered):
    r = run_steered
    theta = r.outputs["theta_L1"]
    values = steered.values
    geometric = values["bL"] * values["lT"] / (RADIUS * values["lLU"])  # 0.06 rad
    assert geometric == pytest.approx(0.06)
    steady = theta[window(r, *STEADY)]
    mean = float(steady.mean())
    # steady in the curve, near the geometric angle, a little less (link stiffnesses)
    assert np.ptp(steady) < 0.01 * mean
    assert 0.85 * geometric < mean < geometric
    # zero on the straights (before the curve, and back near zero after it)
    assert np.all(theta[r.distance < FIRST_TRANSITION[0]] == 0.0)
    assert np.max(np.abs(theta[r.distance > 440.0])) < 0.01 * mean
    # ramps up in the first transition, down in the second (the 163 Hz lever mode
    # ringing is allowed a little)
    up = theta[window(r, FIRST_TRANSITION[0], FIRST_TRANSITION[1] + 5)]
    down = theta[window(r, SECOND_TRANSITION[0] + 10, SECOND_TRANSITION[1])]
    assert np.min(np.diff(up)) > -1e-3 * mean
    assert np.max(np.diff(down)) < 1e-3 * mean
    # and it does so with the vehicle on the ramp, not later: half-way near the middle
    half = r.distance[np.argmax(theta > 0.5 * mean)]
    assert 95.0 < half < 110.0
    # the right lever mirrors the left one; the rear bogie's levers turn the same way
    np.testing.assert_allclose(r.outputs["theta_L2"], -theta, atol=1e-12)
    assert steady_mean(r, "theta_L3") == pytest.approx(-mean, rel=0.1)


def test_steering_makes_both_axles_radial(run_steered, run_conventional, steered):
    radial = steered.values["a"] / RADIUS  # 1.15 / 400
    steered_tw = {j: steady_mean(run_steered, f"psi_TW{j}") for j in (1, 2, 3, 4)}
    conventional_tw = {j: steady_mean(run_conventional, f"psi_TW{j}") for j in (1, 2, 3, 4)}
    # leading axle of each bogie yawed toward the curve centre (+), trailing one outward (-)
    for lead, trail in ((1, 2), (3, 4)):
        assert steered_tw[lead] == pytest.approx(radial, rel=0.1)
        assert steered_tw[trail] == pytest.approx(-radial, rel=0.1)
        for j, ideal in ((lead, radial), (trail, -radial)):
            assert abs(steered_tw[j] - ideal) < 0.2 * abs(conventional_tw[j] - ideal), j
    # without steering the axles stay nearly parallel in the bogie
    assert abs(conventional_tw[1]) < 0.2 * radial and abs(conventional_tw[2]) < 0.2 * radial


def test_steering_lowers_and_evens_out_the_lateral_forces(run_steered, run_conventional):
    s1, s2 = steady_mean(run_steered, "Y1"), steady_mean(run_steered, "Y2")
    c1, c2 = steady_mean(run_conventional, "Y1"), steady_mean(run_conventional, "Y2")
    assert s1 > 0 and c1 > 0  # the outer (right) rail pushes the leading axle toward the centre
    assert s1 < 0.8 * c1
    assert run_steered.max_abs()["Y1"] < 0.8 * run_conventional.max_abs()["Y1"]
    assert abs(s1 - s2) < 0.5 * abs(c1 - c2)
    # the leading wheelset flanges on the OUTER rail: y - yR < -delta in a left curve
    for r in (run_steered, run_conventional):
        assert np.all(r.outputs["dy1"][window(r, *STEADY)] < 0.0)
        assert np.all(r.outputs["flange1"][window(r, *STEADY)] > 0.0)


@pytest.mark.parametrize("which", ["steered", "conventional"])
def test_everything_returns_to_zero_after_the_curve(which, run_steered, run_conventional):
    r = run_steered if which == "steered" else run_conventional
    end = r.distance > 440.0  # the whole vehicle on the last straight, 30 m on
    for name, values in r.outputs.items():
        peak = np.max(np.abs(values))
        assert np.max(np.abs(values[-1])) <= 0.02 * peak + 1e-300, name
    assert np.all(r.outputs["flange1"][end] == 0.0) and np.all(r.outputs["flange4"][end] == 0.0)


def test_state_decays_on_a_long_straight_after_the_curve(steered):
    r = simulate(steered, paper_curve(lead_out=200.0), progress=False)
    scale = np.max(np.abs(r.q), axis=0)
    assert np.all(np.abs(r.q[-1]) <= 5e-3 * scale + 1e-15)


def test_a_right_curve_mirrors_the_left_curve(steered):
    """The equations are odd in (state, inputs): flange contact and saturation too."""
    left = simulate(steered, paper_curve("left"), end=250.0, progress=False)
    right = simulate(steered, paper_curve("right"), end=250.0, progress=False)
    scale = np.max(np.abs(left.q))
    np.testing.assert_allclose(right.q, -left.q, rtol=0, atol=1e-12 * scale)
    np.testing.assert_allclose(right.outputs["Y1"], -left.outputs["Y1"], rtol=0, atol=1e-9)


# ---------------------------------------------------------------- numerics


def _reference(vehicle, track, result, rtol=1e-8, atol=1e-10):
    from scipy.integrate import solve_ivp

    rhs = continuous_rhs(vehicle, track)
    solution = solve_ivp(rhs, (0.0, float(result.time[-1])), np.zeros(2 * vehicle.n), method="RK45",
                         rtol=rtol, atol=atol, t_eval=result.time)
    assert solution.success, solution.message
    n = vehicle.n
    states = solution.y.T
    inputs = track_inputs(vehicle, track, result.distance, vehicle.speed)
    return states, derived_outputs(vehicle, states[:, :n], states[:, n:], inputs, vehicle.speed)


@pytest.mark.slow
def test_march_agrees_with_solve_ivp_on_the_same_equations(steered, track):
    """First 150 m (through the first transition into the curve, where |Q1| peaks),
    flange contact and saturation on; RK45 at rtol 1e-8 on ``continuous_rhs``."""
    result = simulate(steered, track, end=150.0, progress=False)
    states, outputs = _reference(steered, track, result)
    n = steered.n
    peak = np.max(np.abs(outputs["Y1"]))
    assert peak > 20e3  # the flanging part of the run is included
    assert np.max(np.abs(result.outputs["Y1"])) == pytest.approx(peak, rel=0.01)
    assert np.max(np.abs(result.outputs["Y1"] - outputs["Y1"])) < 0.01 * peak
    scale = np.max(np.abs(states[:, :n]), axis=0)
    assert np.all(np.max(np.abs(result.q - states[:, :n]), axis=0) <= 3e-3 * scale + 1e-8)
    # rates: the flange contact switching on and off is followed only to O(dt); measured
    # at most 4 % of a DOF's peak rate (W4.y) at dt = 0.005 s, 0.4 % at dt = 0.00125 s
    rate_scale = np.max(np.abs(states[:, n:]), axis=0)
    assert np.all(np.max(np.abs(result.q_dot - states[:, n:]), axis=0) <= 0.08 * rate_scale + 1e-6)


def test_continuous_rhs_is_the_simulated_system(steered, track):
    """A cheap check of ``continuous_rhs`` against the march: from rest on the straight
    it is 0; at d1 = 140 m, with both front axles flanging and the creep saturated, its
    value matches the march's own slope over a 3 microsecond step (and differs from the
    right-hand side without flange contact or without saturation)."""
    rhs = continuous_rhs(steered, track)
    assert np.all(rhs(0.5, np.zeros(2 * steered.n)) == 0.0)
    result = simulate(steered, track, end=150.0, progress=False)
    k = int(np.argmin(np.abs(result.distance - 140.0)))
    assert result.outputs["flange1"][k] > 0 and result.outputs["flange2"][k] > 0
    x = np.concatenate([result.q[k], result.q_dot[k]])
    fine = simulate(steered, track, start=result.distance[k], end=result.distance[k] + 1e-4,
                    dt=1e-7, initial_state=x, progress=False)
    slope = (np.concatenate([fine.q[-1], fine.q_dot[-1]]) - x) / fine.time[-1]
    expected = rhs(result.time[k], x)
    scale = np.abs(expected) + 1e-3 * np.max(np.abs(expected))
    assert np.max(np.abs(slope - expected) / scale) < 5e-3  # measured 5e-4
    for options in ({"flange": False}, {"saturation": False}):
        other = continuous_rhs(steered, track, **options)(result.time[k], x)
        assert np.max(np.abs(other - expected) / scale) > 1.0


def test_time_step_convergence(steered, track):
    runs = {dt: simulate(steered, track, end=150.0, dt=dt, progress=False) for dt in (0.01, 0.005, 0.0025, 0.000625)}
    reference = runs[0.000625]
    errors = {}
    for dt in (0.01, 0.005, 0.0025):
        stride = round(0.01 / dt)
        ref_stride = round(0.01 / 0.000625)
        a, b = runs[dt].q[::stride], reference.q[::ref_stride]
        assert a.shape == b.shape
        errors[dt] = float(np.max(np.abs(a - b)))
    assert errors[0.01] > errors[0.005] > errors[0.0025]
    assert errors[0.0025] < errors[0.01] / 5  # close to second order (Heun on the feedback)
    assert errors[0.005] < 1e-4 * np.max(np.abs(reference.q))
    peak = np.max(np.abs(reference.outputs["Y1"]))
    assert np.max(np.abs(runs[0.005].outputs["Y1"])) == pytest.approx(peak, rel=1e-3)


def test_output_is_deterministic(steered, track):
    a = simulate(steered, track, end=200.0, progress=False)
    b = simulate(steered, track, end=200.0, progress=False)
    np.testing.assert_array_equal(a.q, b.q)
    np.testing.assert_array_equal(a.q_dot, b.q_dot)
    assert a.outputs.keys() == b.outputs.keys()
    for name in a.outputs:
        np.testing.assert_array_equal(a.outputs[name], b.outputs[name])


def test_start_and_initial_state_continue_a_run(steered, track):
    """Stopping at a step and restarting from its state gives the same history."""
    whole = simulate(steered, track, end=200.0, progress=False)
    k = whole.time.size // 2  # d1 = 100 m, in the first transition
    rest = simulate(steered, track, start=whole.distance[k], end=200.0, progress=False,
                    initial_state=np.concatenate([whole.q[k], whole.q_dot[k]]))
    m = min(rest.time.size, whole.time.size - k)
    np.testing.assert_allclose(rest.q[:m], whole.q[k : k + m], rtol=0, atol=1e-9 * np.max(np.abs(whole.q)))
    np.testing.assert_allclose(rest.distance[:m], whole.distance[k : k + m])


# ---------------------------------------------------------------- irregularity


def _straight(amplitude, wavelength, length=600.0):
    return Track((Straight(length),), SinusoidIrregularity(amplitude, wavelength))


def test_linear_run_reproduces_the_frequency_response(steered):
    """Flange contact and saturation off: started on the steady-state response computed
    from A, B, Bd with each wheelset's irregularity delayed by its distance behind the
    leading one, the march stays on it (exact discretization, delays, rates)."""
    v = steered.speed
    amplitude, wavelength = 0.002, 25.0
    k = 2 * np.pi / wavelength
    omega = k * v
    inputs = list(steered.inputs)
    lead = max(w.station for w in steered.wheelsets)
    u = np.zeros(len(inputs), dtype=complex)
    for wheelset, name in zip(steered.wheelsets, steered.layout.irregularity):
        u[inputs.index(name)] = amplitude * np.exp(-1j * k * (lead - wheelset.station))
    a = steered.state_matrix(v)
    response = np.linalg.solve(1j * omega * np.eye(a.shape[0]) - a, steered.input_matrix(v) @ u + 1j * omega * (steered.input_rate_matrix(v) @ u))
    result = simulate(steered, _straight(amplitude, wavelength), end=300.0, flange=False, saturation=False,
                      initial_state=response.imag, progress=False)
    expected = np.imag(response[None, :] * np.exp(1j * omega * result.time)[:, None])
    n = steered.n
    w1 = steered.wheelsets[0]
    assert abs(response[w1.y]) > 2 * amplitude  # a resonant wavelength: a demanding case
    for states, target in ((result.q, expected[:, :n]), (result.q_dot, expected[:, n:])):
        scale = np.max(np.abs(target), axis=0)
        moving = scale > 1e-9 * scale.max()
        error = np.max(np.abs(states - target), axis=0)
        assert np.all(error[moving] <= 2e-3 * scale[moving])
        assert np.all(error[~moving] <= 1e-9 * scale.max())


def test_sinusoidal_irregularity_response_is_symmetric(steered):
    """Straight track, 2 mm / 40 m alignment, no flange contact, saturation on: after the
    start transient the response is periodic at v / wavelength with half-wave symmetry
    (x(t + T/2) = -x(t)), and the run with the irregularity reversed is its mirror."""
    amplitude, wavelength = 0.002, 40.0
    dt = 0.005
    track = _straight(amplitude, wavelength)
    result = simulate(steered, track, flange=False, dt=dt, progress=False)
    mirrored = simulate(steered, track.with_irregularity(SinusoidIrregularity(-amplitude, wavelength)), flange=False,
                        dt=dt, progress=False)
    np.testing.assert_allclose(mirrored.q, -result.q, rtol=0, atol=1e-12 * np.max(np.abs(result.q)))
    period = wavelength / steered.speed
    half = round(period / 2 / dt)
    assert half * dt == pytest.approx(period / 2)
    late = np.flatnonzero(result.distance > 300.0)
    late = late[late + half < result.time.size]
    y = result.q[:, steered.wheelsets[0].y]
    amplitude_y = np.max(np.abs(y[late]))
    assert 0.5 * amplitude < amplitude_y < 0.02  # bounded, not running away
    np.testing.assert_allclose(y[late + half], -y[late], atol=1e-3 * amplitude_y)
    q1 = result.outputs["Y1"][late]
    assert q1.max() == pytest.approx(-q1.min(), rel=1e-3)
    # the dominant frequency is the forcing frequency v / wavelength
    spectrum = np.abs(np.fft.rfft(y[late] - y[late].mean()))
    frequencies = np.fft.rfftfreq(late.size, dt)
    assert frequencies[np.argmax(spectrum)] == pytest.approx(1 / period, abs=1.5 / (late.size * dt))


# ---------------------------------------------------------------- files


@pytest.fixture(scope="module")
def short_run(steered, track):
    return simulate(steered, track, end=160.0, progress=False)


def test_save_csv_round_trips(short_run, tmp_path):
    path = tmp_path / "run.csv"
    short_run.save(path)
    with path.open(newline="") as handle:
        header = next(csv.reader(handle))
    columns = short_run.series()
    units = short_run.units()
    assert header == [column_name(name, units[name]) for name in columns]  # units in the header
    assert header[:2] == ["time_s", "d1_m"] and "W1.y_m" in header and "W1.y_dot_m_s" in header and "Y1_N" in header
    data = np.loadtxt(path, delimiter=",", skiprows=1)
    assert data.shape == (short_run.time.size, len(columns))
    for i, (name, values) in enumerate(columns.items()):
        np.testing.assert_allclose(data[:, i], values, rtol=1e-8, atol=0, err_msg=name)
    assert list(tmp_path.iterdir()) == [path]


def test_save_npz_and_mat_round_trip(short_run, tmp_path):
    from scipy.io import loadmat

    columns = short_run.series()
    short_run.save(tmp_path / "run.npz")
    short_run.save(tmp_path / "run.MAT")  # the suffix is case-insensitive
    with np.load(tmp_path / "run.npz") as stored:
        assert sorted(stored.files) == sorted(name.replace(".", "_") for name in columns)
        for name, values in columns.items():
            np.testing.assert_array_equal(stored[name.replace(".", "_")], values)
    mat = loadmat(tmp_path / "run.MAT")
    for name, values in columns.items():
        np.testing.assert_array_equal(np.ravel(mat[name.replace(".", "_")]), values)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["run.MAT", "run.npz"]


def test_save_refuses_an_unknown_suffix_without_writing(short_run, tmp_path):
    for name in ("run.txt", "run", "run.json"):
        with pytest.raises(ValueError, match="unknown result format"):
            short_run.save(tmp_path / name)
    assert list(tmp_path.iterdir()) == []


def test_save_is_all_or_nothing(short_run, tmp_path, monkeypatch):
    """A failure half-way through writing leaves the previous file intact and no
    temporary file behind."""
    path = tmp_path / "run.npz"
    short_run.save(path)
    before = path.read_bytes()

    def broken(handle):
        os.write(handle, b"partial")
        raise OSError(28, "disk full")

    monkeypatch.setattr(os, "fsync", broken)  # the output layer's flush to disk
    with pytest.raises(OutputError, match="disk full"):
        short_run.save(path)
    assert path.read_bytes() == before
    assert list(tmp_path.iterdir()) == [path]


def test_the_library_runs_at_the_tracks_speed_as_the_command_line_does(capsys):
    """Issue 35 item 1: ``express.simulate(vehicle, track)`` ran the Manchester car at its
    model's 198 km/h on R400, whose line speed is 95 km/h (6.6 m/s^2 of cant deficiency,
    no warning), where ``express simulate`` takes the track's speed.  Now the library
    takes the same speed and says where it came from; a given speed still wins."""
    import json

    from express.cli import main
    from express.numeric.statespace import load_vehicle
    from express.rail.track.named import named_track

    path = ROOT / "examples" / "manchester.toml"
    vehicle = load_vehicle(path)
    track, _ = named_track("R400")
    run = simulate(vehicle, track, progress=False)
    assert run.speed == track.speed and run.options["speed_from"] == "track"
    assert main(["simulate", str(path), "--track", "R400", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["speed"] == run.speed
    given = simulate(vehicle, track, speed=20.0, end=50.0, progress=False)
    assert given.speed == 20.0 and given.options["speed_from"] == "given"
