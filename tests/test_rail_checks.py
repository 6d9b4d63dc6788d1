"""Checks of the rail modules on the bundled vehicles (issue checks).

* pin elimination: 28 DOFs before (``keep_virtual=True``), 24 after; the virtual pin
  stiffness ``kinf`` appears in no output;
* M symmetric positive definite; C symmetric; K symmetric except the creep terms,
  which sit only in the wheelset rows (the ``y``/``rz`` pair of each wheelset);
* curvature terms: in a steady curve the steering levers turn by the geometric angle
  ``bL lT / (R lLU)`` when the upper link is much stiffer than the lower ones;
* cant deficiency: the total lateral force equals ``-m_total (v^2 rho - g S / G)``.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import sympy as sp

from express.export import FORMATS
from express.io import load_model
from express.numeric.statespace import vehicle_model
from express.rail.build import generate_vehicle

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
LEVERS = ("L1.ry", "L2.ry", "L3.ry", "L4.ry")


@pytest.fixture(scope="module")
def steered_model():
    return load_model(EXAMPLES / "forced-steering.toml")


@pytest.fixture(scope="module")
def steered_equations(steered_model):
    return generate_vehicle(steered_model).equations


@pytest.fixture(scope="module")
def steered(steered_model):
    return vehicle_model(steered_model)


# --- pin elimination ------------------------------------------------------------------------


def test_dof_counts_before_and_after_elimination(steered_model, steered_equations):
    full = generate_vehicle(steered_model, keep_virtual=True)
    assert len(full.equations.dofs) == 28
    assert len(steered_equations.dofs) == 24
    assert set(full.equations.dofs) - set(steered_equations.dofs) == {"L1.x", "L2.x", "L3.x", "L4.x"}
    assert steered_equations.eliminated == ("L1.x", "L2.x", "L3.x", "L4.x")
    # with the virtual DOFs kept, the virtual stiffness is there (the check below can see it)
    assert "kinf" in full.equations.parameters


def test_no_kinf_in_any_output(steered_equations, steered):
    assert "kinf" not in steered_equations.parameters
    kinf = sp.Symbol("kinf")
    for key, matrix in steered_equations.matrices.items():
        assert kinf not in matrix.free_symbols, key
    for name, export in FORMATS.items():
        assert "kinf" not in export(steered_equations), name
    # the numerical model does not depend on it either
    changed = steered.with_values({"kinf": 1.0e3})
    for attribute in ("mass", "stiffness", "damping_base", "damping_creep", "forcing_base", "forcing_speed2", "forcing_rate_matrix"):
        np.testing.assert_array_equal(getattr(changed, attribute), getattr(steered, attribute))


# --- symmetry --------------------------------------------------------------------------------


@pytest.mark.parametrize("name", ["forced-steering", "conventional"])
def test_mass_damping_stiffness_symmetry(name, steered_equations):
    equations = (steered_equations if name == "forced-steering"
                 else generate_vehicle(load_model(EXAMPLES / f"{name}.toml")).equations)
    dofs = equations.dofs
    M, C, K = (equations.matrices[key] for key in ("M", "C", "K"))
    for matrix in (M, C):
        assert (matrix - matrix.T).applyfunc(sp.expand) == sp.zeros(*matrix.shape)
    difference = (K - K.T).applyfunc(sp.expand)
    nonzero = {(dofs[i], dofs[j]): difference[i, j]
               for i in range(K.rows) for j in range(K.cols) if difference[i, j] != 0}
    # only the creep coupling of each wheelset: K[y, rz] = -2 f2, K[rz, y] = 2 b f1 Gamma / r0
    f1, f2, gamma, r0, b = sp.symbols("f1 f2 Gamma r0 b")
    creep = 2 * f2 + 2 * b * f1 * gamma / r0
    wheelsets = ("W1", "W2", "W3", "W4")
    expected = {}
    for w in wheelsets:
        expected[(f"{w}.y", f"{w}.rz")] = -creep
        expected[(f"{w}.rz", f"{w}.y")] = creep
    assert set(nonzero) == set(expected)
    for key, value in nonzero.items():
        assert sp.expand(value - expected[key]) == 0, key
    # every asymmetric entry is in a wheelset row (and column)
    assert all(row.split(".")[0] in wheelsets and col.split(".")[0] in wheelsets for row, col in nonzero)


@pytest.mark.parametrize("name", ["forced-steering", "conventional"])
def test_mass_positive_definite(name, steered):
    vehicle = steered if name == "forced-steering" else vehicle_model(load_model(EXAMPLES / f"{name}.toml"))
    np.testing.assert_array_equal(vehicle.mass, vehicle.mass.T)
    assert np.linalg.eigvalsh(vehicle.mass).min() > 0
    np.testing.assert_allclose(vehicle.damping(30.0), vehicle.damping(30.0).T, atol=1e-9 * np.abs(vehicle.damping(30.0)).max())


# --- curvature terms: the steering levers ---------------------------------------------------


def _curve_inputs(vehicle, rho: float, cant: float = 0.0) -> np.ndarray:
    u = np.zeros(len(vehicle.inputs))
    for name in vehicle.layout.curvature:
        u[vehicle.inputs.index(name)] = rho
    for name in vehicle.layout.cant:
        u[vehicle.inputs.index(name)] = cant
    return u


@pytest.mark.parametrize("direction", [1.0, -1.0])
def test_geometric_lever_angle_in_a_steady_curve(steered, direction):
    """R = 400 m, every body but the levers held at zero in its own track frame,
    kLU = 1e12 >> kLL = 1: the static equilibrium of the lever DOFs alone,
    ``K_LL theta = P_L u`` (u = curvature at every station, no cant), gives the paper's
    geometric angle ``bL lT / (R lLU) = 1 * 7.2 / (400 * 0.3) = 0.06 rad``.

    Left (L1, L3) and right (L2, L4) levers of a bogie turn in opposite directions and
    the rear bogie's levers mirror the front's (L3 = -L1, L4 = -L2).
    """
    vehicle = steered.with_values({"kLU": 1.0e12, "kLL": 1.0})
    levers = [vehicle.dof_index(name) for name in LEVERS]
    u = _curve_inputs(vehicle, direction / 400.0)
    k_ll = vehicle.stiffness[np.ix_(levers, levers)]
    force = (vehicle.forcing(120 / 3.6) @ u)[levers]
    theta = np.linalg.solve(k_ll, force)
    geometric = 1.0 * 7.2 / (400.0 * 0.3)
    assert geometric == pytest.approx(0.06)
    np.testing.assert_allclose(theta, direction * geometric * np.array([1.0, -1.0, -1.0, 1.0]), rtol=1e-2)
    np.testing.assert_allclose(theta, direction * geometric * np.array([1.0, -1.0, -1.0, 1.0]), rtol=1e-6)


# --- cant deficiency --------------------------------------------------------------------------


@pytest.mark.parametrize("direction", [1.0, -1.0])
def test_cant_deficiency_force_on_the_whole_vehicle(steered, direction):
    """120 km/h on R = 400 m with 95 mm cant: the sum of ``P u`` over the lateral (y)
    rows is ``-m_total (v^2 rho - g S / G)`` (to the outside of the curve: negative for
    a left curve); the connection forces cancel in the sum.

    ``m_total = mc + 2 mt + 4 mw = 30000 + 5200 + 5600 = 40800 kg``: the bodies with a
    lateral DOF. The four 20 kg levers (80 kg) have no lateral DOF; after the pin
    elimination their mass enters the bogie frames' longitudinal DOF (``M[T1.x, T1.x] =
    mt + 2 mL``), not the lateral one (``M[T1.y, T1.y] = mt``), so they carry no
    cant-deficiency force. The car's mass is 40 880 kg.
    """
    speed, rho, cant = 120 / 3.6, direction / 400.0, direction * 0.095
    u = _curve_inputs(steered, rho, cant)
    force = steered.forcing(speed) @ u
    lateral = [i for i, dof in enumerate(steered.dofs) if dof.endswith(".y")]
    longitudinal = [i for i, dof in enumerate(steered.dofs) if dof.endswith(".x")]
    m_total = 30000.0 + 2 * 2600.0 + 4 * 1400.0
    expected = -m_total * (speed**2 * rho - 9.81 * cant / 1.067)
    assert force[lateral].sum() == pytest.approx(expected, rel=1e-9)
    assert abs(expected) == pytest.approx(40800 * (speed**2 / 400 - 9.81 * 0.095 / 1.067), rel=1e-12)
    assert abs(force[longitudinal].sum()) < 1e-9 * abs(expected)
    for bogie in ("T1", "T2"):
        i, j = steered.dof_index(f"{bogie}.x"), steered.dof_index(f"{bogie}.y")
        assert steered.mass[i, i] == pytest.approx(2600.0 + 2 * 20.0)
        assert steered.mass[j, j] == pytest.approx(2600.0)
    # the force on each body alone, seen without the connections: P2 v^2 + cant column
    for body, mass in (("CB", 30000.0), ("T1", 2600.0), ("W1", 1400.0)):
        row = steered.dof_index(f"{body}.y")
        station = next(s for s in steered.layout.stations if body in s.bodies)
        own = (steered.forcing_speed2[row, steered.inputs.index(station.curvature_input)] * speed**2 * rho
               + steered.forcing_base[row, steered.inputs.index(station.cant_input)] * cant)
        assert own == pytest.approx(-mass * (speed**2 * rho - 9.81 * cant / 1.067), rel=1e-9)
