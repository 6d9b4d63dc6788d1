"""Run the exported MATLAB files in GNU Octave and compare with SymPy.

Skipped when Octave is missing, except in CI (environment variable ``CI`` set), where a
missing Octave is a failure: CI installs Debian's ``octave``.
"""

from __future__ import annotations

import numpy as np
import pytest

from express.export.matlab import to_matlab
from octave_runner import (
    assert_matrices_close,
    evaluate_matrices,
    require_octave,
    run_octave,
)
from test_export import chain_eom, inputs_eom, keyword_eom, lever_eom

RECORDS = {
    "lever": lever_eom,
    "inputs": inputs_eom,
    "chain": lambda: chain_eom(60),
    "keywords": keyword_eom,
}


@pytest.fixture(scope="module")
def octave():
    return require_octave()


def _write(tmp_path, eom, name=None):
    fname = name or eom.name
    path = tmp_path / f"{fname}.m"
    path.write_text(to_matlab(eom, name), encoding="utf-8")
    return path


@pytest.mark.parametrize("record", sorted(RECORDS))
def test_octave_matches_sympy(tmp_path, octave, record):
    eom = RECORDS[record]()
    got = run_octave(_write(tmp_path, eom), eom.values, octave=octave)
    assert_matrices_close(got, evaluate_matrices(eom), rtol=1e-12)


@pytest.mark.parametrize("record", ["lever", "inputs"])
def test_octave_other_values(tmp_path, octave, record):
    eom = RECORDS[record]()
    values = {name: 0.5 + 0.37 * k for k, name in enumerate(eom.parameters)}
    got = run_octave(_write(tmp_path, eom), values, octave=octave)
    assert_matrices_close(got, evaluate_matrices(eom, values), rtol=1e-12)


def test_octave_default_values(tmp_path, octave):
    eom = inputs_eom()
    got = run_octave(_write(tmp_path, eom), None, octave=octave)
    assert_matrices_close(got, evaluate_matrices(eom), rtol=1e-12)
    assert list(got) == ["M", "C", "K", "P", "Pd", "G"]
    assert got["P"].shape == (3, 2)


def test_octave_explicit_name(tmp_path, octave):
    eom = lever_eom()
    name = "lever_" + "x" * 57  # 63 characters, the longest valid name
    got = run_octave(_write(tmp_path, eom, name), eom.values, octave=octave)
    assert_matrices_close(got, evaluate_matrices(eom), rtol=1e-12)
    assert np.array_equal(got["K"], got["K"].T)
