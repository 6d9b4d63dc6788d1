"""Steady-state curving (express.analysis.curving.steady): against the closed-form linear
solution of a two-axle bogie (Boocock 1969), the settled state of a time simulation, and
the statics of the wheel loads."""

from __future__ import annotations

import numpy as np
import pytest

from express.analysis.curving.steady import (
    MAX_UNBALANCED_ACCELERATION,
    CurveError,
    SteadyCurve,
    SteadyCurvingSolver,
    steady_curving,
)
from express.analysis.time.simulate import simulate
from express.numeric.statespace import load_vehicle
from express.rail.track import Curve, Straight, Track, Transition


@pytest.fixture(scope="module")
def bogie():
    return load_vehicle("tests/data/boocock_bogie.toml")


def boocock(p: dict, rho: float, deficiency: float) -> tuple[float, float, float, float]:
    """Lateral shifts and angles of attack of the two wheelsets of a free two-axle bogie in a
    steady curve with linear creep (Boocock 1969, "Steady-state motion of railway vehicles
    on curved track", J. Mech. Eng. Sci. 11: wheelsets guided by creep and conicity alone,
    no gravitational stiffness or spin), solved in closed form for a frame joined to each
    wheelset by a yaw stiffness ``kpsi = 2 kx b1^2`` and a lateral ``2 ky``; ``F`` the
    bogie's lateral load ``(mt + 2 mw) a``, ``a`` the cant deficiency.

    The equilibrium (track frame, curvature rho, wheelsets at x = +-a)::

        wheelset i:  2 f2 psi_i - 2 ky d_i - mw a = 0
                     -2 b f1 (Gamma y_i / r0 + b rho) - kpsi (psi_i + rho x_i - psi_T) = 0
        frame:       sum 2 ky d_i = mt a,   sum kpsi (psi_i + rho x_i - psi_T) + 2 ky d_i x_i = 0
        d_i = y_i + rho a^2 / 2 - y_T - psi_T x_i
    """
    a, b, f1, f2, gamma, r0 = (p[k] for k in ("a", "b", "f1", "f2", "Gamma", "r0"))
    ky, kpsi = p["ky"], 2 * p["kx"] * p["b1"] ** 2
    force = (p["mt"] + 2 * p["mw"]) * deficiency
    c = gamma * b * f1 * f2
    delta = 4 * a**2 * c * ky + 2 * c * kpsi + kpsi**2 * ky * r0
    psi_odd = -a * rho * kpsi**2 * ky * r0 / delta
    psi_even = force * (2 * a * gamma * b * f1 * kpsi * ky) / (4 * f2 * delta)
    psi_load = force * (4 * a**2 * c * ky + 2 * c * kpsi + kpsi**2 * ky * r0) / (4 * f2 * delta)
    y_even = -r0 * rho * (16 * a**2 * b**2 * c * f1 * f2 * ky + 8 * b**2 * c * f1 * f2 * kpsi
                          + 4 * a**2 * f2**2 * kpsi**2 * ky * r0 + 4 * b**2 * f1 * f2 * kpsi**2 * ky * r0) / (4 * c * delta)
    y_odd = -r0 * rho * (8 * a**3 * c * f2 * kpsi * ky + 4 * a * c * f2 * kpsi**2) / (4 * c * delta)
    y_load = -r0 * force * (2 * a**2 * c * kpsi * ky) / (4 * c * delta)
    y_load_odd = r0 * force * (a * gamma * b * f1 * kpsi**2 * ky) / (4 * c * delta)
    return (y_even + y_odd + y_load + y_load_odd, psi_odd + psi_load - psi_even,
            y_even - y_odd + y_load - y_load_odd, -psi_odd + psi_load + psi_even)


@pytest.mark.parametrize(("radius", "direction", "cant", "speed"),
                         [(500.0, "left", 0.0, 1e-3), (300.0, "right", 0.0, 1e-3), (800.0, "left", 0.1, 25.0),
                          (1500.0, "right", 0.05, 40.0)])
def test_linear_steady_state_is_boococks_closed_form(bogie, radius, direction, cant, speed):
    curve = SteadyCurve(radius, cant, direction)
    result = steady_curving(bogie, curve, speeds=speed, flange=False, saturation=False)[0]
    p = bogie.values
    deficiency = speed**2 * curve.curvature - p["g"] * curve.signed_cant / p["G"]  # the model's small-angle form
    expected = boocock(p, curve.curvature, deficiency)
    index = [bogie.dof_index(name) for name in ("W1.y", "W1.rz", "W2.y", "W2.rz")]
    # achieved: 9e-16 relative (one linear solve); y is 1.4-18 mm, psi 0.1-1 mrad
    np.testing.assert_allclose(result.q[index], expected, rtol=1e-13, atol=0)


def test_pure_rolling_without_yaw_stiffness(bogie):
    # kx -> 0: the wheelsets roll radially, y = -b r0 rho / Gamma, no angle of attack
    soft = bogie.with_values({"kx": 1e-3})
    curve = SteadyCurve(600.0, 0.0, "left")
    result = steady_curving(soft, curve, speeds=1e-3, flange=False, saturation=False)[0]
    p = soft.values
    assert result.q[soft.dof_index("W1.y")] == pytest.approx(-p["b"] * p["r0"] / (p["Gamma"] * 600.0), rel=1e-6)
    assert abs(result.q[soft.dof_index("W1.rz")]) < 1e-9


TRACK = Track((Straight(20.0), Transition(60.0), Curve(600.0, 600.0, "left", 0.150)))


@pytest.mark.parametrize(("model", "flanging"), [("examples/conventional.toml", 1.0),
                                                ("examples/forced-steering.toml", 0.0)])
def test_equals_the_settled_time_simulation_deadband(model, flanging):
    vehicle = load_vehicle(model)
    run = simulate(vehicle, TRACK, speed=30.0, end=650.0, progress=False)
    steady = steady_curving(vehicle, SteadyCurve(600.0, 0.150, "left"), speeds=30.0)[0]
    settling = np.max(np.abs(run.q[-200] - run.q[-1]))  # still moving by this much over the last 5 s
    # achieved 3-4e-7 m / rad, the run's own settling over its last 5 s; coordinates are ~7e-3
    assert settling < 1e-6
    np.testing.assert_allclose(steady.q, run.q[-1], rtol=0, atol=2 * settling)
    wheel = steady.wheel_rail.columns()
    # the outer (right) wheel of the leading wheelset flanges unless the wheelsets are steered
    assert wheel["flanging1R"][0] == flanging
    assert wheel["YQ1R"][0] > 0


@pytest.mark.slow
def test_equals_the_settled_time_simulation_tables():
    vehicle = load_vehicle("examples/manchester-s1002.toml")
    run = simulate(vehicle, TRACK, speed=30.0, end=650.0, progress=False)
    steady = steady_curving(vehicle, SteadyCurve(600.0, 0.150, "left"), speeds=30.0)[0]
    assert steady.contact.startswith("tables")
    # achieved 6e-9 against the run's own settling of 1e-8 over its last 5 s
    np.testing.assert_allclose(steady.q, run.q[-1], rtol=0, atol=3e-8)


def test_wheel_loads_close_the_statics():
    vehicle = load_vehicle("examples/conventional.toml")
    result = steady_curving(vehicle, SteadyCurve(400.0, 0.105, "right"), speeds=120 / 3.6)[0]
    out = result.wheel_rail
    mass = sum(vehicle.values[k] * n for k, n in (("mc", 1), ("mt", 2), ("mw", 4)))
    g, base = vehicle.values["g"], vehicle.values["G"]
    sin_phi = 0.105 / base
    normal = g * np.sqrt(1 - sin_phi**2) + (120 / 3.6) ** 2 / 400.0 * sin_phi
    assert out.vertical_load.sum() == pytest.approx(mass * normal, rel=1e-13)
    # a right curve with cant deficiency: the outer (left) wheels carry more
    assert np.all(out.vertical_load[0, :, 0] > out.vertical_load[0, :, 1])


def test_sweep_continues_and_matches_single_solutions():
    vehicle = load_vehicle("examples/conventional.toml")
    curves = [SteadyCurve(r, 0.105, "right") for r in (2000.0, 1000.0, 600.0, 400.0)]
    sweep = steady_curving(vehicle, curves, speeds=25.0)
    single = steady_curving(vehicle, curves[-1], speeds=25.0)[0]
    np.testing.assert_allclose(sweep[-1].q, single.q, rtol=0, atol=1e-10)
    assert [s.curve.radius for s in sweep] == [2000.0, 1000.0, 600.0, 400.0]


@pytest.mark.parametrize(("curve", "speed", "match"), [
    (SteadyCurve(0.0, 0.1), 30.0, "radius"),
    (SteadyCurve(-300.0, 0.1), 30.0, "radius"),
    (SteadyCurve(400.0, 1.2), 30.0, "cant base"),
    (SteadyCurve(300.0, 0.0), 40.0, "unbalanced acceleration"),
    (SteadyCurve(400.0, 0.0, "up"), 30.0, "direction"),
])
def test_bad_curves_are_refused(curve, speed, match):
    vehicle = load_vehicle("examples/conventional.toml")
    with pytest.raises(CurveError, match=match):
        SteadyCurvingSolver(vehicle, speed).solve(curve)


def test_unbalanced_limit_is_documented_value():
    assert MAX_UNBALANCED_ACCELERATION == 2.0
    curve = SteadyCurve(1000.0, 0.150, "right")
    assert curve.unbalanced_acceleration(160 / 3.6, 1.5, 9.81) == pytest.approx(0.99, abs=0.01)


def test_demo_fig9_steady_state_matches_its_runs():
    from pathlib import Path

    from express.paper.demo import load_cars
    from express.paper.demo_curving import measure_curving

    curving = measure_curving(load_cars(Path("examples")), check=False)
    for name in ("steered", "conventional"):
        state = curving.steady_state[name]
        run_mean = curving.steady[f"psi_TW1_{name}"]
        # the run's mean over the car's stay in the 170 m circular curve: achieved 8e-5 (steered) and
        # 6e-5 (conventional) relative, the run's remaining settling
        assert state["psi_TW1"] == pytest.approx(run_mean, rel=3e-4)
        # the paper's curve at 120 km/h (1.9 m/s^2 of cant deficiency): the car bodies shift
        # outward on their suspension (the conventional one 131 mm from the chord, 34 mrad of
        # roll), unloading the inner wheels by 61 % of Q0, beyond EN 14363's 0.6
        assert state["dQQ0"] > 0.6 and state["passed"] == 0.0


@pytest.mark.slow
def test_a_contact_jump_is_settled_by_the_march():
    # S1002/60E1 at R = 357 m: the iteration stalls at a jump of the contact (residual 2e-4); the time march
    # from there settles to the equilibrium, whose residual is then at rounding level
    vehicle = load_vehicle("examples/manchester-s1002.toml")
    curve = SteadyCurve(357.143, 0.150, "right")
    speed = curve.speed_for(0.5, 1.5, 9.81)
    steady = SteadyCurvingSolver(vehicle, speed).solve(curve)
    assert steady.residual < 1e-12  # achieved 1.7e-15
    track = Track((Straight(20.0), Transition(60.0), Curve(900.0, 357.143, "right", 0.150)))
    run = simulate(vehicle, track, speed=speed, end=950.0, progress=False)
    # achieved 1e-11 m: the run and the steady state are the same fixed point
    np.testing.assert_allclose(steady.q, run.q[-1], rtol=0, atol=1e-9)


def test_the_bogie_yaw_stiffness_raises_the_leading_wheels_y_over_q_in_a_tight_curve():
    """Issue 31: the secondary yaw stiffness resists the bogie's turn in a curve, so the
    leading wheelset's angle of attack and Y/Q grow with it.  Before the rotational element
    got its curvature term, Y/Q of the S1002 car at R 250 m fell from 0.409 to 0.376 as kb2
    went from 0 to 1 MN m/rad; now it rises, to 0.532 at 0.5 MN m/rad (regression guards
    of this run with the table law: 0.4045 and 0.5318, asserted to 1e-3; FASTSIM gave
    0.4046 and 0.5302). In this tight curve the car is in
    two-point contact: the iteration stalls (residual 0.08-0.3) and the time march settles
    the state (residual 1e-14). At 1 MN m/rad (0.6209 on the machine of 2026-12-02) the
    march now ends 0.4 mm beyond the contact table on this one (2026-12-03): that stiffness
    is left out of the guard."""
    vehicle = load_vehicle("examples/manchester-s1002.toml")
    curve = SteadyCurve(250.0, 0.150, "right")
    speed = 75 / 3.6
    soft, stiff = (SteadyCurvingSolver(vehicle.with_values({"kb2": k}), speed).solve(curve) for k in (1.0, 5e5))
    soft_yq, stiff_yq = (state.columns()["YQ1L"] for state in (soft, stiff))
    assert soft_yq == pytest.approx(0.4045, abs=1e-3) and stiff_yq == pytest.approx(0.5318, abs=1e-3)
    assert stiff.columns()["aoa1"] > soft.columns()["aoa1"]


@pytest.mark.slow
@pytest.mark.parametrize(("speed_kmh", "radius", "law", "stable"), [
    (95.0, 400.0, "table", True), (260.0, 3000.0, "table", True), (260.0, 3000.0, "fastsim", False)])
def test_every_equilibrium_says_whether_it_is_stable_as_the_time_run_finds(speed_kmh, radius, law, stable):
    """Issue 32 item 5: the S1002 car's steady state carries the largest real part of the
    eigenvalues of its equations linearised there (-0.46 1/s in R 400 m at 95 km/h; in
    R 3000 m at 260 km/h, above the nonlinear critical speed of 172 km/h and below the
    linear one of 284, -0.29 1/s with the default table law and +0.76 1/s with FASTSIM);
    a time run started at it with 10 um on the leading wheelset settles back (stable) or
    moves away (unstable): over 4 s its distance from the state shrinks below half, or
    grows beyond twice.  (With the table law the equilibrium turns unstable from 264 km/h,
    +0.49 1/s at 268, by a mode this start barely excites: the run's distance still falls
    to 0.36 of it in 4 s; not used here.)"""
    vehicle = load_vehicle("examples/manchester-s1002.toml")
    curve = SteadyCurve(radius, 0.150 if radius < 1000 else 0.100, "right")
    speed = speed_kmh / 3.6
    steady = SteadyCurvingSolver(vehicle, speed, creep_law=law).solve(curve)
    assert steady.stable is stable and (steady.growth < -0.1 if stable else steady.growth > 0.1)
    start = steady.state.copy()
    start[vehicle.wheelsets[0].y] += 1e-5
    stations = [w.station for w in vehicle.wheelsets]
    length = max(stations) - min(stations) + 1.0
    track = Track((Curve(2 * length + speed * 4.0, radius, "right", curve.cant),))
    run = simulate(vehicle, track, speed=speed, start=length, end=length + speed * 4.0, initial_state=start,
                   progress=False, creep_law=law)
    away = np.max(np.abs(run.q - steady.q), axis=1)
    quarter = away.size // 4
    early, late = away[:quarter].max(), away[-quarter:].max()
    assert (late < 0.5 * early) if stable else (late > 2.0 * early)
