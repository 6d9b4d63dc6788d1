"""Tests of the ``express`` command line (``express.cli.main``).

``main(argv)`` returns the exit status (argparse's own exits -- ``--version``, usage
mistakes -- arrive as SystemExit and are turned into a status here).  A bad model
prints one ``error: file:line: item: message`` line per problem on stderr and exits 2,
never a Python traceback, and writes nothing.
"""

from __future__ import annotations

import importlib.util
import json
import os
import re
import stat
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

import express
from express.cli import UsageError, main, parse_assignments

ROOT = Path(__file__).resolve().parents[1]
SRC = ROOT / "src"
LEVER = ROOT / "examples" / "lever.exp"
LEVER_TEXT = LEVER.read_text(encoding="utf-8")
FORMATS = {"json": ".json", "matlab": ".m", "python": ".py", "latex": ".tex", "text": ".txt"}
PROBLEM_LINE = re.compile(r"^error: (?P<file>[^:]+):(?P<line>\d+): (?P<item>[^:]+): (?P<message>.+)$")

J1, J2, b, c, kLL, kLU, lLL, lLU, m = sp.symbols("J1 J2 b c kLL kLU lLL lLU m")
K_LEVER = sp.Matrix(
    [[b**2 * (kLU + kLL), b * (lLU * kLU - lLL * kLL)], [b * (lLU * kLU - lLL * kLL), lLU**2 * kLU + lLL**2 * kLL]]
)


def run(argv, capsys):
    """Run ``main``; return (status, stdout, stderr)."""
    capsys.readouterr()
    try:
        status = main([str(a) for a in argv])
    except SystemExit as exit_:
        status = exit_.code if isinstance(exit_.code, int) else (0 if exit_.code is None else 2)
    out, err = capsys.readouterr()
    assert "Traceback" not in out + err
    return status, out, err


@pytest.fixture
def lever_copy(tmp_path):
    path = tmp_path / "lever.exp"
    path.write_text(LEVER_TEXT, encoding="utf-8")
    return path


# --------------------------------------------------------------------------- version


def test_version(capsys):
    """``express --version`` prints the package version and exits 0."""
    status, out, err = run(["--version"], capsys)
    assert status == 0
    assert express.__version__ in out + err
    assert re.search(r"\d+\.\d+\.\d+", out + err)


def test_python_dash_m_version():
    """``python -m express --version`` works from a fresh interpreter."""
    env = dict(os.environ, PYTHONPATH=str(SRC))
    done = subprocess.run(
        [sys.executable, "-m", "express", "--version"], capture_output=True, text=True, env=env, timeout=120
    )
    assert done.returncode == 0, done.stderr
    assert express.__version__ in done.stdout + done.stderr
    assert "Traceback" not in done.stderr


def test_no_command_is_a_usage_error(capsys):
    """``express`` alone is a usage error (status 2), with a usage message."""
    status, out, err = run([], capsys)
    assert status == 2
    assert "usage" in (out + err).lower()


# --------------------------------------------------------------------------- generate


def test_generate_text_to_stdout(capsys):
    """``express generate examples/lever.exp`` writes the text view to stdout: the
    reduced DOFs, the eliminated one, no ``kinf``, and nothing on stderr."""
    status, out, err = run(["generate", LEVER], capsys)
    assert status == 0
    assert "B1.rz" in out and "B2.ry" in out and "B2.x" in out
    assert "kinf" not in out
    assert "b**2*(kLL + kLU)" in out
    assert err == ""


def test_keep_virtual_shows_kinf(capsys):
    """``--keep-virtual`` keeps the virtual DOF and the virtual stiffness (eq. 6)."""
    status, out, _ = run(["generate", LEVER, "--keep-virtual"], capsys)
    assert status == 0
    assert "kinf" in out


def test_keep_virtual_json(tmp_path, capsys):
    """With ``--keep-virtual`` the JSON has three DOFs ending in B2.x, nothing
    eliminated, and K is eq. (6)."""
    target = tmp_path / "lever.json"
    status, _, _ = run(["generate", LEVER, "--keep-virtual", "--format", "json", "-o", target], capsys)
    assert status == 0
    data = json.loads(target.read_text())
    assert data["dofs"] == ["B1.rz", "B2.ry", "B2.x"]
    assert data["eliminated"] == []
    assert "kinf" in data["parameters"]
    K = sp.Matrix([[sp.sympify(e) for e in row] for row in data["K"]])
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
    gives the very same bytes."""
    first_dir, second_dir = tmp_path / "one", tmp_path / "two"
    first_dir.mkdir()
    second_dir.mkdir()
    name = "lever" + FORMATS[fmt]
    status, out, err = run(["generate", LEVER, "--format", fmt, "-o", first_dir / name], capsys)
    assert status == 0, err
    assert out == ""
    data = (first_dir / name).read_bytes()
    assert data.strip()
    status, _, _ = run(["generate", LEVER, "--format", fmt, "-o", second_dir / name], capsys)
    assert status == 0
    assert (second_dir / name).read_bytes() == data
    status, _, _ = run(["generate", LEVER, "--format", fmt, "-o", first_dir / name], capsys)
    assert status == 0
    assert (first_dir / name).read_bytes() == data  # overwriting an earlier output is fine
    assert sorted(p.name for p in first_dir.iterdir()) == [name]  # no temporary left behind


@pytest.mark.parametrize("fmt", sorted(FORMATS))
def test_each_format_to_stdout_matches_the_file(tmp_path, capsys, fmt):
    """Without ``-o`` the same text goes to stdout (MATLAB: same function name)."""
    target = tmp_path / ("lever" + FORMATS[fmt])
    assert run(["generate", LEVER, "--format", fmt, "-o", target], capsys)[0] == 0
    status, out, _ = run(["generate", LEVER, "--format", fmt], capsys)
    assert status == 0
    assert out == target.read_text(encoding="utf-8")


def test_output_file_permissions_follow_the_umask(tmp_path, capsys):
    """The written file gets the usual permissions (0666 minus the umask), not the
    0600 of a private temporary file."""
    umask = os.umask(0o022)
    try:
        target = tmp_path / "lever.json"
        assert run(["generate", LEVER, "--format", "json", "-o", target], capsys)[0] == 0
    finally:
        os.umask(umask)
    assert stat.S_IMODE(target.stat().st_mode) == 0o644


def test_json_follows_the_contract(tmp_path, capsys):
    """The JSON file has the keys of conventions.md with their meaning: DOF names,
    eliminated DOFs, sorted parameters, matrices as SymPy strings (``**`` powers)."""
    target = tmp_path / "lever.json"
    assert run(["generate", LEVER, "--format", "json", "-o", target], capsys)[0] == 0
    data = json.loads(target.read_text(encoding="utf-8"))
    assert data["dofs"] == ["B1.rz", "B2.ry"]
    assert data["eliminated"] == ["B2.x"]
    assert data["parameters"] == ["J1", "J2", "b", "c", "kLL", "kLU", "lLL", "lLU", "m"]
    parse = lambda rows: sp.Matrix([[sp.sympify(entry) for entry in row] for row in rows])  # noqa: E731
    assert all(isinstance(entry, str) for name in ("M", "C", "K") for row in data[name] for entry in row)
    assert "^" not in target.read_text()
    assert parse(data["M"]) == sp.Matrix([[J1 + b**2 * m, 0], [0, J2]])
    assert parse(data["C"]) == sp.Matrix([[b**2 * c, 0], [0, 0]])
    assert sp.simplify(parse(data["K"]) - K_LEVER) == sp.zeros(2, 2)


def test_python_module_evaluates_to_the_closed_form(tmp_path, capsys):
    """The ``--format python`` module imports and its matrices equal the closed form
    evaluated at the same values."""
    target = tmp_path / "lever_eom.py"
    assert run(["generate", LEVER, "--format", "python", "-o", target], capsys)[0] == 0
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
    assert run(["generate", LEVER, "--format", "matlab", "-o", target], capsys)[0] == 0
    first = next(line for line in target.read_text().splitlines() if line.strip() and not line.startswith("%"))
    assert re.match(r"function\s*\[.*\]\s*=\s*leverEOM\s*\(", first), first


def test_matlab_needs_dot_m(tmp_path, capsys):
    """``--format matlab -o x.txt`` is refused (exit 2), nothing written."""
    target = tmp_path / "lever.txt"
    status, _, err = run(["generate", LEVER, "--format", "matlab", "-o", target], capsys)
    assert status == 2
    assert ".m" in err
    assert not target.exists()


def test_unknown_format_is_a_usage_error(capsys):
    """An unknown ``--format`` is refused by the argument parser with status 2."""
    status, _, err = run(["generate", LEVER, "--format", "fortran"], capsys)
    assert status == 2
    assert "fortran" in err


def test_generate_refuses_to_overwrite_the_model(lever_copy, capsys):
    """``generate X -o X`` exits 2 and leaves X unchanged."""
    before = lever_copy.read_bytes()
    status, _, err = run(["generate", lever_copy, "--format", "text", "-o", lever_copy], capsys)
    assert status == 2
    assert lever_copy.read_bytes() == before
    assert "overwrite" in err


@pytest.mark.parametrize("kind", ["directory", "under a file"])
def test_unwritable_output_is_a_clean_error(tmp_path, capsys, kind):
    """An output path that cannot be a file (an existing directory, or a path below a
    regular file) is reported as an error with a non-zero status, not a traceback."""
    if kind == "directory":
        target = tmp_path / "out"
        target.mkdir()
    else:
        (tmp_path / "plain").write_text("x")
        target = tmp_path / "plain" / "lever.json"
    status, _, err = run(["generate", LEVER, "--format", "json", "-o", target], capsys)
    assert status != 0
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
    the form ``error: file:line: item: message`` naming this file, no traceback, and no
    output file."""
    text = LEVER_TEXT
    for old, new in edits:
        assert old in text
        text = text.replace(old, new, 1)
    model = tmp_path / "bad.exp"
    model.write_text(text, encoding="utf-8")
    target = tmp_path / "bad.json"
    status, out, err = run(["generate", model, "--format", "json", "-o", target], capsys)
    assert status == 2
    assert out == ""
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
    status, out, err = run(["generate", path], capsys)
    assert status == 2
    assert str(path) in err
    assert out == ""


def test_model_that_is_a_directory(tmp_path, capsys):
    """A directory given as the model: status 2, clean message."""
    status, _, err = run(["generate", tmp_path], capsys)
    assert status == 2
    assert "directory" in err


def test_convert_of_missing_file(tmp_path, capsys):
    """``convert`` of a missing file: status 2, nothing written."""
    target = tmp_path / "x.toml"
    status, _, err = run(["convert", tmp_path / "nope.exp", "-o", target], capsys)
    assert status == 2
    assert not target.exists()


def test_zero_inertia_warning_goes_to_stderr(tmp_path, capsys):
    """A DOF with no mass or inertia is a warning on stderr; generation still succeeds."""
    model = tmp_path / "w.exp"
    model.write_text(LEVER_TEXT.replace("B2,\tm,\t0,\tJ2,", "B2,\tm,\t0,\t0,"), encoding="utf-8")
    status, out, err = run(["generate", model], capsys)
    assert status == 0
    assert "warning" in err and "B2.ry" in err
    assert "B1.rz" in out


# --------------------------------------------------------------------------- --set


@pytest.mark.parametrize(
    "items, expected",
    [
        (["kLU=5e5"], {"kLU": 5e5}),
        (["kLU = 500 kN/m"], {"kLU": 5e5}),
        (["v=120 km/h"], {"v": 120 / 3.6}),
        (["b=95 mm", "c=2*3"], {"b": 0.095, "c": 6.0}),
        (["Gamma=0.05"], {"Gamma": 0.05}),
        (["a=-1"], {"a": -1.0}),
        (["a=1", "a=2"], {"a": 2.0}),
    ],
)
def test_parse_assignments_good(items, expected):
    """``--set NAME=VALUE``: a number, a number with a unit, or constant arithmetic;
    values in SI; the last one wins."""
    values = parse_assignments(items)
    assert values.keys() == expected.keys()
    for name, value in expected.items():
        assert values[name] == pytest.approx(value, rel=1e-12)


@pytest.mark.parametrize(
    "item",
    ["x", "1a=2", "a=__import__", "a=__import__('os')", "=3", "a=", "a=b", "a=2*b", "a=1/0", "a=nan", "a=inf", "a b=1", "a=1e999", "a=5 furlongs"],
)
def test_parse_assignments_bad(item):
    """Malformed or non-numeric (or non-finite) assignments are a UsageError naming the
    item."""
    with pytest.raises(UsageError) as info:
        parse_assignments([item])
    assert item.split("=")[0].strip() in str(info.value) or item in str(info.value)


@pytest.mark.parametrize("item", ["x", "1a=2", "a=__import__"])
def test_bad_set_through_the_cli(capsys, item):
    """A bad ``--set`` makes ``generate`` exit 2 with a one-line error, no traceback."""
    status, out, err = run(["generate", LEVER, "--set", item], capsys)
    assert status == 2
    assert out == ""
    assert err.startswith("error: ") and "--set" in err


def test_set_values_reach_the_json(tmp_path, capsys):
    """``--set`` values (SI) appear among the parameter values of the JSON output and do
    not change the symbolic matrices."""
    target = tmp_path / "lever.json"
    status, _, _ = run(
        ["generate", LEVER, "--set", "kLU=500 kN/m", "--set", "b=0.5", "--format", "json", "-o", target], capsys
    )
    assert status == 0
    data = json.loads(target.read_text())
    assert data["values"]["kLU"] == pytest.approx(5e5)
    assert data["values"]["b"] == pytest.approx(0.5)
    assert "kLU" in data["parameters"]
