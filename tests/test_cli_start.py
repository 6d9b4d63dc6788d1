"""Issue 16, a quick start for one-car commands: what a command imports.

``--help`` and ``--version`` are ``tests/test_cli.py``'s; here the commands that do the
work: a one-car ``generate``, ``eigen`` or ``critical-speed`` of a model without wheel
and rail profiles imports neither Numba nor the profile-contact modules nor Matplotlib
(checked in a fresh interpreter's ``sys.modules``), and a model with profiles still gets
its profiles derivation (imported on first use).  Timings are ``benchmarks/bench_cli.py``'s.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
CAR = ROOT / "examples" / "forced-steering.toml"
PROFILED = ROOT / "examples" / "manchester-s1002.toml"
NEEDLESS = ("numba", "matplotlib", "express.rail.profile_contact", "express.rail.contact_tables",
            "express.analysis.time.simulate")


def loaded_after(argv: list[str], modules: tuple[str, ...]) -> tuple[int, list[str]]:
    """Run ``express argv`` in a fresh interpreter: its status and which of ``modules`` it loaded."""
    env = {k: v for k, v in os.environ.items() if not k.endswith("_NUM_THREADS")}
    env["PYTHONPATH"] = str(ROOT / "src")
    code = (
        "import sys, contextlib, io\n"
        "from express.cli import main\n"
        "with contextlib.redirect_stdout(io.StringIO()):\n"
        f"    status = main({argv!r})\n"
        f"print(status, ','.join(m for m in {modules!r} if m in sys.modules))\n"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, timeout=300)
    assert done.returncode == 0, done.stderr
    status, _, loaded = done.stdout.strip().splitlines()[-1].partition(" ")
    return int(status), [m for m in loaded.split(",") if m]


@pytest.mark.slow
@pytest.mark.parametrize("command", [["generate", "--format", "json"], ["eigen"], ["critical-speed"]])
def test_one_car_commands_import_nothing_they_do_not_use(tmp_path, command):
    argv = [command[0], str(CAR), *command[1:]]
    if command[0] == "generate":
        argv += ["-o", str(tmp_path / "car.json")]
    status, loaded = loaded_after(argv, NEEDLESS)
    assert status == 0
    assert loaded == []


def test_a_model_with_profiles_still_gets_its_derivation(tmp_path):
    """The profiles module is imported when the model asks for it (the conicity of the
    S1002/60E1 pair, not the value in the file)."""
    status, loaded = loaded_after(["generate", str(PROFILED), "--format", "json", "-o", str(tmp_path / "m.json")],
                                  ("express.rail.profile_contact",))
    assert status == 0 and loaded == ["express.rail.profile_contact"]


def test_the_profiles_kind_is_spelled_once():
    from express.rail import build, profile_contact

    assert build.PROFILES == profile_contact.KIND
