"""Helpers shared by the ``tests/test_cli*.py`` files: run ``express.cli.main`` as a
user would and check the shape of what it prints."""

from __future__ import annotations

import json
import re
from pathlib import Path

from express.cli import main

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "examples"
STEERED = str(EXAMPLES / "forced-steering.toml")
CONVENTIONAL = str(EXAMPLES / "conventional.toml")
LEVER = str(EXAMPLES / "lever.exp")
SINUSOID = str(EXAMPLES / "tracks" / "straight_sinusoid.toml")

#: ``error: file:line: item: message`` -- one problem of a model file.
PROBLEM_LINE = re.compile(r"^error: (?P<file>[^:]+):(?P<line>\d+): (?P<item>[^:]+): (?P<message>.+)$")

SHORT_TRACK = """
name = "short test curve"
[[segment]]
type = "straight"
length = 10.0
[[segment]]
type = "transition"
length = 30.0
[[segment]]
type = "curve"
length = 40.0
radius = 400.0
direction = "left"
cant = "95 mm"
"""


LEVER_VALUES = "J1 = 2.0\nJ2 = 0.5\nb = 0.4\nc = 300.0\nkLL = 5.5e6\nkLU = 5e5\nlLL = 0.06\nlLU = 0.3\nm = 20.0\n"


def valued_lever(folder: Path) -> Path:
    """The paper's lever as a modern file with parameter values: a model that
    evaluates numerically but has no rail data."""
    from express.io import load_model, model_to_toml

    text = model_to_toml(load_model(LEVER))
    text = re.sub(r"(?m)^# values for: .*$", LEVER_VALUES.rstrip("\n"), text)
    path = folder / "lever.toml"
    path.write_text(text, encoding="utf-8")
    return path


def run(capsys, *argv) -> tuple[int, str, str]:
    """``(status, stdout, stderr)`` of ``express argv``; never a traceback."""
    capsys.readouterr()
    status = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    assert isinstance(status, int)
    assert "Traceback" not in out + err, err
    return status, out, err


def run_json(capsys, *argv) -> dict:
    """The parsed ``--json`` summary of a successful run."""
    status, out, err = run(capsys, *argv, "--json")
    assert status == 0, err
    return json.loads(out)


def assert_fails(capsys, status: int, *argv, mentions: str = "") -> str:
    """The command exits with ``status``, prints nothing on stdout and ``error:`` lines
    on stderr (one per problem; ``warning:`` lines may precede them), one mentioning
    ``mentions``."""
    code, out, err = run(capsys, *argv)
    assert code == status, (code, err)
    assert out == ""
    lines = err.splitlines()
    assert lines and all(line.startswith(("error: ", "warning: ")) for line in lines if not line.startswith("usage")), err
    if mentions:
        assert mentions in err, err
    return err


def assert_input_error(capsys, *argv, mentions: str = "") -> str:
    """Bad input: status 2, one ``error:`` line per problem, no traceback."""
    return assert_fails(capsys, 2, *argv, mentions=mentions)
