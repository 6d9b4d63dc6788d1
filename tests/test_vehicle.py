"""The bundled vehicles: structure, the classic twin file, parameter overrides."""

from __future__ import annotations

import json

import numpy as np
import pytest
import sympy as sp

from express.assembly.generator import generate
from express.cli import main
from express.io import load_model
from express.io.classic_writer import model_to_classic
from express.numeric.statespace import vehicle_model

STEERED = "examples/forced-steering.toml"
CONVENTIONAL = "examples/conventional.toml"


@pytest.mark.parametrize(
    "path, bodies, full, reduced, pins, elements",
    [(STEERED, 11, 28, 24, 4, 54), (CONVENTIONAL, 7, 20, 20, 0, 38)],
)
def test_structure(path, bodies, full, reduced, pins, elements):
    """Bodies, DOFs before/after elimination, pins and elements (virtual ones included)."""
    model = load_model(path)
    result = generate(model)
    assert len(model.bodies) == bodies
    assert len(result.full_dofs) == full
    assert len(result.equations.dofs) == reduced
    assert len(model.pins) == pins
    assert len(model.elements) == elements


def test_classic_file_generates_the_same_matrices():
    """``examples/forced-steering.exp`` (renumbered items) gives the TOML file's M, C, K."""
    modern = load_model(STEERED)
    classic = load_model("examples/forced-steering.exp")
    a, b = generate(classic).equations, generate(modern).equations
    _, renaming = model_to_classic(modern)
    renamed = [f"{renaming[dof.split('.')[0]]}.{dof.split('.')[1]}" for dof in b.dofs]
    assert list(a.dofs) == renamed
    for key in ("M", "C", "K"):
        difference = (a.matrices[key] - b.matrices[key]).applyfunc(sp.expand)
        assert difference == sp.zeros(*difference.shape), key


def test_classic_file_is_current():
    """The committed .exp file is what the writer makes of the TOML file today."""
    text, _ = model_to_classic(load_model(STEERED))
    with open("examples/forced-steering.exp", encoding="utf-8") as stream:
        assert stream.read() == text


def test_mass_matrix_is_symmetric_positive_definite_and_k_asymmetry_is_creep_only():
    """M is SPD; C is symmetric; K - K^T is non-zero only where the creep couples a
    wheelset's lateral and yaw DOFs."""
    vehicle = vehicle_model(load_model(STEERED))
    np.linalg.cholesky(vehicle.mass)
    for c in (vehicle.damping_base, vehicle.damping_creep):
        assert np.allclose(c, c.T)
    asymmetric = np.argwhere(np.abs(vehicle.stiffness - vehicle.stiffness.T) > 1e-6 * np.abs(vehicle.stiffness).max())
    wheelset_dofs = {i for w in vehicle.wheelsets for i in (w.y, w.psi)}
    assert len(asymmetric) > 0
    assert {int(i) for pair in asymmetric for i in pair} <= wheelset_dofs


def test_creep_coefficients_are_computed_from_the_contact():
    """[rail.creep]: f1, f2 follow the wheel load (Hertz + Kalker), also under --set."""
    model = load_model(STEERED)
    assert model.parameters["f1"].value == pytest.approx(8.711e6, rel=1e-3)
    assert model.parameters["f2"].value == pytest.approx(7.822e6, rel=1e-3)
    lighter = vehicle_model(model).with_values({"P0": 40e3})
    ratio = lighter.wheelsets[0].f1 / model.parameters["f1"].value
    assert ratio == pytest.approx((40 / 50.0) ** (2 / 3), rel=0.02)  # Hertz: f ~ N^(2/3)


def test_set_overrides_values_in_the_json_export(tmp_path, capsys):
    """--set changes the exported parameter values (SI), never the symbolic matrices."""
    output = tmp_path / "fs.json"
    assert main(["generate", STEERED, "--format", "json", "-o", str(output), "--set", "Gamma=0.05", "--set", "v=100 km/h"]) == 0
    data = json.loads(output.read_text())
    assert data["values"]["Gamma"] == 0.05
    assert data["values"]["v"] == pytest.approx(100 / 3.6)
    assert len(data["dofs"]) == 24 and len(data["inputs"]) == 22
    assert "kinf" not in output.read_text()  # not in the matrices, nor in the values
