"""Tests of the modern (TOML) model format: reader, writer and ``express convert``.

``express convert`` turns the paper's classic file into TOML that reads back to the
same model and the same equations; the TOML reader understands units and derived
parameters and reports every mistake at once with its line.
"""

from __future__ import annotations

import dataclasses
import math
import os
import subprocess
import sys
from pathlib import Path

import pytest
import sympy as sp
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from express.assembly.generator import generate
from express.base.diagnostics import ModelError
from express.cli import main
from express.io import load_model, model_to_toml, parse_toml_model, read_classic, read_toml_model

ROOT = Path(__file__).resolve().parents[1]
SRC = ROOT / "src"
LEVER = ROOT / "examples" / "lever.exp"
FORCED = ROOT / "examples" / "forced-steering.toml"


def run_cli(argv) -> int:
    """``express.cli.main`` with argparse's SystemExit turned into a status."""
    try:
        return main([str(a) for a in argv])
    except SystemExit as exit_:
        return int(exit_.code or 0)


def records(model):
    """Bodies, grounds, points, elements and pins without ``line`` (the layout differs
    between formats) -- what must survive a conversion."""

    def clean(items):
        return tuple(dataclasses.replace(item, line=None) for item in items)

    return clean(model.bodies), clean(model.grounds), clean(model.points), clean(model.elements), clean(model.pins)


def without_lines(value):
    """``value`` with every ``line`` field of every nested record set to None."""
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        changes = {f.name: without_lines(getattr(value, f.name)) for f in dataclasses.fields(value)}
        if "line" in changes:
            changes["line"] = None
        return dataclasses.replace(value, **changes)
    if isinstance(value, tuple):
        return tuple(without_lines(v) for v in value)
    if isinstance(value, dict):
        return {k: without_lines(v) for k, v in value.items()}
    return value


def convert(source: Path, target: Path) -> str:
    status = run_cli(["convert", source, "-o", target])
    assert status == 0
    return target.read_text(encoding="utf-8")


# A small TOML model (the lever) whose [parameters] table is filled in by each test.
LEVER_TOML = """\
[model]
name = "lever"

[parameters]
{parameters}

[bodies.B1]
mass = 0
inertia = [0, 0, "J1"]
dofs = ["rz"]

[bodies.B2]
mass = "m"
inertia = [0, "J2", 0]
dofs = ["x", "ry"]

[grounds.G1]
[grounds.G2]
[grounds.G3]

[points.C1]
body = "B2"
offset = [0, 0, "lLU"]

[points.C2]
body = "G1"
offset = [0, 0, 0]

[points.C3]
body = "B2"
offset = [0, 0, "-lLL"]

[points.C4]
body = "G2"
offset = [0, 0, 0]

[points.C5]
body = "B2"
offset = [0, 0, 0]

[points.C6]
body = "B1"
offset = [0, "-b", 0]

[points.C8]
body = "G3"
offset = [0, 0, 0]

[elements.T1]
from = "C1"
to = "C2"
direction = "x"
stiffness = "kLU"
damping = 0

[elements.T2]
from = "C3"
to = "C4"
direction = "x"
stiffness = "kLL"

[elements.T3]
from = "C5"
to = "C6"
direction = "x"
stiffness = "kinf"

[elements.T4]
from = "C6"
to = "C8"
direction = 1
damping = "c"

[pins.P1]
virtual = "C5"
non_virtual = "C6"
"""


def lever_toml(parameters: str = "") -> str:
    return LEVER_TOML.replace("{parameters}", parameters)


def line_of(text: str, needle: str, occurrence: int = 0) -> int:
    """1-based line of the ``occurrence``-th line containing ``needle``."""
    numbers = [n for n, line in enumerate(text.splitlines(), 1) if needle in line]
    return numbers[occurrence]


# --------------------------------------------------------------------------- convert


def test_convert_reads_back_to_the_same_model(tmp_path):
    """``express convert lever.exp -o lever.toml`` reads back to the same bodies, grounds,
    CPs, elements and pins (lines and source aside)."""
    converted = tmp_path / "lever.toml"
    convert(LEVER, converted)
    original = read_classic(LEVER)
    again = load_model(converted)
    assert records(again) == records(original)
    assert again.name == original.name


def test_convert_gives_the_same_equations(tmp_path):
    """The converted model generates exactly the same matrices, DOFs and inputs."""
    converted = tmp_path / "lever.toml"
    convert(LEVER, converted)
    for keep_virtual in (False, True):
        a = generate(read_classic(LEVER), keep_virtual=keep_virtual).equations
        b = generate(load_model(converted), keep_virtual=keep_virtual).equations
        assert (a.dofs, a.eliminated, a.inputs, a.parameters) == (b.dofs, b.eliminated, b.inputs, b.parameters)
        assert list(a.matrices) == list(b.matrices)
        for name in a.matrices:
            assert sp.srepr(a.matrices[name]) == sp.srepr(b.matrices[name]), name


def test_convert_is_deterministic(tmp_path):
    """Two conversions give byte-identical files."""
    first = convert(LEVER, tmp_path / "a.toml")
    second = convert(LEVER, tmp_path / "b.toml")
    assert first.encode() == second.encode()
    assert first.endswith("\n") and "\r" not in first


@pytest.mark.slow
def test_convert_is_deterministic_across_processes(tmp_path):
    """Conversions in processes with different hash seeds give identical bytes (no set
    or dict ordering leaks into the output)."""
    outputs = []
    for seed in ("1", "12345"):
        env = dict(os.environ, PYTHONPATH=str(SRC), PYTHONHASHSEED=seed)
        done = subprocess.run(
            [sys.executable, "-m", "express", "convert", str(LEVER)], capture_output=True, env=env, timeout=120
        )
        assert done.returncode == 0, done.stderr
        outputs.append(done.stdout)
    assert outputs[0] == outputs[1]


def test_convert_of_a_converted_file_is_stable(tmp_path):
    """Converting the converted file again gives the same text (apart from the comment
    naming the source): the writer is a fixed point of read-then-write."""
    first = convert(LEVER, tmp_path / "a.toml")
    second = convert(tmp_path / "a.toml", tmp_path / "b.toml")
    assert first.splitlines()[1:] == second.splitlines()[1:]


def test_convert_writes_to_stdout(capsys):
    """Without ``-o`` the TOML goes to standard output and parses as the same model."""
    assert run_cli(["convert", LEVER]) == 0
    out = capsys.readouterr().out
    assert records(parse_toml_model(out, "stdout.toml")) == records(read_classic(LEVER))


def test_convert_refuses_to_overwrite_its_input(tmp_path, capsys):
    """``convert X -o X`` exits 2 and leaves X byte for byte unchanged."""
    source = tmp_path / "lever.exp"
    source.write_bytes(LEVER.read_bytes())
    before = source.read_bytes()
    status = run_cli(["convert", source, "-o", source])
    assert status == 2
    assert source.read_bytes() == before
    assert "overwrite" in capsys.readouterr().err


def test_convert_refuses_to_overwrite_its_input_by_another_name(tmp_path):
    """The same file reached through ``./`` or a symbolic link is still the input."""
    source = tmp_path / "lever.exp"
    source.write_bytes(LEVER.read_bytes())
    link = tmp_path / "link.exp"
    link.symlink_to(source)
    before = source.read_bytes()
    assert run_cli(["convert", source, "-o", tmp_path / "." / "lever.exp"]) == 2
    assert run_cli(["convert", source, "-o", link]) == 2
    assert source.read_bytes() == before
    assert link.is_symlink()


def test_convert_of_a_bad_model_writes_nothing(tmp_path, capsys):
    """A model with errors is not converted: exit 2, no output file."""
    bad = tmp_path / "bad.exp"
    bad.write_text(LEVER.read_text().replace("C1,\tB2,", "C1,\tB9,"), encoding="utf-8")
    target = tmp_path / "bad.toml"
    assert run_cli(["convert", bad, "-o", target]) == 2
    assert not target.exists()
    assert "B9" in capsys.readouterr().err


def test_convert_keeps_a_modern_model(tmp_path):
    """``convert`` of a TOML model (the forced-steering car) reads back to the same
    model -- records, parameter values and rail data (the writer's docstring: "a TOML
    file that reads back to the same model")."""
    converted = tmp_path / "forced.toml"
    convert(FORCED, converted)
    original = read_toml_model(FORCED)
    again = read_toml_model(converted)
    assert records(again) == records(original)
    assert again.title == original.title
    assert (again.rail is None) == (original.rail is None), "the [rail] data was lost in the conversion"
    assert {n: p.value for n, p in again.parameters.items()} == pytest.approx(
        {n: p.value for n, p in original.parameters.items()}
    )
    assert without_lines(again.rail) == without_lines(original.rail)


# --------------------------------------------------------------------------- parameters


@pytest.mark.parametrize(
    "assignment, name, value, unit",
    [
        ('b = "95 mm"', "b", 0.095, "mm"),
        ('kLU = {value=500, unit="kN/m"}', "kLU", 500e3, "kN/m"),
        ('v = "120 km/h"', "v", 120 / 3.6, "km/h"),
        ('kLL = "5.5 MN/m"', "kLL", 5.5e6, "MN/m"),
        ('m = {value = 1.2, unit = "t"}', "m", 1200.0, "t"),
        ('J2 = "0.5 kg*m^2"', "J2", 0.5, "kg*m^2"),
        ('c = "20 kN*s/m"', "c", 20e3, "kN*s/m"),
        ('a = "90 deg"', "a", math.pi / 2, "deg"),
        ("b = 0.5", "b", 0.5, ""),
        ("b = 3", "b", 3.0, ""),
        ('b = "2.5e-1"', "b", 0.25, ""),
    ],
)
def test_parameter_units_are_converted_to_si(assignment, name, value, unit):
    """Parameter values are stored in SI; the unit as written is kept for display."""
    model = parse_toml_model(lever_toml(assignment), "p.toml")
    parameter = model.parameters[name]
    assert parameter.value == pytest.approx(value, rel=1e-12)
    assert parameter.unit == unit


def test_parameter_values_reach_the_equations():
    """Values (SI) and units travel with the generated equations; the matrices stay
    symbolic."""
    model = parse_toml_model(lever_toml('kLU = {value=500, unit="kN/m"}\nb = "95 mm"'), "p.toml")
    equations = generate(model).equations
    assert equations.values["kLU"] == pytest.approx(5e5)
    assert equations.values["b"] == pytest.approx(0.095)
    assert equations.units["kLU"] == "kN/m"
    assert sp.Symbol("kLU") in equations.K.free_symbols


@pytest.mark.parametrize(
    "parameters, expected",
    [
        ('lLU = 0.3\nlLL = "0.2*lLU"', {"lLL": 0.06}),
        ('lLL = "0.2*lLU"\nlLU = "300 mm"', {"lLL": 0.06}),  # order does not matter
        ('a = "e*2"\ne = "d + 1"\nd = 1', {"a": 4.0, "e": 2.0}),
        ('k = "5 kN/m"\nk2 = "k/2"', {"k2": 2500.0}),
        ('l = 2\nJ2 = "m*l^2/12"\nm = "6 kg"', {"J2": 2.0}),
    ],
)
def test_derived_parameters(parameters, expected):
    """A parameter may be an expression of others (in SI), in any order."""
    model = parse_toml_model(lever_toml(parameters), "p.toml")
    for name, value in expected.items():
        assert model.parameters[name].value == pytest.approx(value, rel=1e-12)


def test_undefined_names_are_reported():
    """A derived parameter naming an unknown parameter: each is reported with its line
    and the missing name."""
    text = lever_toml('lLL = "0.2*lLU"\nx = "y + z"\nok = 1')
    with pytest.raises(ModelError) as info:
        parse_toml_model(text, "p.toml")
    problems = {p.item: p for p in info.value.problems}
    assert "lLU" in problems["parameter lLL"].message
    assert problems["parameter lLL"].line == line_of(text, "lLL =")
    assert "y" in problems["parameter x"].message and "z" in problems["parameter x"].message
    assert problems["parameter x"].line == line_of(text, "x =")


@pytest.mark.parametrize(
    "parameters, names",
    [
        ('p = "2*q"\nq = "p/2"', {"p", "q"}),
        ('p = "p + 1"', {"p"}),
        ('a = "b"\nb = "c"\nc = "a"\nd = 1', {"a", "b", "c"}),
    ],
)
def test_circular_definitions_are_reported(parameters, names):
    """Circular definitions are an error naming the parameters involved."""
    text = lever_toml(parameters)
    with pytest.raises(ModelError) as info:
        parse_toml_model(text, "p.toml")
    messages = " ".join(str(p) for p in info.value.problems)
    assert "circular" in messages
    for name in names:
        assert name in messages
    assert all(p.line is not None for p in info.value.problems)


@pytest.mark.parametrize(
    "parameters",
    [
        'a = 0\nb = "1/a"',
        'a = 0\nb = "a^-1"',
        'a = 1\nb = "1/(a - 1)"',
    ],
)
def test_derived_parameter_dividing_by_zero_is_a_model_error(parameters):
    """A derived parameter that divides by a parameter whose value is zero is a
    reported problem (ModelError naming the parameter), not a crash."""
    with pytest.raises(ModelError) as info:
        parse_toml_model(lever_toml(parameters), "p.toml")
    assert any(p.item == "parameter b" for p in info.value.problems)


@pytest.mark.parametrize(
    "parameters, name",
    [
        ('b = "1e999 m"', "b"),
        ("b = inf", "b"),
        ("b = nan", "b"),
        ('b = {value = inf, unit = "m"}', "b"),
        ('b = {value = nan, unit = "m"}', "b"),
        ('a = 1e300\nb = "a*a"', "b"),
    ],
)
def test_non_finite_parameter_values_are_refused(parameters, name):
    """A parameter value must be a finite number: infinities and NaN (written, or by
    overflow) are reported, as they are for values in the model itself."""
    with pytest.raises(ModelError) as info:
        parse_toml_model(lever_toml(parameters), "p.toml")
    assert any(p.item == f"parameter {name}" for p in info.value.problems)


@pytest.mark.parametrize(
    "parameters, fragment",
    [
        ('b = "95 xyzzys"', "xyzzys"),  # (pint knows furlongs)
        ('b = {value = 1, unit = "xyzzy"}', "xyzzy"),
        ('b = "95 kg"', "has unit kg"),  # b is a CP offset: a length
        ('b = {value = "x"}', "value"),
        ('b = {value = 1, colour = "red"}', "colour"),
        ("b = true", "boolean"),
        ("b = [1, 2]", "list"),
        ('_b = 1', "letter"),
        ('b = "__import__(1)"', "__import__"),
    ],
)
def test_bad_parameter_values_are_reported(parameters, fragment):
    """Unknown units, non-numbers and bad names are errors naming the parameter."""
    text = lever_toml(parameters)
    with pytest.raises(ModelError) as info:
        parse_toml_model(text, "p.toml")
    problem = next(p for p in info.value.problems if p.item.startswith("parameter"))
    assert fragment in problem.message
    assert problem.line == line_of(text, parameters.split(" ")[0] + " =")


# --------------------------------------------------------------------------- errors


ERRORS = [
    # (name, old, new, item, line needle, message fragment)
    ("unknown key in a body", 'mass = "m"', 'mass = "m"\ncolour = "red"', "body B2", "colour", 'unknown key "colour"'),
    ("unknown key in an element", 'to = "C2"', 'to = "C2"\nstiffnes = 1', "TSD T1", "stiffnes", 'unknown key "stiffnes"'),
    ("unknown top-level table", "[pins.P1]", "[pinz.P1]\nvirtual = 1\n[pins.P1]", "file", "[pinz.P1]", "pinz"),
    ("bad direction", 'direction = "x"\nstiffness = "kLU"', 'direction = "w"\nstiffness = "kLU"', "TSD T1", 'direction = "w"', "direction"),
    ("direction 4", "direction = 1", "direction = 4", "TSD T4", "direction = 4", "direction"),
    ("offset of 2 values", 'offset = [0, 0, "lLU"]', 'offset = [0, "lLU"]', "CP C1", 'offset = [0, "lLU"]', "list of 3"),
    ("inertia not a list", 'inertia = [0, "J2", 0]', 'inertia = "J2"', "body B2", 'inertia = "J2"', "list of 3"),
    ("position of 4 values", 'dofs = ["rz"]', 'dofs = ["rz"]\nposition = [0, 0, 0, 0]', "body B1", "position", "list of 3"),
    ("unknown DOF", 'dofs = ["rz"]', 'dofs = ["rz", "q"]', "body B1", '"q"', "dofs"),
    ("bad expression", 'stiffness = "kLU"', 'stiffness = "kLU;"', "TSD T1", 'stiffness = "kLU;"', "not a valid expression"),
    ("unknown CP", 'virtual = "C5"', 'virtual = "C55"', "pin P1", "[pins.P1]", "C55"),
    ("unknown body", 'body = "B1"', 'body = "B9"', "CP C6", "[points.C6]", "B9"),
]


@pytest.mark.parametrize(
    "old, new, item, needle, fragment", [e[1:] for e in ERRORS], ids=[e[0] for e in ERRORS]
)
def test_errors_name_file_line_item_and_problem(tmp_path, old, new, item, needle, fragment):
    """Each mistake is reported as ``file:line: item: message`` with the line of the
    offending key (or of the item's table when the problem is about the whole item)."""
    text = lever_toml()
    assert old in text
    text = text.replace(old, new, 1)
    path = tmp_path / "model.toml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(ModelError) as info:
        read_toml_model(path)
    line = line_of(text, needle)
    found = [p for p in info.value.problems if p.item == item and fragment in p.message]
    assert found, [str(p) for p in info.value.problems]
    assert found[0].line == line, (str(found[0]), line)
    assert str(found[0]).startswith(f"{path}:{line}: {item}: ")


def test_all_errors_are_reported_at_once():
    """Several mistakes in different parts of the file are all reported together."""
    text = (
        lever_toml('lLL = "0.2*lX"')
        .replace('mass = "m"', 'mass = "m"\ncolour = "red"')
        .replace('direction = "x"\nstiffness = "kLU"', 'direction = "w"\nstiffness = "kLU"')
        .replace('offset = [0, 0, "lLU"]', 'offset = [0, "lLU"]')
        .replace('inertia = [0, 0, "J1"]', "inertia = 5")
    )
    with pytest.raises(ModelError) as info:
        parse_toml_model(text, "all.toml")
    got = {(p.item, p.line) for p in info.value.problems}
    expected = {
        ("parameter lLL", line_of(text, "lLL =")),
        ("body B2", line_of(text, "colour")),
        ("TSD T1", line_of(text, 'direction = "w"')),
        ("CP C1", line_of(text, 'offset = [0, "lLU"]')),
        ("body B1", line_of(text, "inertia = 5")),
    }
    assert expected <= got, sorted(got, key=str)


@pytest.mark.parametrize(
    "old, new",
    [
        ('mass = "m"', 'mass = "m'),  # unterminated string
        ('mass = "m"', 'mass = "m"\nmass = "m"'),  # duplicate key
        ("[bodies.B2]", "[bodies.B2"),  # unterminated header
        ('dofs = ["x", "ry"]', 'dofs = ["x", "ry"'),  # unterminated array
    ],
)
def test_toml_syntax_errors_give_a_line(old, new):
    """Invalid TOML is one ModelError with the line the TOML parser reports."""
    text = lever_toml().replace(old, new, 1)
    with pytest.raises(ModelError) as info:
        parse_toml_model(text, "syntax.toml")
    (problem,) = info.value.problems
    assert problem.file == "syntax.toml"
    assert problem.line is not None
    first_changed = next(
        n for n, (a, b) in enumerate(zip(lever_toml().splitlines(), text.splitlines()), 1) if a != b
    )
    assert first_changed <= problem.line <= first_changed + 2
    assert "TOML" in str(problem)


def test_inline_tables_are_read_like_tables():
    """``[bodies]`` with ``B1 = { ... }`` is the same as ``[bodies.B1]``; mistakes in it
    point at its line."""
    text = lever_toml().replace(
        '[bodies.B1]\nmass = 0\ninertia = [0, 0, "J1"]\ndofs = ["rz"]',
        '[bodies]\nB1 = { mass = 0, inertia = [0, 0, "J1"], dofs = ["rz"] }',
    )
    model = parse_toml_model(text, "inline.toml")
    assert model.body("B1").dofs == ("rz",)
    bad = text.replace('dofs = ["rz"] }', 'dofs = ["rz"], colour = 1 }')
    with pytest.raises(ModelError) as info:
        parse_toml_model(bad, "inline.toml")
    (problem,) = [p for p in info.value.problems if "colour" in p.message]
    assert problem.line == line_of(bad, "B1 = {")


@pytest.mark.parametrize(
    "extra, odd_id",
    [
        ('[bodies."B.1"]\nmass = "m"\ndofs = ["x"]', "B.1"),  # DOF name "B.1.x" is ambiguous
        ('[points."C 9"]\nbody = "G1"\noffset = [0, 0, 0]', "C 9"),
        ('[elements."T-9"]\nfrom = "C2"\nto = "C4"\ndirection = "x"\nstiffness = "k9"', "T-9"),
        ('[grounds."G#"]', "G#"),
    ],
)
def test_ids_must_be_identifiers_or_survive_conversion(extra, odd_id):
    """Ids are names like ``B1`` (conventions: a DOF is ``<body>.<dof>``). An id such as
    ``"B.1"`` must be refused by the reader with a problem naming it -- or, if it is
    accepted, ``convert`` must write TOML that reads back to the same ids."""
    text = lever_toml() + "\n" + extra + "\n"
    try:
        model = parse_toml_model(text, "ids.toml")
    except ModelError as error:
        assert any(odd_id in str(p) for p in error.problems), [str(p) for p in error.problems]
        return
    written = model_to_toml(model)
    try:
        again = parse_toml_model(written, "again.toml")
    except ModelError as error:
        pytest.fail(f"accepted the id {odd_id!r} but the converted file does not read back:\n{error}")
    assert records(again) == records(model)


# --------------------------------------------------------------------------- fuzzing

_LEVER_TOML_LINES = model_to_toml(load_model("examples/lever.exp")).splitlines()
_NASTY = st.sampled_from(
    ['"__import__(\'os\').system(\'ls\')"', "[1, 2", "{", '"a(b)"', "inf", "nan", "1e999", '"1/0"', '"x^y"',
     "true", '["x", "q"]', '"\u00e9\u6f22"', "-", "= =", "[[bodies]]", '"(a+b)^64"', "[]", "{}"]
)


@st.composite
def _mutated_toml(draw):
    lines = list(_LEVER_TOML_LINES)
    for _ in range(draw(st.integers(1, 4))):
        index = draw(st.integers(0, len(lines) - 1))
        action = draw(st.sampled_from(["delete", "duplicate", "value", "text", "swap"]))
        if action == "delete":
            del lines[index]
        elif action == "duplicate":
            lines.insert(index, lines[index])
        elif action == "value" and "=" in lines[index]:
            key = lines[index].split("=", 1)[0]
            lines[index] = f"{key}= {draw(_NASTY)}"
        elif action == "text":
            lines[index] = draw(st.text(max_size=40))
        elif action == "swap":
            other = draw(st.integers(0, len(lines) - 1))
            lines[index], lines[other] = lines[other], lines[index]
        if not lines:
            break
    return "\n".join(lines) + "\n"


@settings(max_examples=200, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(_mutated_toml())
def test_mutated_toml_gives_a_model_or_the_clean_error(text):
    """A damaged modern file either loads or raises ModelError, whose problems all name
    the file: never another exception."""
    try:
        model = parse_toml_model(text, source="fuzz.toml")
    except ModelError as error:
        assert error.problems and all(problem.file == "fuzz.toml" for problem in error.problems)
    else:
        assert model.source == "fuzz.toml"


@settings(max_examples=200, deadline=None)
@given(st.text(max_size=300))
def test_random_text_as_toml_gives_the_clean_error(text):
    """Random text is never anything but a model or a ModelError."""
    try:
        parse_toml_model(text, source="random.toml")
    except ModelError:
        pass
