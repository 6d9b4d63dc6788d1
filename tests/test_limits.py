"""Issue 17: bounded work, physical valid ranges, refused input, no traceback.

The limits of :mod:`express.base.limits` (expression size, nesting, exponents, constants,
file size, model size; overrides through environment variables), the valid ranges of
:mod:`express.model.parameter_ranges` (``--set mu=0``, ``G=0``, ``ky1=1e300``, a car body
listed as a wheelset), the honest exit statuses of the issue's cases (``ky2=-150000``
and ``cy2=-300000`` diverge: status 1; ``mc=0`` is a DOF without mass: status 2), and
the error texts (a short excerpt of a file at most, one line per problem).
"""

from __future__ import annotations

import importlib.util
import math
import time
from pathlib import Path

import numpy as np
import pytest
import tomllib

from cli_support import CONVENTIONAL, LEVER, run
from express.base.diagnostics import ModelError, UsageError
from express.base.expressions import ExpressionError, parse_expression
from express.base.limits import LIMITS, limit, read_input_text
from express.io import load_model, parse_classic, parse_toml_model
from express.rail.contact import creep_coefficients
from express.rail.kalker import kalker_coefficients
from express.rail.nonlinear import saturation_factor

EXAMPLES = Path(CONVENTIONAL).parent
CAR = Path(CONVENTIONAL).read_text(encoding="utf-8")


def errors(err: str) -> list[str]:
    return [line for line in err.splitlines() if line.startswith("error: ")]


# ------------------------------------------------------------------ expressions


@pytest.mark.parametrize(
    "text, message",
    [
        ("(" * 450 + "1" + ")" * 450, "nested more than 100 levels"),
        ("-" * 300 + "1", "nested more than 100 levels"),
        ("(" * 101 + "a" + ")" * 101, "nested more than 100 levels"),
        ("mc*(2^63)^64", "beyond the range of a double"),
        ("9e308", "beyond the range of a double"),
        ("1e308*10", "beyond the range of a double"),
        ("1e-300/1e100", "beyond the range of a double"),
        ("a^65", "at most 64"),
        ("2^2^2^2^2^2", "at most 64"),
        ("x" * 1001, "EXPRESS_MAX_EXPRESSION"),
    ],
)
def test_expressions_beyond_the_limits_are_refused_at_once(text, message):
    start = time.perf_counter()
    with pytest.raises(ExpressionError, match=message):
        parse_expression(text)
    assert time.perf_counter() - start < 1.0


@pytest.mark.parametrize("text, value", [("(" * 100 + "2" + ")" * 100, 2), ("-" * 99 + "1", -1), ("1e308", 1e308),
                                         ("2^-64", 2.0**-64), ("(2^63)^4/(2^63)^4", 1)])
def test_expressions_within_the_limits_are_read(text, value):
    assert float(parse_expression(text)) == value


def test_expression_length_limit_has_an_override(monkeypatch):
    text = "+".join(["a"] * 600)  # 1199 characters
    with pytest.raises(ExpressionError, match="longer than the limit of 1000"):
        parse_expression(text)
    monkeypatch.setenv("EXPRESS_MAX_EXPRESSION", "2000")
    assert parse_expression(text) == 600 * parse_expression("a")


def test_a_bad_override_is_a_usage_error(monkeypatch):
    monkeypatch.setenv("EXPRESS_MAX_BODIES", "lots")
    with pytest.raises(UsageError, match="EXPRESS_MAX_BODIES='lots': expected a positive whole number"):
        limit("bodies")


def test_the_huge_exponent_model_of_the_issue_is_refused_within_a_second(tmp_path, capsys):
    """``mass = "mc*(2^63)^64"`` took 74 s to generate; now it is bad input, at once."""
    path = tmp_path / "big.toml"
    path.write_text(CAR.replace('mass = "mc"', 'mass = "mc*(2^63)^64"'), encoding="utf-8")
    start = time.perf_counter()
    status, _, err = run(capsys, "generate", path)
    assert status == 2 and time.perf_counter() - start < 5
    assert 'body CB: mass "mc*(2^63)^64"' in err and "range of a double" in err


# ------------------------------------------------------------------ files and model size


def test_model_size_limits_name_the_item_and_the_variable(monkeypatch, capsys):
    monkeypatch.setenv("EXPRESS_MAX_BODIES", "6")  # the car has 7: 1 + 2 bogie instances of 3
    status, _, err = run(capsys, "generate", CONVENTIONAL)
    assert status == 2
    assert errors(err) == [f"error: {CONVENTIONAL}: bodies: 7 bodies, more than the limit of 6 bodies "
                           "(raise it with the environment variable EXPRESS_MAX_BODIES)"]
    monkeypatch.setenv("EXPRESS_MAX_BODIES", "7")
    monkeypatch.setenv("EXPRESS_MAX_ELEMENTS", "4")
    assert run(capsys, "generate", LEVER, "-o", "/dev/null")[0] == 0  # the lever has 4 elements
    monkeypatch.setenv("EXPRESS_MAX_ELEMENTS", "3")
    with pytest.raises(ModelError, match="4 elements, more than the limit of 3"):
        parse_classic(Path(LEVER).read_text(encoding="utf-8"), "lever.exp")


def test_a_file_beyond_the_size_limit_is_not_read(tmp_path, monkeypatch):
    monkeypatch.setenv("EXPRESS_MAX_FILE_MB", "1")
    path = tmp_path / "huge.toml"
    path.write_bytes(b"# " + b"x" * (2 * 1024 * 1024) + b"\n")
    with pytest.raises(ModelError, match=r"larger than the limit of 1 MB .*EXPRESS_MAX_FILE_MB"):
        load_model(path)


def test_a_device_as_model_is_refused_by_its_kind_before_it_is_read():
    from express.io.classic import read_classic

    with pytest.raises(ModelError, match=r"/dev/zero: not a regular file but a character device"):
        read_classic("/dev/zero")


def _train_toml(cars: int) -> str:
    spec = importlib.util.spec_from_file_location("make_vehicles", EXAMPLES / "make_vehicles.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module.vehicle_toml(True, cars=cars)


@pytest.mark.parametrize("cars", [100, 150])
def test_long_trains_pass_the_default_limits(tmp_path, monkeypatch, cars):
    """Issue 16's 100-car train (and a 150-car one) is read without any
    ``EXPRESS_MAX_*`` variable: the reader's own count, on the parsed file, is within
    every default.  (Generating the train is ``benchmarks/bench_scaling.py``'s work.)"""
    for spec in LIMITS.values():
        monkeypatch.delenv(spec.variable, raising=False)
    from express.io.toml_model import _size_problems

    path = tmp_path / f"train{cars}.toml"
    path.write_text(_train_toml(cars), encoding="utf-8")
    data = tomllib.loads(read_input_text(path))  # within the file-size limit, or this raises
    counts = {key: len(data[key]) for key in ("bodies", "elements", "points")}
    assert counts == {"bodies": 11 * cars, "elements": 56 * cars - 2, "points": 112 * cars - 4}
    assert _size_problems(data, str(path)) == []
    assert all(counts[key] <= limit(key) for key in counts)


def test_a_train_beyond_the_defaults_is_refused_by_its_size(monkeypatch):
    """The defaults stay a bound: 179 cars of the forced-steering car exceed the
    elements and connection-point limits (checked on counts, not a generated file)."""
    for spec in LIMITS.values():
        monkeypatch.delenv(spec.variable, raising=False)
    assert limit("bodies") >= 11 * 178 and limit("elements") >= 56 * 178 - 2 and limit("points") >= 112 * 178 - 4
    assert limit("elements") < 56 * 179 - 2 and limit("points") < 112 * 179 - 4
    assert limit("bodies") < 11 * 200


def test_deeply_nested_toml_is_a_model_error():
    with pytest.raises(ModelError, match="nested too deeply"):
        parse_toml_model("a = " + "[" * 5000 + "]" * 5000, "deep.toml")


def test_limits_table_is_documented():
    text = (EXAMPLES.parent / "docs" / "reliability.md").read_text(encoding="utf-8")
    for spec in LIMITS.values():
        assert spec.variable in text and str(spec.default) in text.replace(" ", "").replace(",", "")


# ------------------------------------------------------------------ valid ranges


@pytest.mark.parametrize(
    "assignment, expected",
    [
        ("mu=0", "parameter mu: set to 0, outside the valid range 0 < friction <= 1 of its use as wheelset W1 "
                 "friction and 3 more uses"),
        ("G=0", "parameter G: set to 0 m, outside the valid range 0 < cant_base <= 5 m"),
        ("ky1=1e300", "parameter ky1: set to 1e+300 N/m, outside the valid range -1e+15 <= stiffness <= 1e+15 N/m"),
        ("mc=-1", "parameter mc: set to -1 kg, outside the valid range 0 <= mass <= 1e+08 kg"),
        ("Gamma=-0.1", "0 <= conicity <= 1"),
        ("delta=0.2", "0 <= flange_clearance <= 0.1 m"),
        ("v=0", "0 < speed <= 1000 km/h"),
        ("Emod=0", "youngs_modulus must be a positive finite number"),
        ("P0=1000", "body W1 weighs 13.734 kN (1.4 t), more than its two wheels carry (2 x wheel_load = 2 kN)"),
        ("mc=0", "M cannot be inverted: DOFs CB.x, CB.y have zero (or negative) mass or inertia"),
        ("gamma=0.05", "parameter gamma: no such parameter in the model; did you mean Gamma?"),
        ("ky1=4 s", "ky1"),
    ],
)
def test_values_outside_their_valid_range_are_bad_input(capsys, assignment, expected):
    """Each case of the issue is refused with status 2 and one line naming the value,
    its use and its range; ``mu=0`` and ``G=0`` no longer reach a division by zero."""
    status, _, err = run(capsys, "eigen", CONVENTIONAL, "--set", assignment)
    assert status == 2, err
    assert "Traceback" not in err and "internal error" not in err
    assert any(expected in line for line in errors(err)), err


def test_simulate_refuses_a_zero_friction_before_the_march(capsys):
    status, _, err = run(capsys, "simulate", CONVENTIONAL, "--set", "mu=0", "--speed", "300", "--dt", "0.02",
                         "--track", EXAMPLES / "tracks" / "straight_sinusoid.toml")
    assert status == 2 and "0 < friction <= 1" in err and "ZeroDivisionError" not in err


def test_a_value_out_of_range_in_a_file_names_its_line(tmp_path, capsys):
    path = tmp_path / "car.toml"
    path.write_text(CAR.replace('mu = { value = 0.3, unit = "1" }', 'mu = { value = 0.0, unit = "1" }'), encoding="utf-8")
    line = next(n for n, text in enumerate(path.read_text().splitlines(), 1) if text.startswith("mu = "))
    status, _, err = run(capsys, "generate", path)
    assert status == 2
    assert errors(err) == [f"error: {path}:{line}: parameter mu: 0 is outside the valid range 0 < friction <= 1 of "
                           "its use as wheelset W1 friction and 3 more uses (the creep forces saturate at friction "
                           "x wheel load)"]


def test_an_expression_out_of_range_names_the_use(tmp_path):
    text = CAR.replace('friction = "mu"', 'friction = "mu - 0.3"')
    with pytest.raises(ModelError) as info:
        parse_toml_model(text, "car.toml")
    assert 'car.toml:89: wheelset W1: friction "mu - 3/10" = 0 is outside the valid range 0 < friction <= 1' in str(info.value)


def test_a_negative_stiffness_warns_and_the_analyses_judge(capsys, tmp_path):
    """``ky2=-150000``: legal as a modelling device, so a warning; the eigen analysis
    reports the unstable mode (status 0); the simulation diverges (status 1) and
    replaces nothing (the issue had Q = 1.6e22 N with status 0)."""
    status, out, err = run(capsys, "eigen", CONVENTIONAL, "--set", "ky2=-150000")
    assert status == 0 and "UNSTABLE" in out
    assert [line for line in err.splitlines() if line.startswith("warning: ")] == [
        f"warning: {CONVENTIONAL}: parameter ky2: a negative stiffness (TSD T1_syL stiffness and 3 more uses) is a "
        "modelling device, not a physical element; the analyses check their own results (a diverging simulation "
        "ends with status 1)"]
    target = tmp_path / "run.csv"
    target.write_text("earlier\n")
    status, _, err = run(capsys, "simulate", CONVENTIONAL, "--set", "ky2=-150000", "--dt", "0.01", "-o", target)
    assert status == 1 and "diverged" in err and "least-damped eigenvalue" in err
    assert target.read_text() == "earlier\n"


@pytest.mark.parametrize("assignment", ["cy2=-300000", "ky1=1e14"])
def test_runs_that_leave_the_range_of_validity_exit_1_or_succeed_finite(capsys, tmp_path, assignment):
    target = tmp_path / "run.csv"
    status, _, err = run(capsys, "simulate", CONVENTIONAL, "--set", assignment, "--dt", "0.01", "-o", target,
                         "--linear")
    assert status in (0, 1), err
    if status == 0:
        data = np.genfromtxt(target, delimiter=",", names=True)
        assert all(np.isfinite(data[name]).all() for name in data.dtype.names)
    else:
        assert "diverged" in err and not target.exists()


# ------------------------------------------------------------------ wheelsets


@pytest.mark.parametrize(
    "wheelsets, expected",
    [
        ('["W1", "W2", "W3", "W4", "W1"]', "wheelset W1: listed twice in rail.wheelsets"),
        ('["W1", "W2", "W3", "W4", "CB"]', "wheelset CB: body CB weighs 294.3 kN (30 t), more than its two wheels carry"),
        ('["W1", "W2", "W3", "W4", "T9"]', "wheelset T9: unknown body"),
    ],
)
def test_wheelset_lists_are_checked(wheelsets, expected):
    text = CAR.replace('wheelsets = ["W1", "W2", "W3", "W4"]', f"wheelsets = {wheelsets}")
    with pytest.raises(ModelError) as info:
        parse_toml_model(text, "car.toml")
    assert expected in str(info.value)


def test_a_body_without_the_wheelset_dofs_is_not_a_wheelset():
    text = CAR.replace('dofs = ["x", "y", "rx", "rz"]', 'dofs = ["x", "rx"]', 1)
    text = text.replace('wheelsets = ["W1", "W2", "W3", "W4"]', 'wheelsets = ["W1", "W2", "W3", "W4", "CB"]')
    with pytest.raises(ModelError, match="wheelset CB: a wheelset body needs the y and rz DOFs"):
        parse_toml_model(text, "car.toml")


# ------------------------------------------------------------------ contact functions


@pytest.mark.parametrize(
    "arguments",
    [(1e-300, 1e-300, 1e-300, 5e-324, 0.0), (1e-300, 1e-300, 1e-300, 1e-300, 0.0), (5e4, 0.43, 0.3, 0.0, 0.3),
     (5e4, 0.43, 0.3, 206e9, 0.6), (math.nan, 0.43, 0.3, 206e9, 0.3)],
)
def test_contact_functions_refuse_degenerate_data_with_a_value_error(arguments):
    with pytest.raises(ValueError):
        creep_coefficients(*arguments)


def test_a_degenerate_contact_ellipse_is_a_value_error():
    with pytest.raises(ValueError, match="degenerate contact ellipse"):
        kalker_coefficients(1e-300, 1e300, 0.3)


def test_creep_saturation_refuses_a_zero_limit():
    with pytest.raises(ValueError, match="mu N must be positive"):
        saturation_factor(np.array([1.0, 2.0]), np.array([1.0, 0.0]))


# ------------------------------------------------------------------ error texts and convert


def test_a_profile_that_is_not_a_profile_is_quoted_once_and_briefly(tmp_path, capsys):
    """A file the user did not write (``/etc/passwd`` given as a profile) is quoted in
    one short excerpt; at most 20 bad rows are listed, then a count."""
    secret = tmp_path / "secret.csv"
    secret.write_text("\n".join(f"user{i}:x:{i}:{i}:Secret Person {i}:/home/user{i}:/bin/sh" for i in range(40)) + "\n")
    for argv in (["conicity", secret, "60E1"], ["conicity", "--delta-r", secret], ["contact-geometry", secret, "60E1"]):
        status, _, err = run(capsys, *argv)
        assert status == 2
        lines = errors(err)
        assert len(lines) <= 23
        quoted = [line for line in lines if "Secret Person" in line or "user1:" in line]
        assert len(quoted) <= 1 and all(len(line) < len(str(secret)) + 200 for line in lines)
        assert "40 bad rows in all" in err or "39 bad rows in all" in err


def test_convert_loads_back_names_with_newlines_quotes_del_and_unicode(tmp_path, capsys):
    text = CAR.replace('title = "The same car', 'title = "A\\n\\"quoted\\" \\u007f é 車 \\u2028 car').replace(
        'label = "car body"', 'label = "body \\t\\"B\\" \\u0000"')
    model = tmp_path / "weird car é.toml"
    model.write_text(text, encoding="utf-8")
    target = tmp_path / "out.toml"
    status, _, err = run(capsys, "convert", model, "-o", target)
    assert status == 0, err
    original, converted = load_model(model), load_model(target)
    assert converted.title == original.title and "\x7f" in converted.title
    assert converted.body("CB").label == original.body("CB").label


def test_convert_keeps_gravity(tmp_path, capsys):
    target = tmp_path / "man.toml"
    assert run(capsys, "convert", EXAMPLES / "manchester.toml", "-o", target)[0] == 0
    assert load_model(target).gravity == load_model(EXAMPLES / "manchester.toml").gravity is not None


def test_a_classic_file_with_a_non_ascii_name_converts(tmp_path, capsys):
    model = tmp_path / "é x.exp"
    model.write_text(Path(LEVER).read_text(encoding="utf-8"), encoding="utf-8")
    status, out, _ = run(capsys, "convert", model)
    assert status == 0 and 'name = "model___x"' in out


@pytest.mark.parametrize("text", ['[bodies.B]\nmass = 1\n'])
def test_a_model_without_dofs_is_bad_input_for_the_analyses(tmp_path, capsys, text):
    """Bodies without DOFs (an empty file, found by the fuzzer, is refused by the reader:
    tests/test_reliability.py)."""
    path = tmp_path / "empty.toml"
    path.write_text(text)
    for command in ("eigen", "frf"):
        status, _, err = run(capsys, command, path)
        assert status == 2 and errors(err) == [f"error: {path}: model: no DOFs: no body has a DOF, there is nothing "
                                               "to analyse"]


@pytest.mark.parametrize(
    "argv, status, expected",
    [
        (["--set", "ky2=-150000"], 1, "the vehicle is unstable at 120.0 km/h (least-damped eigenvalue 3.786 + "
                                      "0.02735j 1/s, car body lateral"),
        (["--speed", "520"], 1, "the vehicle is unstable at 520.0 km/h (least-damped eigenvalue 1.585 + 25.77j 1/s, "
                                "hunting"),
        (["--speed", "400"], 0, ""),  # below the critical speed, 420.8 km/h
    ],
)
def test_a_frequency_response_of_an_unstable_vehicle_is_no_valid_result(capsys, argv, status, expected):
    """A steady state exists only when every free motion decays: above the critical
    speed, or with a negative lateral stiffness, frf exits 1 naming the mode."""
    code, _, err = run(capsys, "frf", CONVENTIONAL, "--points", "8", *argv)
    assert code == status, err
    assert expected in err


def test_check_model_refuses_a_wheelset_listed_twice_in_a_model_built_in_python():
    from dataclasses import replace

    from express.model.checks import check_model

    car = load_model(CONVENTIONAL)
    rail = replace(car.rail, wheelsets=car.rail.wheelsets + car.rail.wheelsets[:1])
    assert [str(p) for p in check_model(replace(car, rail=rail))] == [f"{CONVENTIONAL}:89: wheelset W1: listed twice"]


def test_a_huge_model_file_is_refused_before_it_is_read_or_hashed_whole(tmp_path):
    """Issue 36 item 3: a 2 GB model file was hashed whole for the cache's key (2.1 GB of
    memory, 12 s) before the 16 MB refusal; now the size is checked first (a sparse file:
    no disk is used)."""
    import subprocess
    import sys

    path = tmp_path / "huge.toml"
    with open(path, "wb") as stream:
        stream.truncate(2 * 1024**3)
    # measured by a fresh parent of its own: this process's RUSAGE_CHILDREN is the largest of every child so far
    probe = ("import resource, subprocess, sys; "
             "run = subprocess.run([sys.executable, '-m', 'express', 'eigen', sys.argv[1]], capture_output=True, text=True); "
             "print(run.returncode, resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss); sys.stderr.write(run.stderr)")
    run = subprocess.run([sys.executable, "-c", probe, str(path)], capture_output=True, text=True, timeout=120)
    status, peak_kb = (int(x) for x in run.stdout.split())
    assert status == 2 and "file larger than the limit of 16 MB" in run.stderr
    assert peak_kb < 600 * 1024, f"{peak_kb} kB"  # achieved 88 MB (2.1 GB before)
