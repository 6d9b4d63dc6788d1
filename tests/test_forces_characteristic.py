"""Nonlinear characteristics (issue 31, item 2; express.forces.characteristic): force against
deflection and against velocity as piecewise-linear tables and keyword shapes, read and
checked, seen by the linear analyses as their tangent at the static state, marched exactly.

Closed forms: a bilinear spring's static deflection under a load on either side of its
knee; a blow-off damper's energy per cycle at amplitude X and frequency w (the work of a
saturated damper) in a forced run, converged in the step; a one-sided contact with a
preload lifting off at ``U = P (k0 + k)/(k0 k)``.  The runs drive the march directly on
one-mass models (a spring ``k0`` to a ground ``W`` that moves, the input ``W.x``, and the
element to a fixed ground ``G``)."""

from __future__ import annotations

import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from express.analysis.time.integrator import march
from express.analysis.time.simulate import _dense_steps
from express.analysis.time.track_inputs import TrackInputs
from express.base.diagnostics import ModelError
from express.forces.characteristic import characteristic_elements_of
from express.forces.element import ForceSet
from express.io import parse_toml_model
from express.numeric.statespace import vehicle_model

ROOT = Path(__file__).resolve().parents[1]

MODEL = """
[model]
name = "table"
[parameters]
m = "{m}"
k0 = "{k0}"
c0 = "{c0}"
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
[elements.drive]
from = "M1"
to = "W1"
direction = "x"
stiffness = "k0"
damping = "c0"
[elements.part]
from = "M1"
to = "G1"
direction = "x"
characteristic = {characteristic}
"""
BILINEAR = '{ shape = "bilinear", stiffness = "40 * 1e3", knee = 0.005, beyond = "160 * 1e3", compression_knee = 0.002 }'


def _vehicle(characteristic: str, m: str = "100 kg", k0: str = "40 kN/m", c0: str = "2 kN*s/m"):
    text = MODEL.format(m=m, k0=k0, c0=c0, characteristic=characteristic)
    return vehicle_model(parse_toml_model(text, "table.toml"))


def _run(vehicle, u: np.ndarray, dt: float):
    """The march with the characteristic fed back; ``u`` the ground's motion (steps,)."""
    inputs_u = np.zeros((u.size, len(vehicle.inputs)))
    inputs_u[:, vehicle.inputs.index("W.x")] = u
    rate = np.gradient(inputs_u, dt, axis=0)
    empty = np.zeros((u.size, 0))
    inputs = TrackInputs(inputs_u, rate, empty, empty, empty)
    element = characteristic_elements_of(vehicle, inputs_u, rate)
    forces = ForceSet((element,), vehicle.form.size)
    linear = _dense_steps(vehicle, vehicle.state_matrix(1.0), 1.0, dt, inputs, forces.selector())
    states, history = march(linear, np.zeros(vehicle.form.size), forces)
    return states, element.outputs(states, history)["force_part"], element


def _ramp(t: np.ndarray, level: float, rise: float) -> np.ndarray:
    """A smooth step to ``level`` over ``rise`` seconds (then held)."""
    s = np.clip(t / rise, 0.0, 1.0)
    return level * s * s * (3 - 2 * s)


# ------------------------------------------------------------------ reading and the tangent


def test_the_linear_analyses_see_the_tangent_with_its_symbol():
    """K holds the bilinear spring's k1 (its symbol in the generated matrices), C the
    blow-off damper's c; a table's tangent is the slope through zero, the mean of the two
    slopes at a breakpoint there (the small-amplitude limit of a kink's describing function)."""
    from express.cli.common import linearisation

    text = MODEL.format(m="100 kg", k0="40 kN/m", c0="0", characteristic='{ shape = "bilinear", stiffness = "k1", '
                        'knee = "d1", beyond = "k2" }').replace('c0 = "0"', 'c0 = "0"\nk1 = "40 kN/m"\nk2 = "160 kN/m"\n'
                                                                  'd1 = "5 mm"')
    vehicle = vehicle_model(parse_toml_model(text, "table.toml"))
    assert vehicle.stiffness[0, 0] == pytest.approx(80e3, rel=1e-15)
    (term,) = vehicle.equations.element_terms
    assert term.kind == "characteristic" and str(term.values["tangent"]) == "k1"
    assert "deflection" in linearisation(vehicle)["part"]
    damper = _vehicle('{ shape = "blow-off", damping = "600 * 1e3", force = "12 * 1e3" }', c0="0")
    assert damper.damping(1.0)[0, 0] == pytest.approx(600e3, rel=1e-15)
    assert "velocity" in linearisation(damper)["part"]
    kinked = _vehicle('{ shape = "table", of = "deflection", deflection = [-10, 0, 10], force = [-1, 0, 3], '
                      'units = ["mm", "kN"] }', c0="0")
    assert kinked.stiffness[0, 0] == pytest.approx(40e3 + 0.5 * (100e3 + 300e3), rel=1e-12)


CSV = "# a damper measured\nvelocity [m/s], force [kN]\n-0.3, -3\n0, 0\n0.1, 2\n0.3, 3\n"


def test_a_table_from_a_csv_file_with_units(tmp_path):
    (tmp_path / "damper.csv").write_text(CSV)
    text = MODEL.format(m="100 kg", k0="40 kN/m", c0="0",
                        characteristic='{ shape = "table", of = "velocity", file = "damper.csv" }')
    vehicle = vehicle_model(parse_toml_model(text, str(tmp_path / "table.toml")))
    assert vehicle.damping(1.0)[0, 0] == pytest.approx(0.5 * (10e3 + 20e3), rel=1e-12)
    (term,) = vehicle.equations.element_terms
    assert [float(term.values[f"f{i}"]) for i in range(4)] == [-3e3, 0.0, 2e3, 3e3]


@pytest.mark.parametrize("characteristic, messages", [
    ('{ shape = "table", of = "velocity", velocity = [-1, 0, 1], force = [-1, 0.5, 2] }',
     ["table.toml:", "must pass through zero force at zero velocity"]),
    ('{ shape = "table", of = "deflection", deflection = [0, 2, 1], force = [0, 1, 2], units = ["mm", "kN/m"] }',
     ["the deflection values must increase: 1 after 2", 'force unit "kN/m" is not a force']),
    ('{ shape = "contact", stiffness = "1e6", gap = "-1" }', ["characteristic gap must be positive, got -1"]),
    ('{ shape = "contact", stiffness = "1e6", gap = "1", preload = "1" }', ["not both"]),
    ('{ shape = "blow-off", damping = "1e5" }', ["needs its blow-off velocity or its blow-off force"]),
    ('{ shape = "bilinear", stiffness = "1e5", knee = "0.01" }', ["a bilinear characteristic needs beyond"]),
    ('{ shape = "spline" }', ["characteristic shape must be one of"]),
    ('{ shape = "table", of = "deflection", deflection = [0, 1], force = [0, 1], units = ["s", "N"] }',
     ['deflection unit "s" is not a deflection']),
])
def test_bad_characteristics_are_refused_every_problem_at_once_with_the_line(characteristic, messages):
    text = MODEL.format(m="100 kg", k0="40 kN/m", c0="0", characteristic=characteristic)
    line = next(i for i, row in enumerate(text.splitlines(), 1) if row.startswith("characteristic"))
    with pytest.raises(ModelError) as error:
        parse_toml_model(text, "table.toml")
    problems = [str(p) for p in error.value.problems]
    for message in messages:
        assert any(p.startswith(f"table.toml:{line}:") and message in p for p in problems), problems


def test_a_bad_csv_table_names_its_own_file_and_lines_and_the_command_writes_nothing(tmp_path):
    (tmp_path / "damper.csv").write_text("velocity [m/s], force [kN]\n-1, -1\n0, 0\n0, 1\nfast, 2\n")
    path = tmp_path / "table.toml"
    path.write_text(MODEL.format(m="100 kg", k0="40 kN/m", c0="0",
                                 characteristic='{ shape = "table", of = "velocity", file = "damper.csv" }'))
    out = tmp_path / "out.txt"
    run = subprocess.run([sys.executable, "-m", "express", "generate", str(path), "-o", str(out)],
                         capture_output=True, text=True, timeout=300)
    assert run.returncode == 2, run.stderr
    assert "damper.csv:4: TSD part: the velocity values must increase: 0 after 0" in run.stderr
    assert "damper.csv:5: TSD part: a row must be two numbers" in run.stderr
    assert not out.exists()


# ------------------------------------------------------------------ closed forms in the march


def _bilinear_static(load_u: float, k0: float, k1: float, k2: float, knee: float, low: float) -> float:
    """x of k0 (U - x) = F(x), F bilinear (k1 inside [-low, knee], k2 beyond)."""
    x = k0 * load_u / (k0 + k1)
    if x > knee:
        return (k0 * load_u + (k2 - k1) * knee) / (k0 + k2)
    if x < -low:
        return (k0 * load_u - (k2 - k1) * low) / (k0 + k2)
    return x


@pytest.mark.parametrize("level", [0.004, 0.03, -0.002, -0.02])
def test_a_bilinear_spring_settles_at_its_closed_form_static_deflection(level):
    """A load through the spring k0 (the ground moved by U, smoothly over 0.5 s, held):
    the mass settles where k0 (U - x) = F(x) — inside the knee x = k0 U/(k0 + k1), beyond
    it x = (k0 U + (k2 - k1) d)/(k0 + k2), the compression knee 2 mm, the extension one
    5 mm.  The march's fixed point is the exact equilibrium (the linear part is stepped
    exactly, the feedback held): to 1e-9 of x after 3 s (achieved 6e-13; the transient
    decays as exp(-c0 t/(2 m)) = 1e-13)."""
    vehicle = _vehicle(BILINEAR)
    dt = 1e-3
    t = np.arange(0, 3.0, dt)
    states, force, _ = _run(vehicle, _ramp(t, level, 0.5), dt)
    expected = _bilinear_static(level, 40e3, 40e3, 160e3, 0.005, 0.002)
    assert states[-1, 0] == pytest.approx(expected, rel=1e-9)
    assert force[-1] == pytest.approx(40e3 * (level - expected), rel=1e-9)  # what the spring k0 carries


def _blow_off_energy(amplitude: float, omega: float, c: float, force: float) -> float:
    """The work per cycle of a damper c saturated at +-force, at x = X sin(w t):
    (4/w) [F V sin(tb) + c V^2 (pi/4 - tb/2 - sin(2 tb)/4)], V = X w, cos(tb) = F/(c V)
    (pi c V^2/w unsaturated)."""
    velocity = amplitude * omega
    if c * velocity <= force:
        return math.pi * c * velocity**2 / omega
    tb = math.acos(force / (c * velocity))
    return 4 / omega * (force * velocity * math.sin(tb) + c * velocity**2 * (math.pi / 4 - tb / 2 - math.sin(2 * tb) / 4))


def test_the_closed_form_energy_of_a_saturated_damper_by_quadrature():
    """The formula above against the integral of F(v) v over a cycle by 2e6-point
    trapezoids: to 1e-9 (achieved 5.5e-13)."""
    for amplitude in (0.01, 0.05, 1e-4):
        omega, c, force = 2 * math.pi * 2, 600e3, 12e3
        t = np.linspace(0, 2 * math.pi / omega, 2_000_001)
        v = amplitude * omega * np.cos(omega * t)
        power = np.clip(c * v, -force, force) * v
        quadrature = float(np.sum(0.5 * (power[1:] + power[:-1]) * np.diff(t)))
        assert _blow_off_energy(amplitude, omega, c, force) == pytest.approx(quadrature, rel=1e-9)


BLOW_OFF = '{ shape = "blow-off", damping = "600 * 1e3", force = "12 * 1e3" }'


def _damper_cycle(dt: float, characteristic: str = BLOW_OFF, low: float = 12e3) -> tuple[float, float, float]:
    """A blow-off damper (600 kN s/m to 0.02 m/s, then +-12 kN) on a 1 t mass held to a
    ground moving X cos(w t) (X = 50 mm, 2 Hz) by a spring of 1e10 N/m: the damper's
    stroke is the ground's motion to 3e-5.  (energy per cycle from the run, the closed
    form at the run's measured amplitude, the largest force)."""
    vehicle = _vehicle(characteristic, m="1 t", k0="1e10 N/m", c0="0")
    omega = 2 * math.pi * 2
    period = 2 * math.pi / omega
    t = np.arange(0, 3 * period + dt / 2, dt)
    states, force, _ = _run(vehicle, 0.05 * np.sin(omega * t), dt)
    last = t >= 2 * period - dt / 2  # the third cycle
    x, f = states[last, 0], force[last]
    energy = float(np.sum(0.5 * (f[1:] + f[:-1]) * np.diff(x)))
    amplitude = 0.5 * float(np.ptp(x))
    halves = _blow_off_energy(amplitude, omega, 600e3, 12e3) + _blow_off_energy(amplitude, omega, 600e3, low)
    return energy, 0.5 * halves, float(np.max(np.abs(force)))


def test_a_blow_off_damper_dissipates_the_closed_form_energy_per_cycle_converged_in_the_step():
    """The run's ∮ F dx over its third cycle against the closed form at its amplitude
    (2399.63 J; a fully saturated damper's 4 F_b X is 2400 J):
    to 1e-5 at dt = T/2000, T/4000 and T/8000 (achieved 6.5e-7, 9.9e-7, 1.8e-6: the floor
    is the holding spring's compliance, F_b/k_s = 1.2e-6 m of X = 50 mm), the energy itself
    converged in the step (it moves 2.4e-6, then 1.3e-6 of itself as the step halves:
    first order, the blow-off corners are crossed inside a step); the force never beyond
    12 kN (the slope beyond blow-off is zero)."""
    period = 0.5
    energies = []
    for dt in (period / 2000, period / 4000, period / 8000):
        energy, expected, largest = _damper_cycle(dt)
        assert abs(energy / expected - 1) <= 1e-5
        assert largest <= 12e3 * (1 + 1e-9)
        energies.append(energy)
    changes = np.abs(np.diff(energies)) / energies[-1]
    assert changes[1] < 0.7 * changes[0] and changes[1] <= 2e-6


def test_a_preloaded_contact_lifts_off_at_its_closed_form_load():
    """A side bearer: a contact of stiffness k = 200 kN/m with a preload P = 2 kN at the
    static state, the mass pulled away through k0 = 40 kN/m.  In contact x = k0 U/(k0 +
    k) and the bearer carries k x - P; it lifts off at U = P (k0 + k)/(k0 k) = 60 mm and
    beyond carries exactly nothing, x = U - P/k0.  At U = 0.5 and 2 times the lift-off
    load, settled: to 1e-9 (achieved 3e-15)."""
    vehicle = _vehicle('{ shape = "contact", stiffness = "200 * 1e3", preload = "2 * 1e3" }', c0="3 kN*s/m")
    k0, k, preload = 40e3, 200e3, 2e3
    lift = preload * (k0 + k) / (k0 * k)
    assert lift == pytest.approx(0.06)
    dt = 1e-3
    t = np.arange(0, 6.0, dt)
    u = _ramp(t, 0.5 * lift, 0.5) + _ramp(t - 3.0, 1.5 * lift, 0.5)
    states, force, _ = _run(vehicle, u, dt)
    half = np.searchsorted(t, 2.9)
    x_half = k0 * 0.5 * lift / (k0 + k)
    assert states[half, 0] == pytest.approx(x_half, rel=1e-9)
    assert force[half] == pytest.approx(k * x_half - preload, rel=1e-9)
    assert states[-1, 0] == pytest.approx(2 * lift - preload / k0, rel=1e-9)
    assert force[-1] == 0.0  # lifted off: exactly nothing
    assert np.all(force <= 0.0)  # a contact only pushes


# ------------------------------------------------------------------ a vehicle on the command line

YAW_DAMPER = """
[elements.T1_yaw_blow_off]
from = "{a}"
to = "{b}"
direction = "x"
characteristic = {{ shape = "blow-off", damping = "cyb", force = "Fyb" }}
label = "yaw damper with blow-off"
"""


def _blow_off_car(tmp_path: Path) -> Path:
    """The conventional car with a blow-off yaw damper between car body and bogie 1."""
    text = (ROOT / "examples" / "conventional.toml").read_text()
    model = parse_toml_model(text, "conventional.toml")
    body_point = next(p.id for p in model.points if p.host == "CB")
    bogie_point = next(p.id for p in model.points if p.host == "T1")
    path = tmp_path / "blow_off.toml"
    parameters = '[parameters]\ncyb = "600 kN*s/m"\nFyb = "12 kN"\n'
    path.write_text(text.replace("[parameters]\n", parameters, 1) + YAW_DAMPER.format(a=body_point, b=bogie_point))
    return path


def test_a_vehicle_with_a_blow_off_damper_on_the_command_line(tmp_path):
    """eigen says it saw the damper's tangent (JSON "linearisation" and standard error);
    simulate writes its force with its unit, never beyond 12 kN."""
    import json

    path = _blow_off_car(tmp_path)
    run = subprocess.run([sys.executable, "-m", "express", "eigen", str(path), "--json"], capture_output=True,
                         text=True, timeout=600)
    assert run.returncode == 0, run.stderr
    assert "tangent at the static state" in json.loads(run.stdout)["linearisation"]["T1_yaw_blow_off"]
    assert "nonlinear characteristics seen by this linear analysis" in run.stderr
    out = tmp_path / "run.csv"
    run = subprocess.run([sys.executable, "-m", "express", "simulate", str(path), "--track", "R400", "--dt", "1 ms",
                          "-o", str(out)], capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stderr
    header = out.read_text().splitlines()[0].split(",")
    column = header.index("force_T1_yaw_blow_off_N")
    force = np.array([float(line.split(",")[column]) for line in out.read_text().splitlines()[1:]])
    assert 0 < np.max(np.abs(force)) <= 12e3 * (1 + 1e-9)


def test_under_gravity_a_characteristic_carries_the_weight_as_its_tangent():
    """With [gravity] the static equilibrium sees the characteristic as the linear analyses
    do, its tangent: a mass on a bilinear coil is carried (it was refused: no element
    carried its weight) and K is the tangent."""
    text = """
[model]
name = "coil"
[parameters]
m = "1 t"
g = "9.81 m/s^2"
[bodies.M]
mass = "m"
dofs = ["z"]
[grounds.G]
[points.M1]
body = "M"
offset = [0, 0, 0]
[points.G1]
body = "G"
offset = [0, 0, 0]
[elements.coil]
from = "M1"
to = "G1"
direction = "z"
characteristic = { shape = "bilinear", stiffness = "1e6", knee = 0.01, beyond = "3e6" }
[gravity]
acceleration = "g"
"""
    vehicle = vehicle_model(parse_toml_model(text, "coil.toml"))
    assert vehicle.stiffness[0, 0] == pytest.approx(1e6, rel=1e-15)


def test_a_substructure_instance_puts_its_parameters_into_characteristics_and_air_springs():
    """A formal parameter used by a characteristic's breakpoints and tangent and by an
    air spring's gas is replaced by the instance's expression (the breakpoints and the
    derived stiffness are expressions of the parameters like any element value)."""
    text = """
[model]
name = "subs"
[parameters]
kfront = "40 kN/m"
pfront = "500 kPa"
[bodies.B]
mass = "100"
dofs = ["x", "z"]
[grounds.G]
[points.B1]
body = "B"
offset = [0, 0, 0]
[points.G1]
body = "G"
offset = [0, 0, 0]
[substructures.mount]
parameters = ["kc", "p"]
connectors = ["top", "base"]
[substructures.mount.elements]
coil = { from = "top", to = "base", direction = "x", characteristic = { shape = "bilinear", stiffness = "kc", knee = 0.01, beyond = "2*kc" } }
air = { from = "top", to = "base", direction = "z", air_spring = { gauge_pressure = "p", area = 0.25, bag_volume = 0.06 } }
[instances.front]
substructure = "mount"
prefix = "F_"
parameters = { kc = "kfront", p = "pfront" }
connect = { top = "B1", base = "G1" }
"""
    vehicle = vehicle_model(parse_toml_model(text, "subs.toml"))
    term = next(t for t in vehicle.equations.element_terms if t.element == "F_coil")
    assert str(term.values["tangent"]) == "kfront" and "kfront" in str(term.values["f3"])
    x, z = vehicle.dof_index("B.x"), vehicle.dof_index("B.z")
    assert vehicle.stiffness[x, x] == pytest.approx(40e3, rel=1e-15)
    assert vehicle.stiffness[z, z] == pytest.approx(1.4 * (500e3 + 101325) * 0.25**2 / 0.06, rel=1e-12)


def test_a_changed_csv_table_is_read_again_not_taken_from_the_cache(tmp_path):
    """The derivation cache is keyed by every file a model reads (express.base.reads): a
    CSV table edited between two runs gives the new tangent (here C 15 -> 105 kN s/m)."""
    (tmp_path / "damper.csv").write_text(CSV)
    path = tmp_path / "table.toml"
    path.write_text(MODEL.format(m="100 kg", k0="40 kN/m", c0="0",
                                 characteristic='{ shape = "table", of = "velocity", file = "damper.csv" }'))
    env = {"EXPRESS_CACHE_DIR": str(tmp_path / "cache")}

    def damping() -> str:
        run = subprocess.run([sys.executable, "-m", "express", "generate", str(path)], capture_output=True, text=True,
                             timeout=300, env={**os.environ, **env})
        assert run.returncode == 0, run.stderr
        return next(line for line in run.stdout.splitlines() if line.strip().startswith("C[M.x, M.x]"))

    assert damping().endswith("= c0 + 15000")
    (tmp_path / "damper.csv").write_text(CSV.replace("0.1, 2", "0.01, 2"))
    assert damping().endswith("= c0 + 105000")


def test_express_convert_writes_characteristics_and_friction_back():
    """model_to_toml (``express convert``) writes every characteristic (a keyword shape with
    its values, a table in SI) and a friction element's limit, and reads back to the same
    element terms and matrices (they were dropped before: friction silently)."""
    from express.io import model_to_toml

    shapes = {
        "part": '{ shape = "bilinear", stiffness = "k1", knee = "d1", beyond = "2*k1", compression_knee = 0.002 }',
        "damp": '{ shape = "blow-off", damping = "c1", force = "F1", beyond = 100 }',
        "lift": '{ shape = "contact", stiffness = "k1", gap = "d1", side = "extension" }',
        "tab": '{ shape = "table", of = "deflection", deflection = [-10, 0, 10], force = [-1, 0, 3], units = ["mm", "kN"] }',
    }
    text = MODEL.format(m="100 kg", k0="40 kN/m", c0="0", characteristic=shapes["part"])
    text = text.replace('c0 = "0"', 'c0 = "0"\nk1 = "40 kN/m"\nd1 = "5 mm"\nc1 = "10 kN*s/m"\nF1 = "1 kN"\nF = "200 N"')
    for name in ("damp", "lift", "tab"):
        text += f'[elements.{name}]\nfrom = "M1"\nto = "G1"\ndirection = "x"\ncharacteristic = {shapes[name]}\n'
    text += '[elements.slider]\nfrom = "M1"\nto = "G1"\ndirection = "x"\nstiffness = "1e6"\nfriction = "F"\n'
    model = parse_toml_model(text, "table.toml")
    again = parse_toml_model(model_to_toml(model), "again.toml")
    first, second = vehicle_model(model), vehicle_model(again)
    assert second.equations.element_terms == first.equations.element_terms
    np.testing.assert_array_equal(second.stiffness, first.stiffness)
    np.testing.assert_array_equal(second.damping(1.0), first.damping(1.0))


def test_an_oscillation_across_the_knee_converges_in_the_step():
    """The bilinear spring (k1 40 kN/m inside +5 / -2 mm, 160 kN/m beyond, with k0 40 kN/m
    beside it, undamped) set swinging across its knees by a 30 mm step of the ground: at
    the step the element asks for (w dt = 0.02, w = sqrt((k2 - k1)/m)) the run is within
    5e-4 of its amplitude of a run at 1e-5 s (achieved 3.1e-4), and within 2e-3 at w dt =
    0.05 (achieved 1.4e-3): the error falls with the step."""
    vehicle = _vehicle(BILINEAR, c0="0")
    omega = math.sqrt(120e3 / 100)

    def run(dt: float):
        t = np.arange(0, 1.0 + dt / 2, dt)
        return t, _run(vehicle, _ramp(t, 0.03, 0.05), dt)[0][:, 0]

    t_fine, x_fine = run(1e-5)
    errors = []
    for wdt in (0.02, 0.05):
        t, x = run(wdt / omega)
        errors.append(np.max(np.abs(np.interp(t, t_fine, x_fine) - x)) / np.max(np.abs(x_fine)))
    assert errors[0] <= 5e-4 and errors[1] <= 2e-3 and errors[0] < 0.5 * errors[1]
    (element,) = ForceSet((characteristic_elements_of(vehicle, np.zeros((2, 2)), np.zeros((2, 2))),),
                          vehicle.form.size).elements
    assert element.resolved_step(vehicle.mass) == pytest.approx(0.02 / omega, rel=1e-12)


def test_an_asymmetric_blow_off_damper_dissipates_half_of_each_sides_closed_form():
    """Blow-off at 12 kN in extension, 6 kN in compression (compression_force): each half
    cycle dissipates half of its symmetric damper's work, so the cycle the mean of the two
    closed forms (1799.80 J): to 1e-5 at T/4000 (achieved 5.5e-7); the force within its
    limit."""
    characteristic = ('{ shape = "blow-off", damping = "600 * 1e3", force = "12 * 1e3", '
                      'compression_force = "6 * 1e3" }')
    energy, expected, largest = _damper_cycle(0.5 / 4000, characteristic, 6e3)
    assert abs(energy / expected - 1) <= 1e-5
    assert largest <= 12e3 * (1 + 1e-9)
