"""Simulation with the contact tables (express.analysis.time.contact_march through
express.analysis.time.simulate.simulate).

* Linear limit: with smooth profiles (a circular tread on the 60E1 crown), rigid rails
  and a tiny disturbance the contact run equals the linear model's run: the fed-back
  difference between the contact forces and the model's linear wheel/rail terms vanishes
  to second order.
* Reference: scipy's LSODA on the same equations (contact_rhs) agrees with the march.
* Outputs and options.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from express.analysis.time.contact_march import contact_rhs
from express.forces.contact import linear_coefficients
from express.analysis.time.simulate import simulate
from express.io.toml_model import parse_toml_model
from express.numeric.statespace import vehicle_model
from express.rail.contact_forces import quasi_static_forces
from express.rail.profile_contact import wheelset_contacts
from express.rail.track import Curve, Straight, Track, Transition
from test_contact_geometry import arc_wheel
from test_profile_contact import WHEELSET

TRACK = Track((Straight(5000.0),))
ROOT = Path(__file__).resolve().parents[1]


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
    assert contact.options["contact"] == "tables (table)" and "contact" not in linear.options
    scale = np.abs(linear.q).max(axis=0)
    # 1.6e-3 of the motion with the table law (its excess over Kalker's slopes is O(u^2)), less with FASTSIM
    assert np.abs(contact.q - linear.q).max(axis=0) == pytest.approx(0, abs=2e-3 * scale.max())
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
    names = [f"{prefix}1{side}" for prefix in ("Q", "Y", "YQ", "Fx", "u", "gamma", "flanging") for side in "LR"]
    for name in [*names, "SY1", "aoa1", "dQQ0"]:
        assert run.outputs[name].shape == run.time.shape
    for name in ("Y1", "YQ1", "Ytot1", "flange1", "dy1", "NL1"):  # the dead-band model's, or gone
        assert name not in run.outputs
    o = run.outputs
    assert o["Y1L"][0] < -30e3 and o["flanging1L"][0] == 1.0 and o["flanging1R"][0] == 0.0  # the left rail pushes back
    assert o["YQ1L"][0] == pytest.approx(-o["Y1L"][0] / o["Q1L"][0])
    assert o["SY1"][0] == pytest.approx(o["Y1L"][0] + o["Y1R"][0])
    # the contact on the rail, from the centred wheelset's contact point: on the flange of S1002/60E1,
    # about 30 mm toward the gauge corner (the rail's give under the flange force: tests/test_contact_tables.py)
    assert -0.036 < o["u1L"][0] < -0.024 and abs(o["u1R"][0]) < 0.01
    units = run.units()
    assert (units["Q1L"], units["Y1L"], units["YQ1L"], units["gamma1L"], units["u1L"], units["SY1"]) == (
        "N", "N", "", "rad", "m", "N")
    assert run.options["wheel_loads"] == "quasi-static estimate"
    assert run.wheel_rail is not None and run.wheel_rail.loads == "quasi-static estimate"
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


def test_energy_outputs_of_a_run(s1002):
    """Tgamma, the USFD wear rate and Burstow's index of every wheel (docs/wear.md) are
    columns of a contact-tables run, with units: the flanging wheel dissipates more
    than the other; the wear and RCF columns are the functions of the recorded Tgamma and
    patch area (bit for bit); the dead-band run has none."""
    from express.rail.contact_forces import OUTPUTS
    from express.rail.wear import burstow_damage, wear_rate_of_contact

    state = np.zeros(s1002.form.size)
    state[0] = 9e-3
    run = simulate(s1002, TRACK, speed=50.0, dt=0.005, end=50.0, initial_state=state, progress=False)
    o, units = run.outputs, run.units()
    assert (units["Tgamma1L"], units["wear1L"], units["rcf1R"]) == ("N", "ug/m/mm^2", "")
    # on the flange 136 N, the other on its tread 109 N (the table law; FASTSIM 153 and 86 N)
    assert o["Tgamma1L"][0] > 1.2 * o["Tgamma1R"][0] > 0.0
    w = run.wheel_rail
    assert w is not None and w.frictional_power is not None
    assert np.array_equal(o["Tgamma1L"], w.frictional_power[:, 0, 0])
    assert np.array_equal(o["rcf1L"], burstow_damage(o["Tgamma1L"]))
    assert np.all((w.patch_area > 1e-6) & (w.patch_area < 1e-3))  # 1 to 1000 mm^2
    assert np.array_equal(o["wear1R"], wear_rate_of_contact(o["Tgamma1R"], w.patch_area[:, 0, 1]))
    assert len(OUTPUTS) == len(set(OUTPUTS))
    # the wear across the profile holds the wear rate's mass (rate x A x distance), to 1e-12
    from express.rail.wear_profile import WHEEL_STEEL_DENSITY, rolled_per_instant

    rolled = rolled_per_instant(run.distance)
    edges = np.linspace(-0.06, 0.04, 201)
    depth = w.wheel_wear_depth(rolled, edges, radius=0.46)
    mass = np.sum(depth * np.diff(edges), axis=-1) * 2 * math.pi * 0.46 * WHEEL_STEEL_DENSITY  # (n, 2)
    rate = wear_rate_of_contact(w.frictional_power, w.patch_area) * w.patch_area * 1e6
    assert mass == pytest.approx(np.einsum("k,kjs->js", rolled, rate) * 1e-9, rel=1e-12)
    assert w.wheel_position[0, 0, 0] < -0.02  # the flange: toward the wheel's inside
    dead = simulate(s1002, TRACK, speed=50.0, dt=0.005, end=50.0, initial_state=state, progress=False,
                    contact="deadband")
    assert not [name for name in dead.outputs if name.startswith(("Tgamma", "wear", "rcf"))]


def test_linear_coefficients_follow_the_speed(s1002):
    slow, fast = linear_coefficients(s1002, 20.0), linear_coefficients(s1002, 40.0)
    assert slow[0, 2] == pytest.approx(2 * fast[0, 2])  # C ~ 1/v
    assert slow[0, 0] == fast[0, 0]
    assert slow[0, 0] == pytest.approx(1e6 * 0 + s1002.values["Gamma_e_ky"])


def test_forces_on_straight_centred_track_stay_at_their_steady_values(s1002):
    """No sign chatter: on straight, centred, irregularity-free track each wheel's forces
    are the centred contact's, at every step.  (The ±248 N of issue 22 came from picking
    "the flanging wheel" as the one with the larger contact angle: centred, both angles
    are equal to rounding, W1.y ~ 1e-17 m picked either wheel, and the tread's lateral
    forces of the two wheels are opposite.  The outputs are per wheel now.)"""
    run = simulate(s1002, TRACK, speed=50.0, dt=0.005, end=100.0, progress=False)
    contact = wheelset_contacts(s1002.model, s1002.values, s1002.wheelsets)[0]
    centred = quasi_static_forces(contact, 0.0, speed=50.0, law="table")
    o = run.outputs
    for side, name in (("L", "left"), ("R", "right")):
        # achieved: constant to 1e-11 N, the centred value to 1e-11 N (forces ~250 N)
        assert np.ptp(o[f"Y1{side}"]) < 1e-6
        np.testing.assert_allclose(o[f"Y1{side}"], centred[f"Y_{name}"], rtol=0, atol=1e-6)
        np.testing.assert_allclose(o[f"Q1{side}"], contact.wheel_load, rtol=0, atol=1e-6)
        assert not o[f"flanging1{side}"].any()
    assert abs(centred["Y_left"]) > 100.0  # the tread's contact angle: a real, opposite force on each wheel
    assert np.sign(o["Y1L"]).min() == np.sign(o["Y1L"]).max() == -np.sign(o["Y1R"]).max()
    np.testing.assert_allclose(o["SY1"], 0.0, atol=1e-6)


CURVE = Track((Straight(20.0), Transition(60.0), Curve(600.0, 600.0, "left", 0.150)))


@pytest.fixture(scope="module")
def manchester():
    from express.io import load_model

    return vehicle_model(load_model(ROOT / "examples" / "manchester-s1002.toml"))


@pytest.fixture(scope="module")
def lateral_car():
    """``examples/conventional.toml`` on standard gauge with S1002/60E1 (the contact
    benchmark's car): a lateral-only model with the contact tables."""
    import sys

    sys.path.insert(0, str(ROOT / "benchmarks"))
    from bench_contact_sim import standard_gauge_car

    return vehicle_model(standard_gauge_car())


@pytest.mark.parametrize("speed", [30.0, 10.0])
def test_wheel_loads_close_the_statics_of_a_canted_curve(lateral_car, speed):
    """A lateral-only model, settled in a canted curve (R 600 m, 150 mm): each wheelset's
    loads carry the normal load and the roll moment of the vehicle as rigid masses on
    their wheelsets (load_transfer's statics written out here):
    ``Q_L + Q_R = 2 Q0 + (a_n - g) sum s m``, ``Q_L - Q_R = sum s m (a_y h + a_n y) / b0``
    (y the bodies' lateral displacements from the track centre line under their wheelsets,
    the coordinate less the chord ``rho / 2 sum s (x_j - x)**2``, the wheelsets' own
    excepted); cant deficiency (30 m/s) loads the outer (right) wheel, cant excess
    (10 m/s) the inner one."""
    from express.model.parameters import expression_value
    from express.rail.load_transfer import body_loads

    vehicle = lateral_car
    run = simulate(vehicle, CURVE, speed=speed, end=650.0, progress=False)
    assert run.options["wheel_loads"] == "quasi-static estimate"
    rail = vehicle.model.rail
    g, base = (expression_value(getattr(rail, name), vehicle.values) for name in ("gravity", "cant_base"))
    sin_phi = 0.150 / base
    cos_phi = math.sqrt(1 - sin_phi**2)
    a_y = g * sin_phi - speed**2 / 600.0 * cos_phi
    a_n = g * cos_phi + speed**2 / 600.0 * sin_phi
    body = body_loads(vehicle.model, vehicle.values, [w.b for w in vehicle.wheelsets])
    wheelsets = {w.name for w in vehicle.wheelsets}
    y = np.array([run.q[-1, vehicle.dof_index(f"{b}.y")] if f"{b}.y" in vehicle.dofs and b not in wheelsets else 0.0
                  for b in body.bodies])
    station = np.array([expression_value(vehicle.model.body(b).position[0], vehicle.values) for b in body.bodies])
    under = station[[body.bodies.index(w.name) for w in vehicle.wheelsets]]
    y -= np.array([sum(s * (x - xi) ** 2 for s, x in zip(row, under, strict=True)) for row, xi in
                   zip(body.shares, station, strict=True)]) / (2 * 600.0)  # the chord in R 600 m
    weights = body.mass[:, None] * body.shares
    total = 2 * np.array([w.wheel_load for w in vehicle.wheelsets]) + (a_n - g) * weights.sum(axis=0)
    difference = ((a_y * body.height + a_n * y) @ weights) / body.half_base
    out = run.wheel_rail
    left, right = out.vertical_load[-1, :, 0], out.vertical_load[-1, :, 1]
    # achieved: to rounding (1e-9 N) against loads of 50 kN
    np.testing.assert_allclose(left + right, total, rtol=1e-12)
    np.testing.assert_allclose(left - right, difference, rtol=1e-9, atol=1e-6)
    outer_heavier = speed == 30.0
    assert np.all((right > left) == outer_heavier)
    assert abs(difference).min() > 1e3  # a real transfer: kilonewtons


def test_wheel_loads_of_a_3d_model_come_from_its_vertical_contact_springs(manchester):
    """A model whose wheels stand on vertical springs (kH between wheel and rail) gets its
    wheel loads from them: raising the leading wheelset by 2 um and rolling it by 2 urad
    (left wheel up) unloads its wheels by kH (dz +- lever droll), to rounding, where
    ``lever = l - r tan(delta)`` is where the centred contact's normal meets the axle (the
    wheel's contact point moves up by ``l droll`` and across by ``r droll``, which its
    rail's slope turns into ``r tan(delta) droll`` of rise: docs/contact.md, "Dynamic wheel
    loads"); the springs' own lever ``b`` is 8 mm longer."""
    from express.rail.contact_tables import ANGLE, ARM, RADIUS
    from express.rail.profile_contact import wheelset_contacts

    vehicle = manchester
    k_h, load = (vehicle.values[name] for name in ("kH", "P0"))
    tables = wheelset_contacts(vehicle.model, vehicle.values, vehicle.wheelsets)[0].tables
    lever = [np.interp(0.0, tables.y, tables.data[ARM, side])
             - np.interp(0.0, tables.y, tables.data[RADIUS, side]) * math.tan(np.interp(0.0, tables.y, tables.data[ANGLE, side]))
             for side in (0, 1)]
    state = np.zeros(vehicle.form.size)
    state[vehicle.dof_index("W1.z")] = 2e-6
    state[vehicle.dof_index("W1.rx")] = 2e-6
    run = simulate(vehicle, TRACK, speed=30.0, dt=0.001, end=0.5, initial_state=state, progress=False)
    assert run.options["wheel_loads"] == "dynamic"
    q = run.wheel_rail.vertical_load[0, 0]
    np.testing.assert_allclose(q, [load - k_h * (2e-6 + lever[0] * 2e-6), load - k_h * (2e-6 - lever[1] * 2e-6)],
                               rtol=1e-12)
    assert np.all(run.wheel_rail.vertical_load[0, 1:] == load)  # the others at rest
    assert np.ptp(run.wheel_rail.vertical_load[:, 0, 0]) > 1e3  # and the loads follow the motion


def test_the_dampers_under_the_wheels_carry_load(manchester):
    """The contact dampers' share of the wheel load, ``-c_z`` times the deflection's rate
    (:func:`express.forces.contact.dynamic_wheel_loads`): the leading wheelset released
    centred with a vertical velocity of 1 mm/s and a roll rate of 2 mrad/s (left wheel
    up) starts with ``Q0 - cH (dz' +- b droll')``, ``b`` the wheel points' lateral
    offset read from the model, to rounding (achieved 1e-16 relative, asserted 1e-12);
    the stiffness alone would leave both loads at Q0."""
    from express.model.parameters import expression_value

    vehicle = manchester
    c_h, load = (vehicle.values[name] for name in ("cH", "P0"))
    b = [abs(expression_value(vehicle.model.point(point).offset[1], vehicle.values)) for point in ("T1_FL_wheel", "T1_FR_wheel")]
    velocity = {int(i): vehicle.n + j for j, i in enumerate(vehicle.form.massive)}
    state = np.zeros(vehicle.form.size)
    state[velocity[vehicle.dof_index("W1.z")]] = 1e-3
    state[velocity[vehicle.dof_index("W1.rx")]] = 2e-3
    run = simulate(vehicle, TRACK, speed=30.0, dt=0.001, end=0.01, initial_state=state, progress=False)
    q = run.wheel_rail.vertical_load[0, 0]
    np.testing.assert_allclose(q, [load - c_h * (1e-3 + b[0] * 2e-3), load - c_h * (1e-3 - b[1] * 2e-3)], rtol=1e-12)
    assert abs(q[0] - load) > 100.0  # the share is not rounding


def _curve_statics(vehicle, run, speed: float, radius: float = 600.0, cant: float = 0.150):
    """The roll moments of a vehicle settled in a constant canted curve (free body,
    docs/curving.md "Statics of a canted curve"), in the frame of the track's tangent at
    the vehicle's origin, where a point at station ``x`` on the track centre lies
    ``rho x**2 / 2`` to the inside.

    Returns ``(contact, rigid, estimate)`` per wheelset: the moment of the rails' forces
    about the wheelset's own track centre line at rail level, ``y (Q_L + Q_R) + Mx - h_w Y``
    (``Mx`` the contact's roll moment about the wheelset centre, from the contact at the
    settled state and loads); the rigid-vehicle estimate ``sum s m a_y h``; and that plus
    the suspension's roll, ``sum s m (a_y h + a_n e)`` with ``e`` each body's offset from
    the track centre under its wheelsets (the lever rule's shares ``s``)."""
    from express.model.parameters import expression_value
    from express.rail.load_transfer import body_loads

    model, values = vehicle.model, vehicle.values
    g, base = (expression_value(getattr(model.rail, name), values) for name in ("gravity", "cant_base"))
    rho, sin_phi = 1.0 / radius, cant / base
    a_y = g * sin_phi - speed**2 * rho  # the model's cant forcing -m (v^2 rho - g S / G)
    a_n = g * math.sqrt(1 - sin_phi**2) + speed**2 * rho * sin_phi
    body = body_loads(model, values, [w.b for w in vehicle.wheelsets])
    station = np.array([expression_value(model.body(b).position[0], values) for b in body.bodies])
    y = np.array([run.q[-1, vehicle.dof_index(f"{b}.y")] if f"{b}.y" in vehicle.dofs else 0.0 for b in body.bodies])
    inside = rho * station**2 / 2
    under = inside[[body.bodies.index(w.name) for w in vehicle.wheelsets]]
    offset = inside + y - body.shares @ under
    weights = body.mass[:, None] * body.shares
    rigid = (a_y * body.height) @ weights
    estimate = (a_y * body.height + a_n * offset) @ weights
    contacts = wheelset_contacts(model, values, vehicle.wheelsets)
    loads = run.wheel_rail.vertical_load[-1]
    contact = np.zeros(len(vehicle.wheelsets))
    for j, w in enumerate(vehicle.wheelsets):
        forces = quasi_static_forces(contacts[j], run.q[-1, w.y], run.q[-1, w.psi], rho=rho, speed=speed, law="table",
                                     loads=tuple(loads[j]))
        np.testing.assert_allclose(forces["Y_left"], run.wheel_rail.lateral_force[-1, j, 0], rtol=1e-6)  # the march's
        height = body.height[body.bodies.index(w.name)]
        contact[j] = run.q[-1, w.y] * loads[j].sum() + forces["Mx"] - height * forces["Y"]
    return contact, rigid, estimate


@pytest.mark.parametrize("speed", [30.0, 10.0])
def test_the_statics_of_a_canted_curve_close(manchester, speed):
    """The 3-D model settled in the canted curve (R 600 m, 150 mm): a free body.

    * the vehicle's loads sum to the load normal to the track plane ``8 Q0 a_n / g`` (to
      rounding), each bogie's to its half (achieved 1.1e-5, asserted 2e-5) and each
      wheelset's to its quarter within 0.15 % (achieved 0.10 %): the leading wheelsets,
      further out, climb higher on their rails (0.40 mm against 0.06 mm at 30 m/s, the
      wheels' rise, docs/contact.md) and take more load through the pitched frame
      (before the rise was in the loads, each wheelset's quarter to rounding); cant
      deficiency loads the outer wheel, cant excess the inner one;
    * vehicle: the rails' roll moment equals that of the masses' lateral and normal
      loads at their true positions (rigid estimate plus the suspension's roll); achieved
      0.37 % (30 m/s) and 0.11 % (10 m/s) of the rigid estimate (tolerance 0.5 %), the
      rest the linear model's weights m g where the track presses with m a_n on the
      bodies' offsets;
    * bogie: its wheelsets carry its lever-rule share; achieved 0.74 % (tolerance 0.8 %;
      0.61 % before the wheels' rise was in the loads);
    * wheelset: within a bogie the moment divides with the lateral forces, at the primary
      suspension's height h1, and with the couple of the load from above (N, on the
      primary springs) on the wheelsets' own lateral shifts; achieved 5.7 % (tolerance
      6 %; 4.8 % at 10 m/s; 1.51 % before the wheels' rise on their rails was in the loads, 1.15 % before
      the secondary yaw element was turned by the curve, issue 31): the rule leaves out
      the bogie's yaw moment, which the wheelsets react, and that a wheel near its flange
      resists roll with its load's own lever (where its contact normal meets the axle,
      0.50 m on the leading wheelset's outer wheel at 30 m/s, against the springs' 0.75 m;
      docs/contact.md, "Dynamic wheel loads"), which moves moment to the trailing one;
    * the suspension's roll is real: it adds 42-43 % (30 m/s) and 29-30 % (10 m/s) to
      the rigid estimate (asserted: more than 25 %).
    """
    from express.model.parameters import expression_value
    from express.model.topology import classify_bodies

    vehicle = manchester
    run = simulate(vehicle, CURVE, speed=speed, end=650.0, progress=False)
    assert run.options["wheel_loads"] == "dynamic"
    rail = vehicle.model.rail
    g, base = (expression_value(getattr(rail, name), vehicle.values) for name in ("gravity", "cant_base"))
    sin_phi = 0.150 / base
    a_n = g * math.sqrt(1 - sin_phi**2) + speed**2 / 600.0 * sin_phi
    loads = run.wheel_rail.vertical_load[-1]
    quarter = 2 * run.wheel_rail.static_load * a_n / g
    assert loads.sum() == pytest.approx(quarter.sum(), rel=1e-9)
    np.testing.assert_allclose(loads[:2].sum(), quarter[:2].sum(), rtol=2e-5)
    np.testing.assert_allclose(loads.sum(axis=1), quarter, rtol=1.5e-3)
    assert loads[0].sum() > quarter[0] and loads[2].sum() > quarter[2]  # the leading wheelsets
    assert np.all((loads[:, 1] > loads[:, 0]) == (speed == 30.0))

    contact, rigid, estimate = _curve_statics(vehicle, run, speed)
    scale = abs(rigid.sum())
    assert abs(contact.sum() - estimate.sum()) < 0.005 * scale
    assert np.all(abs(estimate - rigid) > 0.25 * abs(rigid))  # the suspension's roll
    bogie_of = classify_bodies(vehicle.model).bogie_of
    groups: dict[str, list[int]] = {}
    for j, w in enumerate(vehicle.wheelsets):
        groups.setdefault(bogie_of[w.name], []).append(j)
    h1, mass = vehicle.values["h1"], vehicle.values["mw"]
    lateral = run.wheel_rail.lateral_force[-1].sum(axis=1)
    for members in groups.values():
        assert abs(contact[members].sum() - estimate[members].sum()) < 0.008 * abs(estimate[members].sum())
        shift = np.array([run.q[-1, vehicle.wheelsets[j].y] for j in members])
        from_above = loads[members].sum(axis=1) - mass * a_n
        split = (estimate[members] - h1 * (lateral[members] - lateral[members].mean())
                 + from_above * (shift - shift.mean()))
        np.testing.assert_allclose(contact[members], split, rtol=0.06)


def _on_its_rails(vehicle, y: float) -> tuple[float, float]:
    """Height and roll of the leading wheelset displaced by ``y`` on its rails (the wheels
    neither pressed into them nor lifted: both wheels' interpenetration beyond the static
    one zero, :func:`express.rail.wheel_rise.contact_rise`)."""
    from express.analysis.time.force_elements import contact_tables_of
    from express.rail.wheel_rise import contact_rise

    out = np.zeros((2, 2))
    contact_rise(contact_tables_of(vehicle, None, "fastsim"), 0, y, 0.0, out)
    (h_left, lever_left), (h_right, lever_right) = out
    roll = (h_left - h_right) / (lever_left + lever_right)
    return h_left - lever_left * roll, roll


def test_the_contact_rolls_a_3d_wheelset(manchester):
    """On straight track, a leading wheelset pushed onto its left flange: the flange force
    at rail level rolls the wheelset onto the flanging wheel (its roll moment ``r Y`` is fed
    back on the roll coordinate), so the left wheel's load rises above the right's; with no
    roll feedback both would stay at Q0 (the track is level)."""
    vehicle = manchester
    state = np.zeros(vehicle.form.size)
    state[vehicle.wheelsets[0].y] = 8e-3
    state[vehicle.dof_index("W1.z")], state[vehicle.dof_index("W1.rx")] = _on_its_rails(vehicle, 8e-3)
    run = simulate(vehicle, TRACK, speed=30.0, dt=0.001, end=3.0, initial_state=state, progress=False)
    out = run.wheel_rail
    assert out.flange_contact[1, 0, 0]  # on the left flange
    record = run.outputs
    assert record["Y1L"][1] < -10e3
    # achieved: 10.5 kN and 27.7 kN more on the left wheel 1 and 2 ms in, while on the flange
    assert np.all(record["Q1L"][1:3] - record["Q1R"][1:3] > 5e3)


def _unloading_and_forces(vehicle, dt: float) -> np.ndarray:
    from express.analysis.curving.assessment import assess_run
    from express.rail.track import load_track

    track = load_track("R400")
    run = simulate(vehicle, track, speed=95 / 3.6, dt=dt, progress=False)
    _, assessment = assess_run(vehicle, track, run)
    found = {c.name: c.value for c in assessment.criteria}
    return np.array([found["dQQ0"], found["YQ1L"], found["SY1"]])


@pytest.mark.slow
def test_the_s1002_car_converges_in_the_step(manchester):
    """The stiffest bundled car (wheels on 1.2 GN/m contact springs, S1002 tables, dynamic
    loads) along R 400 m at 95 km/h: the EN 14363 quantities at the default 5 ms step
    against 0.625 ms — the largest wheel unloading, the leading wheel's (Y/Q)2m and its
    wheelset's (ΣY)2m — within 0.1 % (achieved 0.04 %, 0.02 %, 0.03 %; docs/contact.md,
    "Damp the contact springs"; a 0.3125 ms run moves them by 0.002 % more).  Without
    the contact springs' damping the 0.625 ms run unloaded the wheels 39 % more."""
    coarse, fine = _unloading_and_forces(manchester, 5e-3), _unloading_and_forces(manchester, 0.625e-3)
    np.testing.assert_allclose(coarse, fine, rtol=1e-3)
    assert 0.25 < fine[0] < 0.26  # regression guard: this run's ΔQ/Q0 (0.2524)


def test_a_run_on_undamped_contact_springs_is_warned(manchester):
    """Wheels on vertical contact springs without damping: one warning naming them (the
    wheelsets' vertical modes on them are undamped; docs/contact.md)."""
    bare = manchester.with_values({"cH": 0.0})
    with pytest.warns(UserWarning, match="FL_contact.*have no damping"):
        simulate(bare, TRACK, speed=30.0, dt=0.005, end=1.0, progress=False)
