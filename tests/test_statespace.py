"""The numerical state space: speed structure, consistency with the symbols, singular M."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

from express.base.diagnostics import ModelError
from express.cli import main
from express.io import load_model, parse_toml_model
from express.numeric.statespace import SingularMassError, vehicle_model

WHEELSET = """
[model]
name = "wheelset"
[parameters]
m = {value = 1400, unit = "kg"}
I = {value = 600, unit = "kg*m^2"}
f = "7.8 MN"
v = "100 km/h"
G = "1067 mm"
[bodies.W]
mass = "{mass}"
inertia = [0, 0, "I"]
dofs = ["y", "rz"]
[rail]
wheelsets = ["W"]
[rail.wheel_rail]
f1 = "f"
f2 = "f"
conicity = 0.1
r0 = 0.43
b = 0.56
flange_clearance = 0.006
rail_stiffness = 2e7
friction = 0.3
wheel_load = 5e4
"""


@pytest.fixture(scope="module")
def vehicle():
    return vehicle_model(load_model("examples/forced-steering.toml"))


@pytest.mark.parametrize("speed", [5.0, 33.3, 70.0])
def test_speed_split_matches_direct_evaluation(vehicle, speed):
    """C0 + C1/v and P0 + P2 v^2 equal the symbolic matrices evaluated at v."""
    values = {sp.Symbol(k): v for k, v in {**vehicle.values, "v": speed}.items()}
    for key, numeric in (("C", vehicle.damping(speed)), ("P", vehicle.forcing(speed)), ("K", vehicle.stiffness)):
        direct = np.array(vehicle.equations.matrices[key].xreplace(values), dtype=float)
        assert np.allclose(numeric, direct, rtol=1e-12, atol=1e-9 * np.abs(direct).max())


def test_state_matrices_are_the_papers_eqs_15_and_16(vehicle):
    """A = [[0, I], [-M^-1 K, -M^-1 C]], B = [[0], [M^-1 P]] (eqs. 15-16)."""
    v = 30.0
    n = vehicle.n
    a, b = vehicle.state_matrix(v), vehicle.input_matrix(v)
    minv = np.linalg.inv(vehicle.mass)
    assert np.array_equal(a[:n, :n], np.zeros((n, n))) and np.array_equal(a[:n, n:], np.eye(n))
    assert np.allclose(a[n:, :n], -minv @ vehicle.stiffness)
    assert np.allclose(a[n:, n:], -minv @ vehicle.damping(v))
    assert np.allclose(b[n:], minv @ vehicle.forcing(v)) and not b[:n].any()
    assert a.shape == (48, 48) and b.shape == (48, 22)


def test_zero_mass_is_refused_where_m_is_inverted():
    """A DOF without mass: generation warns, the state space refuses, naming the DOF."""
    model = parse_toml_model(WHEELSET.replace("{mass}", "0"), source="w.toml")
    with pytest.raises(SingularMassError) as info:
        vehicle_model(model)
    assert "W.y" in str(info.value) and "w.toml" in str(info.value)
    assert isinstance(info.value, ModelError)


def test_zero_mass_cli_exits_2_without_traceback(tmp_path, capsys):
    path = tmp_path / "w.toml"
    path.write_text(WHEELSET.replace("{mass}", "0"))
    assert main(["generate", str(path)]) == 0
    assert "warning" in capsys.readouterr().err
    assert main(["eigen", str(path)]) == 2
    err = capsys.readouterr().err
    assert "W.y" in err and "Traceback" not in err


def test_single_wheelset_hunting_frequency():
    """A free wheelset's kinematic mode at low speed: f = v / (2 pi sqrt(r0 b / Gamma))."""
    model = parse_toml_model(WHEELSET.replace("{mass}", "m"), source="w.toml")
    vehicle = vehicle_model(model)
    v = 2.0
    frequency = np.abs(vehicle.eigenvalues(v).imag).max() / (2 * np.pi)
    expected = v / (2 * np.pi * np.sqrt(0.43 * 0.56 / 0.1))
    assert frequency == pytest.approx(expected, rel=0.01)


@pytest.mark.parametrize("changes", [{"Gamma": 0.23}, {"mc": 31500.0}, {"mw": "1.6 t", "Gamma": 0.05}])
def test_with_values_equals_a_fresh_evaluation_exactly(vehicle, changes):
    """Re-evaluation through the compiled functions (derived parameters following: a
    new mass moves the wheel load and the creep coefficients) gives exactly the arrays
    and wheelset data of a vehicle generated from scratch with those values."""
    from express.model.parameters import with_values

    changed = vehicle.with_values(changes)
    fresh = vehicle_model(with_values(vehicle.model, changes))
    for name in ("mass", "stiffness", "damping_base", "damping_creep", "forcing_base", "forcing_speed2",
                 "forcing_rate_matrix", "station_positions"):
        assert np.array_equal(getattr(changed, name), getattr(fresh, name)), name
    assert changed.wheelsets == fresh.wheelsets and changed.speed == fresh.speed
    assert changed.values == fresh.values
    assert np.array_equal(changed.state_matrix(30.0), fresh.state_matrix(30.0))
    if "mc" in changes:  # derived: the wheel load and the creep coefficients follow
        assert changed.wheelsets[0].wheel_load > vehicle.wheelsets[0].wheel_load
        assert changed.wheelsets[0].f1 > vehicle.wheelsets[0].f1


def test_with_values_reports_a_division_by_zero_as_a_model_error(vehicle):
    """A zero cant base would divide the cant by zero: refused before, as a value
    outside its valid range (issue 17)."""
    with pytest.raises(ModelError, match=r"parameter G: set to 0 m, outside the valid range 0 < cant_base"):
        vehicle.with_values({"G": 0.0})
