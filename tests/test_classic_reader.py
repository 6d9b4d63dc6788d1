"""Tests of the classic (paper Fig. 5) model-file reader, ``express.io.classic``.

The paper's lever file must load as written; separators and headings may vary the way
the contract allows; every mistake is reported at once as ``file:line: item: message``
through ``ModelError.problems``; and no input text whatsoever may crash the reader or
the ``generate`` command with anything but a clean error.
"""

from __future__ import annotations

import dataclasses
import random
import re
from pathlib import Path

import pytest
import sympy as sp
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from express.base.diagnostics import ModelError
from express.cli import main
from express.io import load_model
from express.io.classic import parse_classic, read_classic

ROOT = Path(__file__).resolve().parents[1]
LEVER = ROOT / "examples" / "lever.exp"
LEVER_TEXT = LEVER.read_text(encoding="utf-8")
S = sp.Symbol

# The lever's data rows (paper Fig. 5), section by section, without separators.
LEVER_ROWS = {
    "(1) Body": [
        ["B1", "0", "0", "0", "J1", "0", "0", "0", "0", "0", "1"],
        ["B2", "m", "0", "J2", "0", "1", "0", "0", "0", "1", "0"],
    ],
    "(2) Ground": [["G1"], ["G2"], ["G3"]],
    "(3) CP": [
        ["C1", "B2", "0", "0", "lLU"],
        ["C2", "G1", "0", "0", "0"],
        ["C3", "B2", "0", "0", "-lLL"],
        ["C4", "G2", "0", "0", "0"],
        ["C5", "B2", "0", "0", "0"],
        ["C6", "B1", "0", "-b", "0"],
        ["C7", "B1", "0", "-b", "0"],
        ["C8", "G3", "0", "0", "0"],
    ],
    "(4) TSD": [
        ["T1", "kLU", "0", "C1", "C2", "1"],
        ["T2", "kLL", "0", "C3", "C4", "1"],
        ["T3", "kinf", "0", "C5", "C6", "1"],
        ["T4", "0", "c", "C7", "C8", "1"],
    ],
    "(5) Pinned Joint": [["P1", "C5", "C6"]],
}
HEADINGS = {
    "(1) Body": ["Number,\tMass\tInertia,\t\t\tTranslation,\t\tRotation,", "\t\tx,\ty,\tz,\tx,\ty,\tz,\tx,\ty,\tz,"],
    "(2) Ground": ["Number,"],
    "(3) CP": ["Number,\ton Body,\tLength,", "\t\tx,\ty,\tz,"],
    "(4) TSD": ["Number,\tStiffness,\tDamping,\tCP Number,\t\tDirection", "\t\t\tS_End,\tT_End,"],
    "(5) Pinned Joint": ["Number,\tCP Number,", "\tVirtual,\tNon-Virtual,"],
}


def lever_text(separator: str = ",\t", trailing: str = ",", headings: bool = True, blank: str = "") -> str:
    """The lever file rebuilt with the given field separator and row ending."""
    lines = []
    for header, rows in LEVER_ROWS.items():
        lines.append(header)
        if headings:
            lines += HEADINGS[header]
        for row in rows:
            lines.append(separator.join(row) + trailing)
        lines.append(blank)
    return "\n".join(lines) + "\n"


def strip_lines(model):
    """The model's records with ``line`` (and the model's ``source``) removed, for
    comparing models read from differently laid-out files."""

    def clean(records):
        return tuple(dataclasses.replace(r, line=None) for r in records)

    return (
        clean(model.bodies),
        clean(model.grounds),
        clean(model.points),
        clean(model.elements),
        clean(model.pins),
    )


def line_of(text: str, needle: str) -> int:
    """1-based number of the first line of ``text`` that starts with ``needle``."""
    for number, line in enumerate(text.splitlines(), start=1):
        if line.startswith(needle):
            return number
    raise AssertionError(f"{needle!r} not in text")


# --------------------------------------------------------------------------- the lever


def test_lever_loads_as_in_the_paper():
    """examples/lever.exp is the paper's Fig. 5: 2 bodies, 3 grounds, 8 CPs, 4 TSDs,
    1 pin, with the DOF flags, offsets, directions and expressions as printed."""
    model = read_classic(LEVER)
    assert [b.id for b in model.bodies] == ["B1", "B2"]
    assert [g.id for g in model.grounds] == ["G1", "G2", "G3"]
    assert [p.id for p in model.points] == [f"C{i}" for i in range(1, 9)]
    assert [e.id for e in model.elements] == ["T1", "T2", "T3", "T4"]
    assert [(p.id, p.virtual, p.non_virtual) for p in model.pins] == [("P1", "C5", "C6")]

    b1, b2 = model.bodies
    assert b1.mass == 0 and b1.inertia == (0, 0, S("J1")) and b1.dofs == ("rz",)
    assert b2.mass == S("m") and b2.inertia == (0, S("J2"), 0) and b2.dofs == ("x", "ry")

    points = {p.id: p for p in model.points}
    assert points["C1"].host == "B2" and points["C1"].offset == (0, 0, S("lLU"))
    assert points["C3"].offset == (0, 0, -S("lLL"))
    assert points["C6"].host == "B1" and points["C6"].offset == (0, -S("b"), 0)
    assert points["C8"].host == "G3"

    elements = {e.id: e for e in model.elements}
    assert (elements["T1"].stiffness, elements["T1"].damping) == (S("kLU"), 0)
    assert (elements["T1"].s_end, elements["T1"].t_end) == ("C1", "C2")
    assert (elements["T4"].stiffness, elements["T4"].damping) == (0, S("c"))
    assert all(e.direction == 0 for e in model.elements)  # "1" = x
    assert elements["T3"].stiffness == S("kinf")


def test_lever_records_carry_their_line_numbers():
    """Every record knows the line it came from (for messages)."""
    model = read_classic(LEVER)
    assert model.body("B1").line == line_of(LEVER_TEXT, "B1,")
    assert model.point("C6").line == line_of(LEVER_TEXT, "C6,")
    assert {e.id: e.line for e in model.elements}["T4"] == line_of(LEVER_TEXT, "T4,")
    assert model.pins[0].line == line_of(LEVER_TEXT, "P1,")
    assert model.source == str(LEVER)
    assert model.name == "lever"


def test_rebuilt_lever_matches_the_example_file():
    """Sanity check of this module's own fixture: the rebuilt text reads as the file."""
    assert strip_lines(parse_classic(lever_text())) == strip_lines(read_classic(LEVER))


@pytest.mark.parametrize(
    "separator, trailing",
    [
        (",", ","),  # commas only, trailing comma
        (",", ""),  # commas only, no trailing comma
        ("\t", ""),  # tabs only
        ("\t", "\t"),  # tabs only, trailing tab
        (", ", ", "),  # comma and space
        (" ,\t ", ","),  # spaces around the comma
        (",\t", ",\t"),  # as the paper, trailing tab too
        ("\t,", ","),
    ],
)
def test_separators_and_trailing_commas(separator, trailing):
    """Data rows may be separated by commas or tabs (or both) and may end with a comma:
    the model read is the same whatever the separator."""
    expected = strip_lines(read_classic(LEVER))
    assert strip_lines(parse_classic(lever_text(separator, trailing))) == expected


@pytest.mark.parametrize("headings, blank", [(False, ""), (True, "   "), (True, "\t,\t,")])
def test_headings_and_blank_lines_are_not_data(headings, blank):
    """Column headings and blank (or separator-only) lines are not data."""
    expected = strip_lines(read_classic(LEVER))
    assert strip_lines(parse_classic(lever_text(headings=headings, blank=blank))) == expected


def test_extra_heading_lines_are_ignored():
    """Free text lines such as ``Number, Mass, ...`` anywhere in a section are not data."""
    text = LEVER_TEXT.replace("C5,\tB2,", "Length in metres, see the drawing\nx, y, z\nC5,\tB2,")
    assert strip_lines(parse_classic(text)) == strip_lines(read_classic(LEVER))


def test_windows_line_endings(tmp_path):
    """A file saved with CRLF line endings reads the same."""
    path = tmp_path / "lever.exp"
    path.write_bytes(LEVER_TEXT.replace("\n", "\r\n").encode())
    assert strip_lines(read_classic(path)) == strip_lines(read_classic(LEVER))


def test_utf8_byte_order_mark(tmp_path):
    """A UTF-8 file that starts with a byte-order mark (as Windows Notepad saves plain
    text) reads the same: the BOM must not hide the first section header."""
    path = tmp_path / "lever.exp"
    path.write_bytes(b"\xef\xbb\xbf" + LEVER_TEXT.encode())
    assert strip_lines(read_classic(path)) == strip_lines(read_classic(LEVER))


def test_header_variants():
    """Section headers may have extra spaces and trailing separators."""
    text = LEVER_TEXT.replace("(1) Body", "( 1 )  Body,\t").replace("(5) Pinned Joint", "(5) Pinned Joint\t\t")
    assert strip_lines(parse_classic(text)) == strip_lines(read_classic(LEVER))


def test_expressions_in_values():
    """Values are expressions of parameter names (``2*a``, ``kLU/2``, ``l^2``, ``0.3``)."""
    text = (
        LEVER_TEXT.replace("C1,\tB2,\t0,\t0,\tlLU,", "C1,\tB2,\t0.3,\t2*a,\tl^2,")
        .replace("T1,\tkLU,", "T1,\tkLU/2,")
    )
    model = parse_classic(text)
    assert model.point("C1").offset == (sp.Rational(3, 10), 2 * S("a"), S("l") ** 2)
    assert {e.id: e for e in model.elements}["T1"].stiffness == S("kLU") / 2


# --------------------------------------------------------------------------- errors

ERROR_CASES = [
    # (name, old text, new text, line anchor, item, message pattern)
    ("unknown body in a CP", "C1,\tB2,", "C1,\tB9,", "C1,", "CP C1", r"unknown body or ground.*B9"),
    ("duplicate id", "G3,\n", "G3,\nG2,\n", "G2,", "ground G2", r"duplicate"),
    ("duplicate CP id", "C8,\tG3,", "C7,\tG3,", "C7,", "CP C7", r"duplicate"),
    ("direction 4", "C1,\tC2,\t1,", "C1,\tC2,\t4,", "T1,", "TSD T1", r"direction.*\b4\b"),
    ("direction x", "C1,\tC2,\t1,", "C1,\tC2,\tx,", "T1,", "TSD T1", r"direction.*\bx\b"),
    ("direction 0", "C3,\tC4,\t1,", "C3,\tC4,\t0,", "T2,", "TSD T2", r"direction"),
    ("flag 2", "0,\t0,\t0,\t1,\n", "0,\t0,\t0,\t2,\n", "B1,", "body B1", r"flag.*\b2\b"),
    ("flag a", "B2,\tm,\t0,\tJ2,\t0,\t1,", "B2,\tm,\t0,\tJ2,\t0,\ta,", "B2,", "body B2", r"flag.*\ba\b"),
    (
        "bad expression",
        "T1,\tkLU,",
        "T1,\t__import__('os'),",
        "T1,",
        "TSD T1",
        r"stiffness.*__import__.*not a valid expression.*column",
    ),
    ("bad offset", "C6,\tB1,\t0,\t-b,", "C6,\tB1,\t0,\tb(1),", "C6,", "CP C6", r"ly.*b\(1\).*column"),
    ("bad mass", "B2,\tm,", "B2,\tm;,", "B2,", "body B2", r"mass.*column"),
    ("too few columns", "C1,\tB2,\t0,\t0,\tlLU,", "C1,\tB2,\t0,\tlLU,", "C1,", "C1", r"expected 5 columns.*found 4"),
    ("too many columns", "P1,\tC5,\tC6,", "P1,\tC5,\tC6,\tC7,", "P1,", "P1", r"expected 3 columns.*found 4"),
    ("row of another section", "G3,\n", "G3,\nC9,\tB1,\t0,\t0,\t0,\n", "C9,", "C9", r"section Ground"),
    ("body row among TSDs", "T4,", "B3,\t1,\t0,\t0,\t0,\t1,\t0,\t0,\t0,\t0,\t0,\nT4,", "B3,", "B3", r"section TSD"),
    ("unknown section header", "(2) Ground", "(6) Springs", "(6) Springs", "(6) Springs", r"unknown section"),
    ("misspelt section header", "(3) CP", "(3) CPs", "(3) CPs", "(3) CPs", r"unknown section"),
    ("TSD on unknown CP", "C7,\tC8,\t1,", "C7,\tC88,\t1,", "T4,", "TSD T4", r"T_End.*C88.*not a CP"),
    ("pin on unknown CP", "P1,\tC5,", "P1,\tC55,", "P1,", "pin P1", r"C55.*not a CP"),
    ("pin without element", "P1,\tC5,\tC6,", "P1,\tC5,\tC7,", "P1,", "pin P1", r"no element joins"),
    ("TSD from a CP to itself", "C7,\tC8,\t1,", "C7,\tC7,\t1,", "T4,", "TSD T4", r"same CP"),
    ("section twice", "(5) Pinned Joint", "(2) Ground\n(5) Pinned Joint", "(2) Ground", "(2) Ground", r"twice"),
]


def _problem_lines(error: ModelError) -> list[str]:
    return [str(problem) for problem in error.problems]


@pytest.mark.parametrize(
    "old, new, anchor, item, pattern",
    [case[1:] for case in ERROR_CASES],
    ids=[case[0] for case in ERROR_CASES],
)
def test_error_names_file_line_item_and_problem(tmp_path, old, new, anchor, item, pattern):
    """Each mistake is reported as ``file:line: item: message`` where the line is the
    offending one, the item names the record and the message says what is wrong."""
    assert old in LEVER_TEXT
    text = LEVER_TEXT.replace(old, new, 1)
    path = tmp_path / "model.exp"
    path.write_text(text, encoding="utf-8")
    # the offending line is the last one starting with the anchor (for duplicates,
    # the second definition)
    line = [n for n, l in enumerate(text.splitlines(), 1) if l.startswith(anchor)][-1]
    with pytest.raises(ModelError) as info:
        read_classic(path)
    lines = _problem_lines(info.value)
    wanted = [
        s for s in lines if s.startswith(f"{path}:{line}: ") and item in s and re.search(pattern, s)
    ]
    assert wanted, f"no problem at line {line} about {item!r} matching {pattern!r} in:\n" + "\n".join(lines)
    for problem in info.value.problems:
        assert problem.file == str(path)


def test_several_problems_are_reported_at_once(tmp_path):
    """A file with several independent mistakes reports every one, in line order."""
    text = (
        LEVER_TEXT.replace("C1,\tB2,", "C1,\tB9,")
        .replace("C1,\tC2,\t1,", "C1,\tC2,\t4,")
        .replace("T2,\tkLL,", "T2,\tkLL(",)
        .replace("0,\t0,\t0,\t1,\n", "0,\t0,\t0,\t2,\n", 1)
        .replace("P1,\tC5,\tC6,", "P1,\tC5,\tC6,\tC7,")
    )
    path = tmp_path / "many.exp"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(ModelError) as info:
        read_classic(path)
    problems = info.value.problems
    found = {(p.line, p.item.split()[-1]) for p in problems}
    expected = {
        (line_of(text, "B1,"), "B1"),
        (line_of(text, "C1,"), "C1"),
        (line_of(text, "T1,"), "T1"),
        (line_of(text, "T2,"), "T2"),
        (line_of(text, "P1,"), "P1"),
    }
    assert expected <= found, [str(p) for p in problems]
    lines = [p.line or 0 for p in problems]
    assert lines == sorted(lines)


def test_several_problems_on_one_row():
    """Two mistakes in the same row are both reported."""
    text = LEVER_TEXT.replace("T1,\tkLU,\t0,\tC1,\tC2,\t1,", "T1,\tk LU,\t0,\tC1,\tC2,\t7,")
    with pytest.raises(ModelError) as info:
        parse_classic(text, "f.exp")
    messages = [p.message for p in info.value.problems if p.item == "TSD T1"]
    assert any("stiffness" in m for m in messages)
    assert any("direction" in m for m in messages)


@pytest.mark.parametrize("text", ["", "\n\n", "hello world\n", "B1, 1, 2, 3\n", '{"dofs": []}'])
def test_text_that_is_not_a_model_is_refused(text):
    """Empty files, prose or JSON are refused with a ModelError, not read as an empty model."""
    with pytest.raises(ModelError) as info:
        parse_classic(text, "x.exp")
    assert info.value.problems
    assert all(p.file == "x.exp" for p in info.value.problems)


def test_unknown_host_is_not_called_a_ground():
    """A pin whose virtual CP sits on an unknown body: the messages may say the body
    is unknown, but must not claim that the CP is on a ground."""
    text = LEVER_TEXT.replace("C5,\tB2,", "C5,\tB7,")
    with pytest.raises(ModelError) as info:
        parse_classic(text, "f.exp")
    messages = [str(p) for p in info.value.problems]
    assert any("B7" in m and "unknown" in m for m in messages), messages
    assert not any("on ground B7" in m for m in messages), messages


def test_load_model_reports_a_missing_file(tmp_path):
    """``load_model`` of a missing file is a ModelError naming the file."""
    path = tmp_path / "nothing.exp"
    with pytest.raises(ModelError) as info:
        load_model(path)
    assert str(path) in str(info.value)


def test_non_utf8_file_is_a_model_error(tmp_path):
    """Bytes that are not UTF-8 give a clean ModelError."""
    path = tmp_path / "binary.exp"
    path.write_bytes(b"(1) Body\n\xff\xfe\x00B1,\x80\n")
    with pytest.raises(ModelError) as info:
        read_classic(path)
    assert "UTF-8" in str(info.value)


# --------------------------------------------------------------------------- fuzzing

LEVER_LINES = LEVER_TEXT.splitlines()
JUNK = st.one_of(
    st.text(max_size=12),
    st.sampled_from(
        [
            "(",
            ")",
            "'",
            '"',
            "__import__('os')",
            "__import__",
            "é",
            "Ω",
            "\u2028",
            "1e5",
            "B1",
            "B2",
            "C5",
            "C6",
            "G1",
            "P2",
            "kinf",
            "-b",
            "0",
            "1",
            "2",
            "",
            "x",
            "(6) Foo",
            "(1) Body",
            "(5) Pinned Joint",
            "1/0",
            "a^b",
            "a(b)",
            "lambda: 0",
            "\x00",
            "\ufeff",
        ]
    ),
)


@st.composite
def mutated_lever(draw):
    """The lever file with a few random edits: delete, duplicate or swap lines, replace a
    field by junk, insert junk lines, or insert random bytes decoded as text."""
    lines = list(LEVER_LINES)
    for _ in range(draw(st.integers(1, 5))):
        op = draw(st.sampled_from(["delete", "duplicate", "swap", "replace", "insert", "bytes"]))
        j = draw(st.integers(0, len(lines) - 1)) if lines else 0
        if op == "delete" and lines:
            del lines[j]
        elif op == "duplicate" and lines:
            lines.insert(draw(st.integers(0, len(lines))), lines[j])
        elif op == "swap" and lines:
            k = draw(st.integers(0, len(lines) - 1))
            lines[j], lines[k] = lines[k], lines[j]
        elif op == "replace" and lines:
            fields = re.split(r"(,|\t)", lines[j])
            if fields:
                fields[draw(st.integers(0, len(fields) - 1))] = draw(JUNK)
            lines[j] = "".join(fields)
        elif op == "insert":
            lines.insert(j, draw(JUNK))
        else:
            raw = draw(st.binary(max_size=20))
            lines.insert(j, raw.decode("latin-1"))
    return "\n".join(lines) + draw(st.sampled_from(["\n", "", "\r\n"]))


def _classify(text: str) -> str:
    try:
        model = parse_classic(text, "fuzz.exp")
    except ModelError as error:
        assert error.problems, "a ModelError must carry at least one problem"
        for problem in error.problems:
            assert problem.file == "fuzz.exp"
        return "refused"
    assert model.bodies is not None
    return "model"


@settings(max_examples=200, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(mutated_lever())
def test_mutated_lever_parses_or_is_refused(text):
    """Property: a randomly damaged lever file gives a Model or a ModelError, never any
    other exception."""
    _classify(text)


@settings(max_examples=200, deadline=None)
@given(st.text(max_size=300))
def test_random_text_parses_or_is_refused(text):
    """Property: arbitrary text gives a Model or a ModelError, never another exception."""
    _classify(text)


@settings(max_examples=200, deadline=None)
@given(
    st.lists(
        st.one_of(
            st.sampled_from(list(LEVER_ROWS)),
            st.lists(st.one_of(st.from_regex(r"[BGCTP][0-9]", fullmatch=True), JUNK), min_size=1, max_size=12).map(
                lambda fields: ",".join(fields)
            ),
        ),
        max_size=30,
    ).map("\n".join)
)
def test_random_section_soup_parses_or_is_refused(text):
    """Property: random sequences of real section headers and id-like rows (which get
    past the heading filter into the row readers) give a Model or a ModelError."""
    _classify(text)


def _run_cli(argv) -> int:
    try:
        return main(argv)
    except SystemExit as exit_:  # argparse
        return int(exit_.code or 0)


@pytest.mark.slow
@settings(max_examples=200, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])
@given(text=mutated_lever())
def test_generate_command_on_mutated_lever_never_crashes(tmp_path, capsys, text):
    """Property: ``express generate`` on a damaged lever file exits 0 (it generated) or
    2 (it reported the problems), and never prints a Python traceback."""
    path = tmp_path / "fuzz.exp"
    path.write_text(text, encoding="utf-8", errors="surrogatepass")
    capsys.readouterr()
    status = _run_cli(["generate", str(path)])
    out, err = capsys.readouterr()
    assert status in (0, 2), (status, err)
    assert "Traceback" not in out + err
    if status == 2:
        assert err.strip(), "a refusal must say why"
        assert all(line.startswith("error: ") or line.startswith("warning: ") for line in err.splitlines())
    else:
        assert "M (" in out or "M[" in out or "DOFs" in out


@pytest.mark.slow
@settings(max_examples=200, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(text=st.text(max_size=200))
def test_generate_command_on_random_text_never_crashes(tmp_path, capsys, text):
    """Property: ``express generate`` on random text exits 0 or 2 without a traceback."""
    path = tmp_path / "random.exp"
    path.write_text(text, encoding="utf-8", errors="surrogatepass")
    capsys.readouterr()
    status = _run_cli(["generate", str(path)])
    out, err = capsys.readouterr()
    assert status in (0, 2), (status, err)
    assert "Traceback" not in out + err


def test_seeded_mutations_of_the_lever(tmp_path, capsys):
    """A deterministic sweep (seeded ``random``) of single-field replacements in every
    data row of the lever: each gives a Model or a clean refusal through the CLI."""
    rng = random.Random(2001)
    junk = ["'", "(", "B9", "C9", "9", "-1", "kinf^kinf", "1e999", "", "x", "P1", "G1", "é"]
    path = tmp_path / "sweep.exp"
    for number, line in enumerate(LEVER_LINES):
        if not re.match(r"[BGCTP]\d", line):
            continue
        fields = line.split(",")
        for _ in range(3):
            edited = list(fields)
            edited[rng.randrange(len(edited))] = rng.choice(junk)
            lines = list(LEVER_LINES)
            lines[number] = ",".join(edited)
            path.write_text("\n".join(lines) + "\n", encoding="utf-8")
            capsys.readouterr()
            status = _run_cli(["generate", str(path)])
            out, err = capsys.readouterr()
            assert status in (0, 2), (lines[number], err)
            assert "Traceback" not in out + err


@pytest.mark.parametrize("kept", ["Number,\t", "Number,\tCP Number,\n\tVir", "Number,\tCP Number,\n\tVirtual,\tNon-Virtu"])
def test_a_file_cut_inside_its_last_sections_headings_is_refused(tmp_path, kept):
    """Issue 36 item 6: the lever cut inside the column headings of (5) Pinned Joint read
    as the lever without its pin (exit 0); headings left out altogether stay a valid empty
    section."""
    text = (Path(__file__).resolve().parents[1] / "examples" / "lever.exp").read_text()
    head = text[: text.rindex("(5) Pinned Joint")] + "(5) Pinned Joint\n"
    path = tmp_path / "cut.exp"
    path.write_text(head + kept)
    with pytest.raises(ModelError) as error:
        read_classic(path)
    assert any("inside the section's column headings" in str(p) for p in error.value.problems)
