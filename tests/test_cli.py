"""The ``express`` entry point (``express.cli.main``): parser assembly, exit statuses
0/1/2/70, one-line errors, ``--debug``, broken pipes, BLAS threads and a quick start.

The commands themselves are tested in ``test_cli_<command>.py``.
"""

from __future__ import annotations

import inspect
import os
import re
import subprocess
import sys

import pytest

import express
from cli_support import CONVENTIONAL, LEVER, ROOT, assert_input_error, run
from express import cli
from express.cli import runner
from express.base.diagnostics import AnalysisError, ModelError, OutputError, Problem, UsageError

SRC = ROOT / "src"


def fresh_python(code: str) -> subprocess.CompletedProcess:
    """Run ``code`` in a new interpreter that imports this checkout."""
    env = {k: v for k, v in os.environ.items() if not k.endswith("_NUM_THREADS")}
    env["PYTHONPATH"] = str(SRC)
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, timeout=120)


# --------------------------------------------------------------------------- version, help


def test_version(capsys):
    """``express --version`` prints the package version and exits 0."""
    status, out, err = run(capsys, "--version")
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


def test_help_lists_every_command_and_the_quantity_rule(capsys):
    status, out, _ = run(capsys, "--help")
    assert status == 0
    for command in ("generate", "convert", "simulate", "frf", "eigen", "critical-speed", "demo"):
        assert command in out
    assert "km/h" in out and "70" in out  # the bare-number rule and the exit statuses


def test_no_command_is_a_usage_error(capsys):
    """``express`` alone is a usage error (status 2), with a usage message."""
    status, out, err = run(capsys)
    assert status == 2
    assert "usage" in (out + err).lower()


@pytest.mark.parametrize(
    "argv, mentions",
    [
        (["frobnicate"], "frobnicate"),
        (["generate", LEVER, "--format", "fortran"], "fortran"),
        (["eigen", CONVENTIONAL, "--no-such-option"], "--no-such-option"),
        (["eigen"], "model"),
        (["frf", CONVENTIONAL, "--points", "many"], "--points"),
    ],
)
def test_command_line_mistakes_are_one_line_and_status_2(capsys, argv, mentions):
    status, out, err = run(capsys, *argv)
    assert status == 2 and out == ""
    assert len(err.splitlines()) == 1 and err.startswith("error: "), err
    assert mentions in err


def _command_names() -> list[str]:
    parser = cli.build_parser()
    return sorted(next(a for a in parser._actions if a.dest == "command").choices)


HEAVY = ("sympy", "scipy", "matplotlib", "numba")


@pytest.mark.parametrize("argv", [["--help"], ["--version"], ["generate", "--help"], ["simulate", "--help"],
                                  ["critical-speed", "--help"]])
def test_help_and_version_import_neither_sympy_scipy_nor_matplotlib(argv):
    """A quick start: ``--help`` and ``--version`` stay clear of the heavy libraries
    (checked in a fresh interpreter's ``sys.modules``)."""
    code = (
        "import sys, contextlib, io\n"
        "from express.cli import main\n"
        "with contextlib.redirect_stdout(io.StringIO()):\n"
        f"    status = main({argv!r})\n"
        f"heavy = sorted(m for m in {HEAVY!r} if m in sys.modules)\n"
        "print(status, heavy)\n"
    )
    done = fresh_python(code)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "0 []"


def test_every_commands_help_imports_no_heavy_library():
    """``express COMMAND --help`` for every command, one after the other in one fresh
    interpreter: the heavy libraries are still absent after the last one (modules only
    accumulate, so none was imported by any), and each help printed and exited 0."""
    names = _command_names()
    assert len(names) >= 15
    code = (
        "import sys, contextlib, io\n"
        "from express.cli import main\n"
        f"for name in {names!r}:\n"
        "    out = io.StringIO()\n"
        "    with contextlib.redirect_stdout(out):\n"
        "        status = main([name, '--help'])\n"
        f"    heavy = sorted(m for m in {HEAVY!r} if m in sys.modules)\n"
        "    print(name, status, 'usage:' in out.getvalue(), heavy)\n"
    )
    done = fresh_python(code)
    assert done.returncode == 0, done.stderr
    lines = done.stdout.splitlines()
    assert lines == [f"{name} 0 True []" for name in names]


def test_importing_the_cli_does_not_touch_the_environment():
    """No BLAS variables are set at import (threads are limited while a command runs)."""
    done = fresh_python("import os; before = dict(os.environ); import express.cli; print(before == dict(os.environ))")
    assert done.stdout.strip() == "True", done.stderr


# --------------------------------------------------------------------------- the handlers


def test_every_handler_receives_exactly_the_parsed_values():
    """Each command module has ``add_parser`` and a handler whose keyword parameters are
    the parser's destinations: the argparse Namespace never travels into the library."""
    parser = cli.build_parser()
    subparsers = next(a for a in parser._actions if a.dest == "command")
    assert {"generate", "convert", "simulate", "frf", "eigen", "critical-speed", "demo"} <= set(subparsers.choices)
    for name, sub in subparsers.choices.items():
        defaults = sub._defaults
        handler = defaults["handler"]
        dests = {a.dest for a in sub._actions if a.dest not in ("help", "debug", "no_cache")}
        parameters = set(inspect.signature(handler).parameters)
        assert parameters == dests, name
        assert handler.__module__ == f"express.cli.{name.replace('-', '_')}"


# --------------------------------------------------------------------------- exit statuses


def _raise(error: BaseException):
    def handler(**values):
        raise error

    return handler


@pytest.mark.parametrize(
    "outcome, status, first_line",
    [
        (lambda **v: 0, 0, None),
        (_raise(ModelError([Problem("m.toml", 3, "parameter x", "bad"), Problem("m.toml", 5, "CP C1", "worse")])),
         2, "error: m.toml:3: parameter x: bad"),
        (_raise(UsageError("--speed: out of range")), 2, "error: --speed: out of range"),
        (_raise(OutputError("out.csv: is a directory, not a file")), 2, "error: out.csv: is a directory, not a file"),
        (_raise(AnalysisError("the run diverged at t = 1 s")), 1, "error: the run diverged at t = 1 s"),
        (_raise(ValueError("boom\nsecond line")), 70,
         "error: internal error: ValueError: boom (run with --debug for the traceback)"),
        (_raise(ZeroDivisionError("float division by zero")), 70,
         "error: internal error: ZeroDivisionError: float division by zero (run with --debug for the traceback)"),
        (_raise(RecursionError("maximum recursion depth exceeded")), 70, "error: internal error: RecursionError"),
        (_raise(OSError(13, "Permission denied")), 70, "error: internal error: PermissionError"),
        (_raise(BrokenPipeError()), 0, None),
        (_raise(KeyboardInterrupt()), 130, "error: interrupted"),
    ],
)
def test_exit_statuses(capsys, monkeypatch, outcome, status, first_line):
    """0 success, 1 no valid result, 2 bad input (one line per problem), 70 anything
    unexpected (one line), never a traceback."""
    monkeypatch.setattr(cli.eigen, "run", outcome)
    code, _, err = run(capsys, "eigen", CONVENTIONAL)
    assert code == status
    lines = err.splitlines()
    if first_line is None:
        assert err == ""
    else:
        assert lines[0].startswith(first_line), err
        assert all(line.startswith("error: ") for line in lines)
    if status in (1, 70):
        assert len(lines) == 1


def test_model_problems_are_one_line_each(capsys, monkeypatch):
    problems = [Problem("m.toml", 3, "parameter x", "bad"), Problem("m.toml", None, "", "worse")]
    monkeypatch.setattr(cli.eigen, "run", _raise(ModelError(problems)))
    status, _, err = run(capsys, "eigen", CONVENTIONAL)
    assert status == 2
    assert err.splitlines() == ["error: m.toml:3: parameter x: bad", "error: m.toml: worse"]


@pytest.mark.parametrize("where", [["--debug", "eigen", CONVENTIONAL], ["eigen", CONVENTIONAL, "--debug"]])
def test_debug_shows_the_traceback(capsys, monkeypatch, where):
    monkeypatch.setattr(cli.eigen, "run", _raise(ValueError("boom")))
    status = cli.main(where)
    err = capsys.readouterr().err
    assert status == 70
    assert "Traceback" in err and err.rstrip().splitlines()[-1] == "error: internal error: ValueError: boom"


def test_a_broken_pipe_ends_quietly():
    """``express generate ... | head -1``: status 0 and nothing on stderr."""
    code = (
        "import subprocess, sys\n"
        "p = subprocess.Popen([sys.executable, '-m', 'express', 'generate', sys.argv[1], '--format', 'json'],"
        " stdout=subprocess.PIPE, stderr=subprocess.PIPE)\n"
        "p.stdout.readline(); p.stdout.close()\n"
        "err = p.stderr.read().decode(); status = p.wait()\n"
        "print(status, repr(err))\n"
    )
    env = dict(os.environ, PYTHONPATH=str(SRC))
    done = subprocess.run([sys.executable, "-c", code, str(ROOT / "examples" / "forced-steering.toml")],
                          capture_output=True, text=True, env=env, timeout=300)
    status, err = done.stdout.split(" ", 1)
    assert status == "0", done.stdout
    assert "Traceback" not in err and "BrokenPipe" not in err


# --------------------------------------------------------------------------- threads


def test_numerical_commands_run_blas_on_one_thread_and_restore_it(capsys, monkeypatch):
    from threadpoolctl import threadpool_info

    seen = []
    monkeypatch.setattr(cli.eigen, "run", lambda **values: seen.append(
        [pool["num_threads"] for pool in threadpool_info() if pool["user_api"] == "blas"]) or 0)
    before = [pool["num_threads"] for pool in threadpool_info() if pool["user_api"] == "blas"]
    status, _, _ = run(capsys, "eigen", CONVENTIONAL)
    assert status == 0
    assert seen and seen[0] and all(n == 1 for n in seen[0])
    assert [pool["num_threads"] for pool in threadpool_info() if pool["user_api"] == "blas"] == before


@pytest.mark.parametrize(
    "text, shown",
    [("plain text", "plain text"), ("a\nb", "a\\nb"), ("0\x850", "0\\x850"), ("\x1b[31mred", "\\x1b[31mred"),
     ("tab\there", "tab\\there"), ("é ü 120 km/h", "é ü 120 km/h")],
)
def test_error_lines_show_control_characters_as_escapes(text, shown):
    """What the user typed is echoed in errors; a newline or an escape sequence in it
    must not split the line or drive the terminal."""
    assert runner.printable(text) == shown


def test_a_set_value_with_a_line_break_is_one_error_line(capsys):
    err = assert_input_error(capsys, "eigen", CONVENTIONAL, "--set", "Gamma=0\x850")
    assert len(err.split("\n")) == 2 and "\\x85" in err  # one line and its end
