"""The generator's MATLAB export runs unchanged in GNU Octave and gives the Python numbers.

For the paper's lever and for the forced-steering vehicle (4 pins, rail terms), the
`.m` file written by ``express generate --format matlab`` is run in Octave and its
matrices compared with the generator's own evaluation (SymPy substitution).
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
    assert set(from_octave) == set(equations.matrices)
    assert_matrices_close(from_octave, reference, rtol=1e-12)
    if equations.eliminated:
        assert "kinf" not in mfile.read_text()
