"""How a command runs: the parser, the handler, what it raises mapped to an exit status,
BLAS on one thread, the derivation cache switch, warnings and errors as one line each
(the table of exit statuses: :mod:`express.cli`). Used by :func:`express.cli.main` for
every command and by each command module's own ``main(argv)`` for itself."""

from __future__ import annotations

import argparse
import contextlib
import os
import re
import sys
import time
import traceback
import warnings
from collections.abc import Callable, Iterator, Sequence
from types import ModuleType
from typing import Any, NoReturn

from express import __version__
from express.base.diagnostics import EXIT_ANALYSIS, EXIT_INPUT, EXIT_INTERNAL, EXIT_OK, AnalysisError, InputError
from express.base.interrupts import handling_signals, remove_temporaries
from express.base.kernel_cache import compilation_note
from express.cli import common

__all__ = ["MAX_LINE", "MAX_PROBLEMS", "MAX_QUOTE", "parser_for", "printable", "run", "run_command", "shortened"]

_META = ("handler", "numeric", "debug", "command", "no_cache")


class _Parser(argparse.ArgumentParser):
    """An argument parser whose mistakes are one ``error:`` line and status 2."""

    def error(self, message: str) -> NoReturn:
        choice = re.search(r"invalid choice: '([^']*)' \(choose from (.*)\)", message)
        if choice:  # the same hint as every other name (express.base.names)
            from express.base.names import did_you_mean

            hint = did_you_mean(choice.group(1), re.findall(r"'([^']*)'", choice.group(2)))
            message = message.replace(" (choose from", f"{hint} (choose from", 1)
        message = _LONG_QUOTE.sub(lambda m: f'"{m.group(1)[:MAX_QUOTE - 3]}..." ({len(m.group(1))} characters)', message)
        self.exit(EXIT_INPUT, f"error: {shortened(f'{self.prog}: {message}')} (see {self.prog} --help)\n")


def parser_for(commands_: Sequence[ModuleType]) -> argparse.ArgumentParser:
    """The argument parser of the ``express`` command with ``commands_`` (modules with
    ``add_parser(subparsers)``)."""
    parser = _Parser(
        prog="express",
        description="Exact symbolic equations of motion and dynamics of rail vehicles.",
        epilog="A bare number is SI, except speeds (km/h) and --amplitude (mm); any quantity may carry "
        "a unit ('30 m/s', '2 mm'). Exit status: 0 success, 1 no valid result, 2 bad input, "
        "3 a failed assessment (simulate --assess), 70 internal error. See docs/cli.md.",
    )
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    parser.add_argument("--debug", action="store_true", help="show the traceback of an internal error")
    commands = parser.add_subparsers(dest="command", metavar="COMMAND")
    commands.required = True
    for command in commands_:
        command.add_parser(commands)
    for sub in commands.choices.values():
        sub.add_argument("--debug", action="store_true", default=argparse.SUPPRESS, help=argparse.SUPPRESS)
        sub.add_argument("--no-cache", action="store_true", default=argparse.SUPPRESS,
                         help="derive the model anew and store nothing (also EXPRESS_NO_CACHE=1; docs/cache.md)")
    return parser


@contextlib.contextmanager
def _one_blas_thread(numeric: bool) -> Iterator[None]:
    """BLAS on one thread while a numerical command runs (restored afterwards;
    :mod:`express.base.threads`); commands that compute nothing numerical skip all of it."""
    if not numeric:
        yield
        return
    from express.base.threads import blas_threads  # the library's own limit (EXPRESS_BLAS_THREADS)

    with blas_threads():
        yield


@contextlib.contextmanager
def _cache_switch(no_cache: bool) -> Iterator[None]:
    """The derivation cache off for ``--no-cache`` (:mod:`express.io.cache`), in this
    process and in the workers it starts (``EXPRESS_NO_CACHE``)."""
    if not no_cache:
        yield
        return
    from express.io.cache import disabled

    before = os.environ.get("EXPRESS_NO_CACHE")
    os.environ["EXPRESS_NO_CACHE"] = "1"
    try:
        with disabled():
            yield
    finally:
        if before is None:
            os.environ.pop("EXPRESS_NO_CACHE", None)
        else:
            os.environ["EXPRESS_NO_CACHE"] = before


def printable(text: str) -> str:
    """``text`` with control characters (a newline, NEL, escape sequences the user typed)
    shown as ``\\xNN`` escapes: an error line stays one line and cannot drive the terminal."""
    return "".join(c if c.isprintable() else repr(c)[1:-1] for c in text)


def _show_warning(message, category, filename, lineno, file=None, line=None) -> None:
    """A warning (a negative stiffness in the model, ...) as one ``warning:`` line."""
    print(f"warning: {printable(str(message))}", file=sys.stderr)


#: Characters of the user's input quoted back in a command-line error.
MAX_QUOTE = 200
_COUNT_LINE = re.compile(r"\d+ bad rows in all, the first \d+ listed$")
_LONG_QUOTE = re.compile(f'"([^"]{{{MAX_QUOTE + 1},}})"')
#: Problems printed of one error; the rest are counted (a file with 1000 bad lines).
MAX_PROBLEMS = 20
#: Characters of one error line; a longer one is cut (it quotes too much input).
MAX_LINE = 500


def shortened(line: str) -> str:
    """``line`` (made printable) cut to :data:`MAX_LINE` characters, saying how much was left out."""
    line = printable(line)
    if len(line) <= MAX_LINE:
        return line
    return f"{line[:MAX_LINE - 40]}... ({len(line) - MAX_LINE + 40} more characters)"


def _print_error_lines(lines: Sequence[str]) -> None:
    """One ``error:`` line per problem: the first :data:`MAX_PROBLEMS`, then a count (a
    list that ends in its own count, :class:`~express.base.diagnostics.RowProblems`, has
    one line more)."""
    counts = [line for line in lines if _COUNT_LINE.search(line)]  # a reader's own count is kept
    problems = [line for line in lines if not _COUNT_LINE.search(line)]
    for line in problems[:MAX_PROBLEMS]:
        print(f"error: {shortened(line)}", file=sys.stderr)
    if len(problems) > MAX_PROBLEMS + 1:
        print(f"error: ... and {len(problems) - MAX_PROBLEMS} more problems ({len(problems)} in all, the first "
              f"{MAX_PROBLEMS} shown)", file=sys.stderr)
    elif len(problems) == MAX_PROBLEMS + 1:
        print(f"error: {shortened(problems[-1])}", file=sys.stderr)
    for line in counts:
        print(f"error: {shortened(line)}", file=sys.stderr)


def _internal_error(error: BaseException, debug: bool) -> int:
    if debug:
        traceback.print_exception(type(error), error, error.__traceback__, file=sys.stderr)
    message = printable(str(error).split("\n")[0][:200])
    hint = "" if debug else " (run with --debug for the traceback)"
    print(f"error: internal error: {type(error).__name__}: {message}{hint}", file=sys.stderr)
    return EXIT_INTERNAL


def _quiet_stdout() -> None:
    """After a broken pipe, point stdout at /dev/null so that the interpreter's final
    flush does not complain (the reader has gone: nothing more is wanted)."""
    with contextlib.suppress(AttributeError, OSError, ValueError):
        null = os.open(os.devnull, os.O_WRONLY)
        os.dup2(null, sys.stdout.fileno())
        os.close(null)


def _run(parser: argparse.ArgumentParser, argv: Sequence[str] | None) -> int:
    try:
        args = parser.parse_args(None if argv is None else common.join_negative_values(list(argv)))
    except SystemExit as exit_:  # --help, --version, a usage mistake
        return exit_.code if isinstance(exit_.code, int) else (EXIT_OK if exit_.code is None else EXIT_INPUT)
    values: dict[str, Any] = vars(args)
    handler = values["handler"]
    numeric = bool(values.get("numeric", False))
    command = str(values.get("command"))
    no_cache = bool(values.get("no_cache", False))
    for key in _META:
        values.pop(key, None)
    started = time.perf_counter()
    with _one_blas_thread(numeric), _cache_switch(no_cache), warnings.catch_warnings(), _finite_stdout(command):
        warnings.showwarning = _show_warning
        status = int(handler(**values))
    note = compilation_note(time.perf_counter() - started)
    if note is not None:
        common.note(note)
    return status


@contextlib.contextmanager
def _finite_stdout(command: str) -> Iterator[None]:
    """What the command prints on standard output passes :class:`~express.io.finite.FiniteText`:
    a nan or inf printed as a result is status 1 (``docs/reliability.md``)."""
    from express.io.finite import FiniteText

    stdout = sys.stdout
    sys.stdout = FiniteText(stdout, command)
    try:
        yield
    finally:
        sys.stdout = stdout


def run(build: Callable[[], argparse.ArgumentParser], argv: Sequence[str] | None = None) -> int:
    """Run the parser ``build()`` gives on ``argv`` (default: ``sys.argv[1:]``); return the
    exit status (0, 1, 2 or 70; see :mod:`express.cli`; ``128 + signal`` when stopped
    by Ctrl-C, SIGTERM or SIGHUP, :mod:`express.base.interrupts`)."""
    arguments = list(sys.argv[1:] if argv is None else argv)
    if not arguments:
        parser = build()
        parser.print_usage(sys.stderr)
        print("error: express: give a COMMAND (see express --help)", file=sys.stderr)
        return EXIT_INPUT
    # Run from the command line (argv None), the process ends right after: the handlers
    # stay, so that a signal while it exits cannot print a traceback.
    with handling_signals(keep=argv is None):
        return _status(build, arguments, "--debug" in arguments)


def run_command(module: ModuleType, argv: Sequence[str] | None = None) -> int:
    """``express <command> argv...`` for the command of ``module`` alone (its
    ``main(argv)``): the same parsing, errors and exit status as :func:`express.cli.main`."""
    name = module.__name__.rsplit(".", 1)[-1].replace("_", "-")
    return run(lambda: parser_for([module]), [name, *(sys.argv[1:] if argv is None else argv)])


def _status(build: Callable[[], argparse.ArgumentParser], arguments: list[str], debug: bool) -> int:
    try:
        return _run(build(), arguments)
    except InputError as error:
        _print_error_lines(error.lines())
        return EXIT_INPUT
    except AnalysisError as error:
        _print_error_lines(str(error).split("\n") if str(error) else [type(error).__name__])
        return EXIT_ANALYSIS
    except BrokenPipeError:  # e.g. `express generate ... | head`
        _quiet_stdout()
        return EXIT_OK
    except KeyboardInterrupt as error:  # the first Ctrl-C, SIGTERM or SIGHUP
        remove_temporaries()
        print("error: interrupted", file=sys.stderr)
        return getattr(error, "status", 130)
    except Exception as error:
        return _internal_error(error, debug)
