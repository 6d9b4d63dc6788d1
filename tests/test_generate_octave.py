"""The generator's MATLAB export runs unchanged in GNU Octave and gives the Python numbers.

For the paper's lever and for the forced-steering vehicle (4 pins, rail terms), the
`.m` file written by ``express generate --format matlab`` is run in Octave and its
matrices compared with the generator's own evaluation (SymPy substitution). The car's
wheel load and creep coefficients are derived: the file computes them from the given
parameters (``tests/test_export_derivation.py`` checks a changed mass).
Octave is required in CI (``tests/octave_runner.py``).
"""

from __future__ import annotations

import random

import pytest

from express.cli import main
from express.io import load_model
from express.rail.build import generate_vehicle
from octave_runner import assert_matrices_close, evaluate_matrices, require_octave, run_octave


def _lever_values() -> dict[str, float]:
    rng = random.Random(7)
    names = ["J1", "J2", "b", "c", "kLL", "kLU", "lLL", "lLU", "m"]
    return {name: rng.uniform(0.5, 2.0) for name in names}


@pytest.mark.parametrize(
    "model_path, function_name, values",
    [
        ("examples/lever.exp", "lever", _lever_values()),
        ("examples/forced-steering.toml", "forced_steering", None),
    ],
)
def test_matlab_file_matches_python(tmp_path, model_path, function_name, values):
    """Generate through the CLI, run in Octave, compare every matrix (M, C, K, P, Pd)."""
    octave = require_octave()
    mfile = tmp_path / f"{function_name}.m"
    assert main(["generate", model_path, "--format", "matlab", "-o", str(mfile)]) == 0
    equations = generate_vehicle(load_model(model_path)).equations
    reference = evaluate_matrices(equations, values)
    from_octave = run_octave(mfile, values, octave=octave)
    # a model with derived parameters (P0, f1, f2 of the car) also returns the struct
    # ``values`` of every parameter, the derived ones computed in Octave
    matrices = {key: value for key, value in from_octave.items() if not key.startswith("values.")}
    assert set(matrices) == set(equations.matrices)
    assert_matrices_close(matrices, reference, rtol=1e-12)
    derived = {step.name for step in equations.derivation if hasattr(step, "name")}
    derived |= {name for step in equations.derivation for _, name in getattr(step, "outputs", ())}
    for name in sorted(derived & set(equations.parameters)):
        assert from_octave[f"values.{name}"][0, 0] == pytest.approx(equations.values[name], rel=1e-12), name
    if equations.eliminated:
        assert "kinf" not in mfile.read_text()
