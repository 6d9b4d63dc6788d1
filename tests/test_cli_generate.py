"""``express generate`` (``express.cli.generate``): every export format, whole files,
clean errors for bad models and bad ``--set`` values, no traceback."""

from __future__ import annotations

import importlib.util
import json
import os
import re
import stat
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

from cli_support import LEVER, PROBLEM_LINE, STEERED, assert_input_error, run
from express.export.json_export import dense_rows

LEVER_TEXT = Path(LEVER).read_text(encoding="utf-8")
FORMATS = {"json": ".json", "matlab": ".m", "python": ".py", "latex": ".tex", "text": ".txt"}

J1, J2, b, c, kLL, kLU, lLL, lLU, m = sp.symbols("J1 J2 b c kLL kLU lLL lLU m")
K_LEVER = sp.Matrix(
    [[b**2 * (kLU + kLL), b * (lLU * kLU - lLL * kLL)], [b * (lLU * kLU - lLL * kLL), lLU**2 * kLU + lLL**2 * kLL]]
)


@pytest.fixture
def lever_copy(tmp_path):
    path = tmp_path / "lever.exp"
    path.write_text(LEVER_TEXT, encoding="utf-8")
    return path


# --------------------------------------------------------------------------- formats


def test_generate_text_to_stdout(capsys):
    """``express generate examples/lever.exp`` writes the text view to stdout: the
    reduced DOFs, the eliminated one, no ``kinf``, and nothing on stderr."""
    status, out, err = run(capsys, "generate", LEVER)
    assert status == 0
    assert "B1.rz" in out and "B2.ry" in out and "B2.x" in out
    assert "kinf" not in out
    assert "b**2*(kLL + kLU)" in out
    assert err == ""


def test_dash_is_standard_output(capsys):
    assert run(capsys, "generate", LEVER, "-o", "-")[1] == run(capsys, "generate", LEVER)[1]


def test_keep_virtual_shows_kinf(capsys):
    """``--keep-virtual`` keeps the virtual DOF and the virtual stiffness (eq. 6)."""
    status, out, _ = run(capsys, "generate", LEVER, "--keep-virtual")
    assert status == 0
    assert "kinf" in out


def test_keep_virtual_json(tmp_path, capsys):
    """With ``--keep-virtual`` the JSON has three DOFs ending in B2.x, nothing
    eliminated, and K is eq. (6)."""
    target = tmp_path / "lever.json"
    status, _, _ = run(capsys, "generate", LEVER, "--keep-virtual", "--format", "json", "-o", target)
    assert status == 0
    data = json.loads(target.read_text())
    assert data["dofs"] == ["B1.rz", "B2.ry", "B2.x"]
    assert data["eliminated"] == []
    assert "kinf" in data["parameters"]
    K = sp.Matrix([[sp.sympify(e) for e in row] for row in dense_rows(data["K"])])
    kinf = sp.Symbol("kinf")
    eq6 = sp.Matrix(
        [
            [b**2 * kinf, 0, -b * kinf],
            [0, lLU**2 * kLU + lLL**2 * kLL, lLU * kLU - lLL * kLL],
            [-b * kinf, lLU * kLU - lLL * kLL, kLU + kLL + kinf],
        ]
    )
    assert sp.simplify(K - eq6) == sp.zeros(3, 3)


@pytest.mark.parametrize("fmt", sorted(FORMATS))
def test_each_format_writes_a_deterministic_file(tmp_path, capsys, fmt):
    """``--format F -o FILE`` writes a non-empty file (not stdout), and a second run
    gives the very same bytes; overwriting an earlier output leaves no temporary."""
    first_dir, second_dir = tmp_path / "one", tmp_path / "two"
    first_dir.mkdir()
    second_dir.mkdir()
    name = "lever" + FORMATS[fmt]
    status, out, err = run(capsys, "generate", LEVER, "--format", fmt, "-o", first_dir / name)
    assert status == 0, err
    assert out == ""
    assert f"wrote {first_dir / name}" in err
    data = (first_dir / name).read_bytes()
    assert data.strip()
    assert run(capsys, "generate", LEVER, "--format", fmt, "-o", second_dir / name)[0] == 0
    assert (second_dir / name).read_bytes() == data
    assert run(capsys, "generate", LEVER, "--format", fmt, "-o", first_dir / name)[0] == 0
    assert (first_dir / name).read_bytes() == data
    assert sorted(p.name for p in first_dir.iterdir()) == [name]


@pytest.mark.parametrize("fmt", sorted(FORMATS))
def test_each_format_to_stdout_matches_the_file(tmp_path, capsys, fmt):
    """Without ``-o`` the same text goes to stdout (MATLAB: same function name)."""
    target = tmp_path / ("lever" + FORMATS[fmt])
    assert run(capsys, "generate", LEVER, "--format", fmt, "-o", target)[0] == 0
    status, out, _ = run(capsys, "generate", LEVER, "--format", fmt)
    assert status == 0
    assert out == target.read_text(encoding="utf-8")


def test_output_file_permissions_follow_the_umask(tmp_path, capsys):
    """The written file gets the usual permissions (0666 minus the umask), not the
    0600 of a private temporary file."""
    umask = os.umask(0o022)
    try:
        target = tmp_path / "lever.json"
        assert run(capsys, "generate", LEVER, "--format", "json", "-o", target)[0] == 0
    finally:
        os.umask(umask)
    assert stat.S_IMODE(target.stat().st_mode) == 0o644


def test_dev_null_stays_a_device(capsys):
    """``-o /dev/null`` writes into the device; it is not replaced by a regular file."""
    status, _, _ = run(capsys, "generate", LEVER, "--format", "json", "-o", "/dev/null")
    assert status == 0
    assert stat.S_ISCHR(os.stat("/dev/null").st_mode)


def test_json_follows_the_contract(tmp_path, capsys):
    """The JSON file has the keys of conventions.md with their meaning: DOF names,
    eliminated DOFs, sorted parameters, matrices as SymPy strings (``**`` powers)."""
    target = tmp_path / "lever.json"
    assert run(capsys, "generate", LEVER, "--format", "json", "-o", target)[0] == 0
    data = json.loads(target.read_text(encoding="utf-8"))
    assert data["dofs"] == ["B1.rz", "B2.ry"]
    assert data["eliminated"] == ["B2.x"]
    assert data["parameters"] == ["J1", "J2", "b", "c", "kLL", "kLU", "lLL", "lLU", "m"]

    def parse(matrix):  # JSON version 2 holds the non-zero entries (docs/conventions.md)
        return sp.Matrix([[sp.sympify(entry) for entry in row] for row in dense_rows(matrix)])

    assert "^" not in target.read_text()
    assert parse(data["M"]) == sp.Matrix([[J1 + b**2 * m, 0], [0, J2]])
    assert parse(data["C"]) == sp.Matrix([[b**2 * c, 0], [0, 0]])
    assert sp.simplify(parse(data["K"]) - K_LEVER) == sp.zeros(2, 2)


def test_python_module_evaluates_to_the_closed_form(tmp_path, capsys):
    """The ``--format python`` module imports and its matrices equal the closed form
    evaluated at the same values."""
    target = tmp_path / "lever_eom.py"
    assert run(capsys, "generate", LEVER, "--format", "python", "-o", target)[0] == 0
    spec = importlib.util.spec_from_file_location("lever_eom", target)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    values = {"J1": 2.0, "J2": 0.5, "b": 0.4, "c": 300.0, "kLL": 5.5e6, "kLU": 5e5, "lLL": 0.06, "lLU": 0.3, "m": 20.0}
    result = module.matrices(values)
    symbols = {sp.Symbol(k): v for k, v in values.items()}
    expected_K = np.array(K_LEVER.subs(symbols), dtype=float)
    np.testing.assert_allclose(result["K"], expected_K, rtol=1e-12)
    np.testing.assert_allclose(result["M"], [[2.0 + 0.16 * 20.0, 0], [0, 0.5]], rtol=1e-12)


def test_matlab_file_is_a_function_named_after_the_file(tmp_path, capsys):
    """A MATLAB function file's function is named after the file."""
    target = tmp_path / "leverEOM.m"
    assert run(capsys, "generate", LEVER, "--format", "matlab", "-o", target)[0] == 0
    first = next(line for line in target.read_text().splitlines() if line.strip() and not line.startswith("%"))
    assert re.match(r"function\s*\[.*\]\s*=\s*leverEOM\s*\(", first), first


# --------------------------------------------------------------------------- bad destinations


def test_matlab_needs_dot_m(tmp_path, capsys):
    """``--format matlab -o x.txt`` is refused (exit 2), nothing written."""
    target = tmp_path / "lever.txt"
    assert_input_error(capsys, "generate", LEVER, "--format", "matlab", "-o", target, mentions=".m")
    assert not target.exists()


def test_generate_refuses_to_overwrite_the_model(lever_copy, capsys):
    """``generate X -o X`` exits 2 and leaves X unchanged."""
    before = lever_copy.read_bytes()
    assert_input_error(capsys, "generate", lever_copy, "--format", "text", "-o", lever_copy, mentions="overwrite")
    assert lever_copy.read_bytes() == before


@pytest.mark.parametrize("kind", ["directory", "under a file"])
def test_unwritable_output_is_a_clean_error(tmp_path, capsys, kind):
    """An output path that cannot be a file (an existing directory, or a path below a
    regular file) is bad input: status 2, a one-line error naming it."""
    if kind == "directory":
        target = tmp_path / "out"
        target.mkdir()
    else:
        (tmp_path / "plain").write_text("x")
        target = tmp_path / "plain" / "lever.json"
    err = assert_input_error(capsys, "generate", LEVER, "--format", "json", "-o", target)
    assert len(err.splitlines()) == 1
    assert str(target.name) in err or str(target) in err


# --------------------------------------------------------------------------- bad models


@pytest.mark.parametrize(
    "edits, count",
    [
        ([("C1,\tB2,", "C1,\tB9,")], 1),
        ([("C1,\tB2,", "C1,\tB9,"), ("C1,\tC2,\t1,", "C1,\tC2,\t4,"), ("T2,\tkLL,", "T2,\tkLL(,")], 3),
        ([("P1,\tC5,\tC6,", "P1,\tC5,\tC7,")], 1),
        ([("T1,\tkLU,", "T1,\t__import__('os').system('echo pwned'),")], 1),
    ],
)
def test_malformed_model_exits_2_with_one_line_per_problem(tmp_path, capsys, edits, count):
    """A malformed model: status 2, nothing on stdout, at least ``count`` stderr lines of
    the form ``error: file:line: item: message`` naming this file, and no output file."""
    text = LEVER_TEXT
    for old, new in edits:
        assert old in text
        text = text.replace(old, new, 1)
    model = tmp_path / "bad.exp"
    model.write_text(text, encoding="utf-8")
    target = tmp_path / "bad.json"
    err = assert_input_error(capsys, "generate", model, "--format", "json", "-o", target)
    lines = [line for line in err.splitlines() if line.strip()]
    matches = [PROBLEM_LINE.match(line) for line in lines]
    assert all(matches), lines
    assert len(matches) >= count
    for match in matches:
        assert match["file"] == str(model)
        assert 1 <= int(match["line"]) <= len(text.splitlines())
    assert not target.exists()


def test_missing_model_file(tmp_path, capsys):
    """A model file that does not exist: status 2 and a message naming it."""
    path = tmp_path / "nope.exp"
    assert_input_error(capsys, "generate", path, mentions=str(path))


def test_model_that_is_a_directory(tmp_path, capsys):
    """A directory given as the model: status 2, clean message."""
    assert_input_error(capsys, "generate", tmp_path, mentions="directory")


def test_zero_inertia_warning_goes_to_stderr(tmp_path, capsys):
    """A DOF with no mass or inertia is a warning on stderr; generation still succeeds."""
    model = tmp_path / "w.exp"
    model.write_text(LEVER_TEXT.replace("B2,\tm,\t0,\tJ2,", "B2,\tm,\t0,\t0,"), encoding="utf-8")
    status, out, err = run(capsys, "generate", model)
    assert status == 0
    assert "warning" in err and "B2.ry" in err
    assert "B1.rz" in out


# --------------------------------------------------------------------------- --set


@pytest.mark.parametrize(
    "items, name, expected",
    [
        (["kLU=5e5"], "kLU", 5e5),
        (["kLU = 500 kN/m"], "kLU", 5e5),
        (["kLU=0.5 MN/m"], "kLU", 5e5),
        (["b=95 mm"], "b", 0.095),
        (["b=0.5"], "b", 0.5),
        (["b=1", "b=2"], "b", 2.0),  # the last one wins
    ],
)
def test_set_values_reach_the_json(tmp_path, capsys, items, name, expected):
    """``--set`` values (a number in SI, or with a unit) appear among the parameter
    values of the JSON output and do not change the symbolic matrices."""
    target = tmp_path / "lever.json"
    argv = ["generate", LEVER, "--format", "json", "-o", target]
    for item in items:
        argv += ["--set", item]
    status, _, err = run(capsys, *argv)
    assert status == 0, err
    data = json.loads(target.read_text())
    assert data["values"][name] == pytest.approx(expected, rel=1e-12)
    assert name in data["parameters"]


@pytest.mark.parametrize("item", ["x", "1a=2", "=3", "a b=1", "kLU=", "kLU"])
def test_malformed_set_is_a_one_line_usage_error(capsys, item):
    """A ``--set`` that is not ``NAME=VALUE`` exits 2 with one line naming ``--set``."""
    err = assert_input_error(capsys, "generate", LEVER, "--set", item, mentions="--set")
    assert len(err.splitlines()) == 1


@pytest.mark.parametrize(
    "model, item, mentions",
    [
        (LEVER, "kLU=__import__('os')", "kLU"),
        (LEVER, "kLU=nan", "kLU"),
        (LEVER, "kLU=inf", "kLU"),
        (LEVER, "kLU=1/0", "kLU"),
        (LEVER, "kLU=1e999", "kLU"),
        (LEVER, "kLU=5 blorbs", "kLU"),  # an unknown unit
        (LEVER, "kLUU=5e5", "kLU"),  # no such parameter: the closest name is suggested
        (STEERED, "ky1=4 s", "ky1"),  # a time where a stiffness (N/m) is expected
        (STEERED, "gamma=0.05", "Gamma"),
    ],
)
def test_bad_set_value_is_refused(tmp_path, capsys, model, item, mentions):
    """A ``--set`` value that is not a finite number of the parameter's dimension, or a
    name the model does not have, exits 2 naming it; nothing is written."""
    target = tmp_path / "out.json"
    assert_input_error(capsys, "generate", model, "--set", item, "--format", "json", "-o", target, mentions=mentions)
    assert not target.exists()


def test_rail_model_generates_with_overrides(capsys):
    """The steered car with a ``--set``: rail terms included, the value applied."""
    status, out, err = run(capsys, "generate", STEERED, "--set", "Gamma=0.05", "--format", "json")
    assert status == 0, err
    assert json.loads(out)["values"]["Gamma"] == pytest.approx(0.05)
