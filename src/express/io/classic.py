"""Reader for the classic model file of the paper's Fig. 5 (``conventions.md``).

Five sections opened by ``(1) Body``, ``(2) Ground``, ``(3) CP``, ``(4) TSD``,
``(5) Pinned Joint``; comma- or tab-separated data rows that start with the item's
id (``B1``, ``G1``, ``C1``, ``T1``, ``P1``); any other line (column headings, blank
lines) is not data.  Every problem in the file is collected and raised together.
"""

from __future__ import annotations

import re
from pathlib import Path

import sympy as sp

from express.base.diagnostics import ModelError, Problem
from express.base.expressions import ExpressionError, parse_expression
from express.base.limits import exceeded, read_input_text
from express.model.checks import check_model
from express.model.parameter_ranges import check_ranges
from express.model.records import (
    AXES,
    DOF_NAMES,
    Axis,
    Body,
    ConnectionPoint,
    Element,
    Ground,
    Model,
    PinnedJoint,
)

__all__ = ["model_name_from_path", "parse_classic", "read_classic", "read_model_text"]

SECTIONS = {1: "Body", 2: "Ground", 3: "CP", 4: "TSD", 5: "Pinned Joint"}
_PREFIX = {"Body": "B", "Ground": "G", "CP": "C", "TSD": "T", "Pinned Joint": "P"}
_COLUMNS = {
    "Body": "id, mass, Ix, Iy, Iz, tx, ty, tz, rx, ry, rz",
    "Ground": "id",
    "CP": "id, body or ground, lx, ly, lz",
    "TSD": "id, stiffness, damping, S_End CP, T_End CP, direction",
    "Pinned Joint": "id, virtual CP, non-virtual CP",
}
_WIDTH = {"Body": 11, "Ground": 1, "CP": 5, "TSD": 6, "Pinned Joint": 3}
_HEADER = re.compile(r"\s*\(\s*(\d+)\s*\)\s*([A-Za-z][A-Za-z ]*?)\s*[,\t]*\s*$")
_ID_LIKE = re.compile(r"[A-Za-z][A-Za-z_]*\d[A-Za-z0-9_]*\Z")


def model_name_from_path(path: str | Path) -> str:
    """A valid identifier made from a file name (``lever.exp`` -> ``lever``,
    ``é x.exp`` -> ``model___x``): ASCII letters, digits and ``_`` only."""
    name = re.sub(r"[^A-Za-z0-9_]", "_", Path(path).stem)
    if not name or not ("A" <= name[0] <= "Z" or "a" <= name[0] <= "z"):
        name = "model_" + name
    return name


def read_model_text(path: str | Path) -> str:
    """The text of a model file, refused beyond the size limit before it is read
    whole (:func:`express.base.limits.read_input_text`, ``EXPRESS_MAX_FILE_MB``) and when
    it is not UTF-8 text."""
    return read_input_text(path)


def _short(text: str, limit: int = 60) -> str:
    """A field quoted in a message, cut to ``limit`` characters (a file may hold
    anything, and may not be the user's own)."""
    return text if len(text) <= limit else text[: limit - 3] + "..."


def _fields(line: str) -> list[str]:
    fields = re.split(r"\s*,\s*|\s*\t\s*", line.strip())
    while fields and fields[-1] == "":
        fields.pop()
    return fields


class _RowReader:
    """Turns one data row into a record, noting problems instead of raising."""

    def __init__(self, source: str, line: int, item: str, problems: list[Problem]):
        self.source, self.line, self.item, self.problems = source, line, item, problems
        self.ok = True

    def problem(self, message: str) -> None:
        self.problems.append(Problem(self.source, self.line, self.item, message))
        self.ok = False

    def value(self, text: str, column: str) -> sp.Expr:
        try:
            return parse_expression(text)
        except ExpressionError as error:
            self.problem(f'{column} "{_short(text)}" is not a valid expression ({error})')
            return sp.S.Zero

    def flag(self, text: str, column: str) -> bool:
        if text in ("0", "1"):
            return text == "1"
        self.problem(f'{column} flag must be 0 or 1, got "{_short(text)}"')
        return False

    def direction(self, text: str) -> int:
        if text in ("1", "2", "3"):
            return int(text) - 1
        self.problem(f'direction must be 1, 2 or 3 (x, y, z), got "{_short(text)}"')
        return 0

    def identifier(self, text: str, column: str) -> str:
        if not re.fullmatch(r"[A-Za-z][A-Za-z0-9_]*", text):
            self.problem(f'{column} "{_short(text)}" is not an id')
        return text


def parse_classic(text: str, source: str = "<string>") -> Model:
    """Parse the text of a classic model file.

    Parameters
    ----------
    text : str
        File contents.
    source : str
        File name used in messages and as the model's source.

    Returns
    -------
    Model
        The validated model (no parameter values: the classic format has none).

    Raises
    ------
    ModelError
        With every problem found, each naming the file, line and item.
    """
    problems: list[Problem] = []
    rows = _scan(text.removeprefix("\ufeff"), source, problems)
    for section, name in (("Body", "bodies"), ("TSD", "elements"), ("CP", "points")):
        message = exceeded(name, len(rows[section]))
        if message is not None:  # before any value is parsed
            raise ModelError([Problem(source, None, f"section {section}", message)])
    bodies, grounds, points, elements, pins = _records(rows, source, problems)
    model = Model(
        name=model_name_from_path(source),
        source=source,
        bodies=tuple(bodies),
        grounds=tuple(grounds),
        points=tuple(points),
        elements=tuple(elements),
        pins=tuple(pins),
    )
    problems.extend(check_model(model))
    if problems:
        raise ModelError(sorted(problems, key=lambda p: (p.line or 0)))
    check_ranges(model)  # the constants among the values (a classic file has no parameters)
    return model


def _scan(text: str, source: str, problems: list[Problem]) -> dict[str, list]:
    """The data rows ``(line, fields)`` of each section; problems of the layout."""
    section: str | None = None
    in_unknown_section = False
    seen_sections: set[str] = set()
    rows: dict[str, list] = {name: [] for name in SECTIONS.values()}
    for number, raw in enumerate(text.splitlines(), start=1):
        line = raw.strip()
        if not line or line.startswith(("#", "%")):
            continue
        header = _HEADER.match(raw)
        if header:
            section = _section(header, number, source, seen_sections, problems)
            in_unknown_section = section is None
            continue
        fields = _fields(raw)
        if not fields or not _ID_LIKE.match(fields[0]) or in_unknown_section:
            continue  # column headings and other text are not data; an unknown section is reported
        first = fields[0]
        if section is None:
            problems.append(Problem(source, number, first, "data row before any section header such as (1) Body"))
            continue
        prefix = _PREFIX[section]
        if not first.startswith(prefix):
            problems.append(Problem(
                source, number, first,
                f"row in section {section}, whose ids start with {prefix} (columns: {_COLUMNS[section]})",
            ))
            continue
        width = _WIDTH[section]
        if len(fields) != width:
            problems.append(Problem(
                source, number, f"{section} {first}",
                f"expected {width} columns ({_COLUMNS[section]}), found {len(fields)}",
            ))
            continue
        rows[section].append((number, fields))
    written = text.lstrip().startswith("# EXPRESS classic model") or _RENAMING.search(text)
    if not seen_sections and not problems and written:  # EXPRESS's header, then nothing
        last = len(text.splitlines())
        problems.append(Problem(source, last, "", f"the file stops early, at line {last}, before its first section"))
    elif not seen_sections and not problems:
        problems.append(Problem(source, None, "", "no section header such as (1) Body found: not a classic model file"))
    elif seen_sections:
        _check_structure(text, rows, seen_sections, source, problems)
    return rows


def _check_structure(text: str, rows: dict[str, list], seen: set[str], source: str, problems: list[Problem]) -> None:
    """What the paper's format promises: the five sections, (1) Body to (5) Pinned Joint,
    bodies, and every connection point used by an element or a pinned joint. A file
    that stops early breaks one of these; the message says where it stops."""
    last = len(text.splitlines())
    missing = [f"({k}) {name}" for k, name in SECTIONS.items() if name not in seen]
    if missing:
        after = max((k for k, name in SECTIONS.items() if name in seen), default=0)
        early = all(k > after for k, name in SECTIONS.items() if name not in seen)
        where = f"the file stops early, at line {last}: " if early else ""
        problems.append(Problem(source, None if not early else last, "",
                                f"{where}section{'s' if len(missing) > 1 else ''} {', '.join(missing)} missing "
                                "(a classic model has the five sections (1) Body to (5) Pinned Joint)"))
    if "Body" in seen and not rows["Body"]:
        problems.append(Problem(source, None, "section (1) Body", "no bodies: a model needs at least one"))
    if missing:
        return
    _check_last_headings(text, rows, last, source, problems)
    _check_promised(text, rows, last, source, problems)
    used = {field for _, fields in rows["TSD"] for field in fields[3:5]}
    used |= {field for _, fields in rows["Pinned Joint"] for field in fields[1:3]}
    unused = [(number, fields[0]) for number, fields in rows["CP"] if fields[0] not in used]
    for number, identifier in unused[:3]:
        problems.append(Problem(source, number, f"CP {identifier}",
                                f"used by no element or pinned joint (a file cut short ends at line {last})"))
    if len(unused) > 3:
        problems.append(Problem(source, None, "section (3) CP", f"{len(unused)} connection points used by nothing in all"))


_RENAMING = re.compile(r"#\s+([BGCTP]\d+) = \S", re.MULTILINE)


#: The last word of each section's column headings (the paper's and the writer's alike).
_LAST_HEADING = {"Body": "rz", "Ground": "number", "CP": "z", "TSD": "direction", "Pinned Joint": "non-virtual"}


def _check_last_headings(text: str, rows: dict[str, list], last: int, source: str, problems: list[Problem]) -> None:
    """A file cut inside the column headings of its last section, which has no rows, reads
    as a smaller model (a pinned joint fewer): headings that stop before their last word
    mean the file was cut there.  Headings left out altogether are a valid empty section."""
    lines = text.splitlines()
    opened = [(k, m) for k, line in enumerate(lines) if (m := _HEADER.match(line))]
    if not opened:
        return
    index, header = opened[-1]
    section = SECTIONS.get(int(header.group(1)))
    if section is None or rows.get(section):
        return
    words = [w for w in re.split(r"[\s,]+", " ".join(lines[index + 1:]).strip().lower()) if w]
    if words and words[-1] != _LAST_HEADING[section]:
        problems.append(Problem(source, last, f"section ({header.group(1)}) {section}",
                                f"the file stops early, at line {last}: inside the section's column headings "
                                f"(they end with {_LAST_HEADING[section]!r})"))


def _check_promised(text: str, rows: dict[str, list], last: int, source: str, problems: list[Problem]) -> None:
    """A file written by EXPRESS lists every id in its renaming header (``#   P4 = T2_LR_pin``):
    an id listed there without its row means the file was cut short."""
    promised = _RENAMING.findall(text)
    if not promised:
        return
    present = {fields[0] for section in rows.values() for _, fields in section}
    absent = [identifier for identifier in promised if identifier not in present]
    if absent:
        shown = ", ".join(absent[:5]) + (f" and {len(absent) - 5} more" if len(absent) > 5 else "")
        problems.append(Problem(source, last, "", f"the file stops early, at line {last}: {shown} listed in its "
                                f"renaming header but without a row"))


def _section(header: re.Match, number: int, source: str, seen: set[str], problems: list[Problem]) -> str | None:
    """The section a header opens (None for an unknown one, reported)."""
    index, title = int(header.group(1)), header.group(2).strip()
    expected = SECTIONS.get(index)
    if expected is None or title.lower() != expected.lower():
        known = ", ".join(f"({k}) {v}" for k, v in SECTIONS.items())
        problems.append(Problem(source, number, f"section ({index}) {_short(title)}", f"unknown section; expected one of {known}"))
        return None
    if expected in seen:
        problems.append(Problem(source, number, f"section ({index}) {expected}", "section appears twice"))
    seen.add(expected)
    return expected


def _records(rows: dict[str, list], source: str, problems: list[Problem]) -> tuple[list, list, list, list, list]:
    """Bodies, grounds, CPs, elements and pins from the rows of each section."""
    bodies, grounds, points, elements, pins = [], [], [], [], []
    for number, fields in rows["Body"]:
        row = _RowReader(source, number, f"body {fields[0]}", problems)
        mass = row.value(fields[1], "mass")
        inertia = tuple(row.value(fields[2 + i], f"I{axis}") for i, axis in enumerate(AXES))
        flags = [row.flag(fields[5 + i], name) for i, name in enumerate(DOF_NAMES)]
        dofs = tuple(name for name, on in zip(DOF_NAMES, flags, strict=True) if on)
        bodies.append(Body(fields[0], mass, inertia, dofs, line=number))
    for number, fields in rows["Ground"]:
        grounds.append(Ground(fields[0], line=number))
    for number, fields in rows["CP"]:
        row = _RowReader(source, number, f"CP {fields[0]}", problems)
        host = row.identifier(fields[1], "body")
        offset = tuple(row.value(fields[2 + i], f"l{axis}") for i, axis in enumerate(AXES))
        points.append(ConnectionPoint(fields[0], host, offset, line=number))
    for number, fields in rows["TSD"]:
        row = _RowReader(source, number, f"TSD {fields[0]}", problems)
        stiffness = row.value(fields[1], "stiffness")
        damping = row.value(fields[2], "damping")
        s_end = row.identifier(fields[3], "S_End")
        t_end = row.identifier(fields[4], "T_End")
        direction = row.direction(fields[5])
        elements.append(Element(fields[0], stiffness, damping, s_end, t_end, Axis(direction), line=number))
    for number, fields in rows["Pinned Joint"]:
        row = _RowReader(source, number, f"pin {fields[0]}", problems)
        virtual, non_virtual = row.identifier(fields[1], "virtual CP"), row.identifier(fields[2], "non-virtual CP")
        pins.append(PinnedJoint(fields[0], virtual, non_virtual, line=number))
    return bodies, grounds, points, elements, pins


def read_classic(path: str | Path) -> Model:
    """Read a classic model file (see :func:`parse_classic`)."""
    path = Path(path)
    return parse_classic(read_model_text(path), source=str(path))
