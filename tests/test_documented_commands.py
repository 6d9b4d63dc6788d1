"""Every command line the README and docs/ show runs, with the exit status they show
(issue 36, item 4): a documented input can never again fail unnoticed.

A command line is a ``$ express ...`` line inside a fenced block of ``README.md`` or
``docs/*.md``. It is expected to succeed unless the block shows an ``error:`` line after
it; then its status is the one :data:`FAILING` names (2 bad input, 1 no valid result, 3 a
failed assessment).
Lines with a placeholder (``MODEL``, ``study.toml``, a scheduler's address) are templates,
not examples: they are listed by :func:`test_templates_are_the_only_lines_left_out` so
that nothing else slips out.  Each runs in a fresh folder where ``examples/`` is the
repository's (outputs land in the folder, never in the repository)."""

from __future__ import annotations

import os
import re
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DOCUMENTS = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
_COMMAND = re.compile(r"^\$ (express\b.*?)(?:\s{2,}#.*)?$")
#: Words that make a line a template (a placeholder to fill in), not an example.
TEMPLATE_WORDS = ("MODEL", "CLASS|", "study.toml", "bad.toml", "SCHEDULER", "10.0.0.5")
#: The documented failures and their status, by a fragment of the command line.
FAILING = {"--tolerance 1e-14": 2, "--set cy2=-300000": 1, "twist examples/y25-wagon.toml --assess": 3}


@dataclass(frozen=True)
class Documented:
    where: str
    command: str
    shows_error: bool

    @property
    def template(self) -> bool:
        return any(word in self.command for word in TEMPLATE_WORDS)

    @property
    def status(self) -> int:
        if not self.shows_error:
            return 0
        (status,) = [s for fragment, s in FAILING.items() if fragment in self.command]
        return status


def documented_commands() -> list[Documented]:
    found = []
    for document in DOCUMENTS:
        lines = document.read_text(encoding="utf-8").splitlines()
        fenced = False
        for number, line in enumerate(lines, 1):
            if line.startswith("```"):
                fenced = not fenced
                continue
            match = _COMMAND.match(line) if fenced else None
            if match is None:
                continue
            shown = []
            for after in lines[number:]:
                if after.startswith(("$ ", "```")):
                    break
                shown.append(after)
            found.append(Documented(f"{document.relative_to(ROOT)}:{number}", match.group(1).strip(),
                                    any(s.startswith("error:") for s in shown)))
    return found


EXAMPLES = [d for d in documented_commands() if not d.template]


def test_the_docs_show_commands_and_every_failure_has_its_status():
    assert len(EXAMPLES) > 40
    for example in EXAMPLES:
        assert example.status in (0, 1, 2, 3), example


def test_templates_are_the_only_lines_left_out():
    left_out = [d.command for d in documented_commands() if d.template]
    assert left_out and all(any(word in c for word in TEMPLATE_WORDS) for c in left_out)
    assert len(left_out) <= 8, left_out  # a new placeholder should be a deliberate choice


@pytest.mark.slow
@pytest.mark.parametrize("example", EXAMPLES, ids=[e.where for e in EXAMPLES])
def test_a_documented_command_runs_with_its_status(example: Documented, tmp_path: Path):
    (tmp_path / "examples").symlink_to(ROOT / "examples")
    (tmp_path / "docs" / "figures").mkdir(parents=True)
    express = f"{sys.executable} -m express"
    command = example.command.replace("express", express, 1)
    run = subprocess.run(["bash", "-c", command], cwd=tmp_path, capture_output=True, text=True, timeout=1200,
                         env={**os.environ, "PYTHONPATH": str(ROOT / "src") + os.pathsep + os.environ.get("PYTHONPATH", "")})
    assert run.returncode == example.status, f"{example.where}: {example.command}\n{run.stderr[-2000:]}"
    assert "Traceback" not in run.stderr
