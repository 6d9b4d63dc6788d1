"""The ``express`` command line: a thin layer over the library.

``main(argv) -> int`` assembles the parser from one module per command (each with
``add_parser(subparsers)`` and a handler that receives the parsed values as keyword
arguments), runs the handler and maps what it raises to an exit status
(``docs/cli.md``):

=====  =================================================================================
0      success
1      the analysis could not give a valid result (:class:`~express.base.diagnostics.AnalysisError`)
2      bad input (:class:`~express.base.diagnostics.InputError`: a model, a value, a destination);
       one ``error:`` line per problem
70     an unexpected internal error: one line; the traceback with ``--debug``
=====  =================================================================================

Only the standard library is imported here, so ``express --help`` and ``--version``
start quickly; numerical commands run with BLAS limited to one thread (the matrices are
small, and threads only add start-up and contention).
"""

from __future__ import annotations

import argparse
from collections.abc import Sequence

from express.cli import (
    cache,
    conicity,
    contact_geometry,
    convert,
    critical_speed,
    curving,
    demo,
    draw,
    eigen,
    export,
    frf,
    generate,
    report,
    ride,
    sensitivity,
    simulate,
    study,
    twist,
    wear,
)
from express.cli.runner import parser_for, run

__all__ = ["build_parser", "main"]

COMMANDS = (generate, convert, simulate, curving, frf, eigen, critical_speed, demo, draw, export, report, study, sensitivity, ride,
            contact_geometry, conicity, cache, twist, wear)


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of the ``express`` command."""
    return parser_for(COMMANDS)


def main(argv: Sequence[str] | None = None) -> int:
    """Run the ``express`` command with ``argv`` (default: ``sys.argv[1:]``); return the
    exit status (0, 1, 2 or 70; see the module docstring; ``128 + signal`` when stopped
    by Ctrl-C, SIGTERM or SIGHUP, :mod:`express.base.interrupts`)."""
    return run(build_parser, argv)
