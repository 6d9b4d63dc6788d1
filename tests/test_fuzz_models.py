"""Fuzzing of model files (issue 17): generated TOML models with extreme and broken
values, and the bundled examples (TOML and classic) mutated line by line, through
``generate``, ``convert``, ``eigen`` and ``simulate``.  Every run ends with status 0, 1
or 2 and ``error:`` lines, never a traceback, within a time bound; a refused run leaves
its destination as it was; every file ``convert`` writes loads back.

Derandomized (``tests/fuzz_support.py``): a failure prints the example and reproduces.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from hypothesis import given
from hypothesis import strategies as st

from cli_support import CONVENTIONAL, LEVER
from express.io import load_model
from fuzz_support import NASTY_NUMBERS, assert_untouched, check, fuzz, mutated, snapshot

pytestmark = pytest.mark.slow

EXAMPLES = Path(CONVENTIONAL).parent
SINUSOID = EXAMPLES / "tracks" / "straight_sinusoid.toml"
EARLIER = b"an earlier result\n"

# ------------------------------------------------------------------ generated models

BAD_VALUES = st.one_of(
    st.sampled_from(["2*m", "k/2", "-k", "m - m", "k*c", "(m + k)^2", "1/m", "m/0", "0", "-1", "1e300", "1e-300",
                     "1e308*10", "k^64", "((((k))))", "nope", "m(", "1 kg"]),
    st.floats(allow_nan=True, allow_infinity=True, width=64).map(repr),
    st.sampled_from(NASTY_NUMBERS),
)
BAD_QUANTITIES = st.sampled_from(['"4 s"', '"1 furlong"', "0", "-5", "1e300", '"0 kg"', '"nan kg"', "[1]", "true",
                                  '{ value = 2, unit = "kN/m" }', '{ value = "x" }', '"1e999 m"', '"k*"'])
DOFS = st.lists(st.sampled_from(["x", "y", "z", "rx", "ry", "rz", "q"]), min_size=0, max_size=4)
#: A valid single-wheelset vehicle (a car body on a wheelset), every value of which
#: the strategy may replace by a bad one.
GOOD = {"m": '"1400 kg"', "M": '"8 t"', "k": '"1 MN/m"', "c": '"10 kN*s/m"', "I": '"600 kg*m^2"', "f": '"7.8 MN"',
        "v": '"100 km/h"', "G": '"1067 mm"', "mu": "0.3", "P": '"50 kN"'}


def _quoted(value: str) -> str:
    return value if value[:1] in '"[{' or value in ("nan", "inf", "-inf", "true") else f'"{value}"'


@st.composite
def maybe(draw, good: str, bad) -> str:
    """``good`` fourteen times in fifteen, else a drawn bad value (a model of some
    twenty-five values then has one or two bad ones, or none)."""
    return good if draw(st.integers(0, 14)) < 14 else _quoted(draw(bad))  # Hypothesis favours small integers


@st.composite
def toml_models(draw) -> str:
    """A car body on a wheelset, with a spring and a damper between them and rail
    data; each value, DOF list and reference valid fourteen times in fifteen."""
    lines = ["[model]", 'name = "fuzz"', "", "[parameters]"]
    for name, value in GOOD.items():
        if draw(st.integers(0, 19)) < 19:
            lines.append(f"{name} = {draw(maybe(value, BAD_QUANTITIES))}")
    for body, mass in (("B", '"M"'), ("W", '"m"')):
        dofs = draw(st.one_of(*[st.just(["y", "rz"])] * 6, DOFS))
        lines += ["", f"[bodies.{body}]", f"mass = {draw(maybe(mass, BAD_VALUES))}",
                  f'inertia = [{draw(maybe("0", BAD_VALUES))}, 0, "I"]', f"dofs = {dofs!r}".replace("'", '"')]
    offset = draw(maybe("0", BAD_VALUES))
    host = draw(maybe('"W"', st.sampled_from(["B", "G0", "X"])))
    lines += ["", "[grounds.G0]", "", "[points.PB]", 'body = "B"', f"offset = [0, {offset}, 0]",
              "", "[points.PW]", f"body = {host}"]
    for element, key, value in (("S", "stiffness", '"k"'), ("D", "damping", '"c"')):
        direction = draw(maybe('"y"', st.sampled_from(["rz", "q", "2", "x"])))
        lines += ["", f"[elements.{element}]", 'from = "PB"', 'to = "PW"', f"direction = {direction}",
                  f"{key} = {draw(maybe(value, BAD_VALUES))}"]
    if draw(st.integers(0, 9)) < 9:
        wheelsets = draw(st.sampled_from([["W"]] * 10 + [["W", "W"], ["B"], ["W", "B"], ["Z"], []]))
        lines += ["", "[rail]", f"wheelsets = {wheelsets!r}".replace("'", '"'), "[rail.wheel_rail]"]
        for key, value in (("f1", "f"), ("f2", "f"), ("conicity", "0.1"), ("r0", "0.43"), ("b", "0.56"),
                           ("flange_clearance", "0.006"), ("rail_stiffness", "2e7"), ("friction", "mu"),
                           ("wheel_load", "P")):
            lines.append(f"{key} = {draw(maybe(_quoted(value), BAD_VALUES))}")
    return "\n".join(lines) + "\n"


@fuzz(60)
@given(text=toml_models())
def test_generated_models_end_cleanly(tmp_path_factory, text):
    """Each generated model through ``generate``, ``eigen`` and a linear ``simulate``."""
    folder = tmp_path_factory.mktemp("model")
    model = folder / "model.toml"
    model.write_text(text, encoding="utf-8")
    for command in ("generate", "eigen", "simulate"):
        target = folder / ("run.csv" if command == "simulate" else "out.txt")
        target.write_bytes(EARLIER)
        argv = [command, model]
        if command == "generate":
            argv += ["-o", target]
        elif command == "eigen":
            argv += ["--json"]
        else:
            argv += ["--linear", "--track", SINUSOID, "--speed", "300", "--dt", "0.02", "-o", target]
        before = snapshot(folder)
        status, _, _ = check(argv)
        if status != 0:
            assert_untouched(before, folder, argv, diverged=status == 1)
        elif command != "eigen":
            assert target.read_bytes() != EARLIER


# ------------------------------------------------------------------ mutated examples


@fuzz(60)
@given(data=st.data(), name=st.sampled_from(["conventional.toml", "forced-steering.toml", "manchester.toml"]))
def test_mutated_toml_examples_convert_cleanly_and_load_back(tmp_path_factory, data, name):
    """``convert`` reads the whole model (every value, the parameter graph, the ranges):
    refused with status 2 and nothing written, or written in a form that loads back."""
    text = data.draw(mutated((EXAMPLES / name).read_text(encoding="utf-8")), label="model")
    folder = tmp_path_factory.mktemp("convert")
    model = folder / name
    model.write_text(text, encoding="utf-8")
    target = folder / "converted.toml"
    target.write_bytes(EARLIER)
    before = snapshot(folder)
    status, _, _ = check(["convert", model, "-o", target])
    if status != 0:
        assert_untouched(before, folder, name)
    else:
        converted = load_model(target)
        assert converted.parameters.keys() == load_model(model).parameters.keys()


@fuzz(30)
@given(data=st.data())
def test_mutated_vehicle_analyses_end_cleanly(tmp_path_factory, data):
    """The eigen analysis of a mutated car: a result, no valid result or bad input."""
    text = data.draw(mutated(Path(CONVENTIONAL).read_text(encoding="utf-8"), most=2), label="model")
    folder = tmp_path_factory.mktemp("eigen")
    model = folder / "car.toml"
    model.write_text(text, encoding="utf-8")
    check(["eigen", model, "--json"])


@fuzz(50)
@given(data=st.data(), name=st.sampled_from(["lever.exp", "forced-steering.exp"]),
       command=st.sampled_from(["generate", "convert"]))
def test_mutated_classic_examples_end_cleanly(tmp_path_factory, data, name, command):
    text = data.draw(mutated((EXAMPLES / name).read_text(encoding="utf-8")), label="model")
    folder = tmp_path_factory.mktemp("classic")
    model = folder / name
    model.write_text(text, encoding="utf-8")
    target = folder / ("out.toml" if command == "convert" else "out.txt")
    target.write_bytes(EARLIER)
    before = snapshot(folder)
    status, _, _ = check([command, model, "-o", target])
    if status != 0:
        assert_untouched(before, folder, name)
    elif command == "convert":
        load_model(target)  # every file convert writes loads back


IDENTIFIERS = st.text(alphabet=st.characters(blacklist_categories=("Cs",)), min_size=1, max_size=12)


@fuzz(40)
@given(title=IDENTIFIERS, label=IDENTIFIERS, stem=IDENTIFIERS.filter(lambda s: "/" not in s and "\x00" not in s
                                                                     and s not in (".", "..")))
def test_convert_writes_files_that_load_back_whatever_the_names(tmp_path_factory, title, label, stem):
    """Titles and labels with newlines, quotes, DEL, unicode; file names that are not
    identifiers: the converted file loads back with the same title and label."""
    folder = tmp_path_factory.mktemp("names")
    text = Path(LEVER).read_text(encoding="utf-8")
    model = folder / f"{stem}.exp"
    try:
        model.write_text(text, encoding="utf-8")
    except (OSError, UnicodeEncodeError):
        return  # a name the file system refuses
    target = folder / "out.toml"
    status, _, _ = check(["convert", model, "-o", target])
    assert status == 0
    converted = target.read_text(encoding="utf-8")
    tidy = converted.replace('[bodies.B1]\n', f'[bodies.B1]\nlabel = {_toml_string(label)}\n', 1)
    tidy = tidy.replace("[parameters]", f"title = {_toml_string(title)}\n\n[parameters]", 1)
    (folder / "labelled.toml").write_text(tidy, encoding="utf-8")
    again = folder / "again.toml"
    assert check(["convert", folder / "labelled.toml", "-o", again])[0] == 0
    reread = load_model(again)
    assert reread.title == title and reread.body("B1").label == label


def _toml_string(text: str) -> str:
    escaped = text.replace("\\", "\\\\").replace('"', '\\"')
    return '"' + "".join(c if c.isprintable() or c == " " else f"\\u{ord(c):04x}" if ord(c) < 0x10000
                         else f"\\U{ord(c):08x}" for c in escaped) + '"'


@fuzz(30)
@given(data=st.data())
def test_a_classic_file_written_by_express_cut_at_any_line_is_refused(tmp_path_factory, data):
    """Truncation (issue 26): ``forced-steering.exp`` (written by convert: its header lists
    every id) cut after any of its lines but the last is refused, saying where it stops."""
    lines = (EXAMPLES / "forced-steering.exp").read_text(encoding="utf-8").splitlines(keepends=True)
    kept = data.draw(st.integers(1, len(lines) - 1), label="lines kept")
    folder = tmp_path_factory.mktemp("cut")
    model = folder / "cut.exp"
    model.write_text("".join(lines[:kept]), encoding="utf-8")
    status, _, err = check(["generate", model, "-o", folder / "out.txt"])
    assert status == 2 and "stops early" in err, (kept, err)
    assert sorted(p.name for p in folder.iterdir()) == ["cut.exp"]
