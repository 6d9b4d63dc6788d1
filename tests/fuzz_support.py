"""Shared pieces of the fuzzing suites (``tests/test_fuzz_*.py``, issue 17).

A command is run in-process (``express.cli.main``) under a time limit (SIGALRM, so a
hang fails the example instead of the whole CI job) and judged by :func:`check`: exit
status 0, 1 or 2, never a traceback, errors as ``error:`` lines (warnings may precede
them), no error line that echoes a file at length.  :func:`snapshot` and
:func:`assert_untouched` check that a refused run leaves a directory exactly as it
was.  The mutation strategy edits a text as a careless user, a broken download or a
hostile file would: lines deleted, doubled, swapped or cut, numbers replaced by
extreme ones, garbage inserted.
"""

from __future__ import annotations

import contextlib
import io
import re
import signal
import time
from pathlib import Path

from hypothesis import HealthCheck, event, settings
from hypothesis import strategies as st

from express.cli import main

#: Hypothesis settings of the fuzz tests: derandomized (a run is reproducible, a
#: failure prints its example), no per-example deadline (the time limit below is ours).
FUZZ = settings(
    deadline=None,
    derandomize=True,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture, HealthCheck.data_too_large,
                           HealthCheck.filter_too_much, HealthCheck.large_base_example],
)


def fuzz(examples: int) -> settings:
    """:data:`FUZZ` with ``examples`` examples (kept modest: the suite runs in CI)."""
    return settings(FUZZ, max_examples=examples)


#: A generous bound on one command on a busy 2-core machine [s].
SECONDS = 60
#: The longest error line allowed: a message names a file, a line and an item and may
#: quote a short excerpt, never a file's content.
LONGEST_LINE = 800


class Timeout(BaseException):
    """A command ran past its time limit (a BaseException: the CLI must not catch it)."""


@contextlib.contextmanager
def time_limit(seconds: float):
    def expire(signum, frame):
        raise Timeout(f"still running after {seconds} s")

    previous = signal.signal(signal.SIGALRM, expire)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)


def run(argv: list[str], seconds: float = SECONDS) -> tuple[int, str, str, float]:
    """``(status, stdout, stderr, elapsed)`` of ``express *argv`` run in-process."""
    out, err = io.StringIO(), io.StringIO()
    start = time.perf_counter()
    with time_limit(seconds), contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        status = main([str(a) for a in argv])
    return status, out.getvalue(), err.getvalue(), time.perf_counter() - start


def check(argv: list[str], seconds: float = SECONDS) -> tuple[int, str, str]:
    """Run ``argv`` and assert that it ended cleanly; returns ``(status, out, err)``."""
    status, out, err, elapsed = run(argv, seconds)
    event(f"{argv[0]}: status {status}")  # --hypothesis-show-statistics shows the mix
    assert status in (0, 1, 2), (argv, status, err)
    assert "Traceback" not in out + err, (argv, err)
    assert elapsed < seconds, (argv, elapsed)
    lines = [line for line in err.splitlines() if not line.startswith("warning: ")]
    if status != 0:
        assert lines and all(line.startswith("error: ") for line in lines), (argv, err)
        assert len(lines) <= 500, (argv, len(lines))  # every problem at once, a cascade included
    for line in err.splitlines():
        assert len(line) <= LONGEST_LINE, (argv, line[:200])
    return status, out, err


def snapshot(folder: Path) -> dict[str, bytes | None]:
    """Every path below ``folder`` with the bytes of each file (None: a directory)."""
    return {str(p.relative_to(folder)): (p.read_bytes() if p.is_file() else None) for p in sorted(folder.rglob("*"))}


def assert_untouched(before: dict, folder: Path, argv, diverged: bool = False) -> None:
    """A refused run changed nothing: no file replaced, none left behind (but the
    history of a diverged simulation, ``NAME.diverged.SUFFIX``, when ``diverged``)."""
    after = snapshot(folder)
    if diverged:
        after = {name: data for name, data in after.items() if ".diverged." not in name}
    assert after == before, argv


# ------------------------------------------------------------------------- mutation

#: Numbers that break naive code: zero, signs, the ends of the double range, NaN and
#: infinity, text that is not a number, an overflow in waiting.
NASTY_NUMBERS = ["0", "-0.0", "-1", "1e-300", "5e-324", "1e300", "-1e300", "9e308", "1e999", "nan", "inf", "-inf",
                 "1e15", "1e-15", "0.5", "3", '"(((("', '"1/0"', '"a^65"', '"x"', '"2^63^64"', "true", "[]", "{}",
                 '"' + "(" * 200 + '"', '"1 km^400"', '"' + "9" * 400 + '"']
GARBAGE_LINES = ["[", "]]", "[[segment]]", "= 3", "x = ", "x = [1, 2", '"\\u0000"', "\x00", "\x7f", "é = 1",
                 "[bodies.B9]", "(1) Body", "B1, m, 0, 0, 0, 1, 1, 1, 1, 1, 1", "T9, -5, 0, C1, C1, 4",
                 "P9, C1, C1", "#", "\t\t,,,", "a" * 500, "1,2,3", "-1e300,1e300", "y_mm,z_mm", "nan,nan"]
_NUMBER = re.compile(r"(?<![A-Za-z_])-?\d+(?:\.\d*)?(?:[eE][-+]?\d+)?")


@st.composite
def mutated(draw, text: str, most: int = 3) -> str:
    """``text`` with one to ``most`` edits, each at a drawn place."""
    for _ in range(draw(st.integers(1, most))):
        lines = text.split("\n")
        where = draw(st.integers(0, max(len(lines) - 1, 0)))
        kind = draw(st.sampled_from(["number", "number", "number", "delete", "double", "swap", "insert", "cut",
                                     "char", "value"]))
        if kind == "number":
            numbers = list(_NUMBER.finditer(text))
            if numbers:
                match = numbers[draw(st.integers(0, len(numbers) - 1))]
                text = text[: match.start()] + draw(st.sampled_from(NASTY_NUMBERS)) + text[match.end():]
            continue
        if kind == "delete" and len(lines) > 1:
            del lines[where]
        elif kind == "double":
            lines.insert(where, lines[where])
        elif kind == "swap":
            other = draw(st.integers(0, max(len(lines) - 1, 0)))
            lines[where], lines[other] = lines[other], lines[where]
        elif kind == "insert":
            lines.insert(where, draw(st.sampled_from(GARBAGE_LINES)))
        elif kind == "cut":
            lines = lines[: where + 1]
            lines[-1] = lines[-1][: draw(st.integers(0, len(lines[-1])))]
        elif kind == "char" and lines[where]:
            column = draw(st.integers(0, len(lines[where]) - 1))
            replacement = draw(st.sampled_from(['"', "'", "[", "]", "=", ",", "\\", "\t", "#", "é", "\u2028", "0"]))
            lines[where] = lines[where][:column] + replacement + lines[where][column + 1:]
        elif kind == "value" and "=" in lines[where]:
            key = lines[where].split("=", 1)[0]
            lines[where] = f"{key}= {draw(st.sampled_from(NASTY_NUMBERS))}"
        text = "\n".join(lines)
    return text
