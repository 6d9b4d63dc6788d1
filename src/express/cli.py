"""The ``express`` command line: a thin layer over the library.

``main(argv) -> int`` parses arguments, calls the library and writes outputs whole
(to a temporary file renamed into place).  A bad model prints one line per problem,
``file:line: item: message``, and returns 2; nothing is written.
"""

from __future__ import annotations

import os

# EXPRESS's numerical matrices are small (tens of DOFs): multithreaded BLAS only adds
# contention, which on a busy machine makes a simulation many times slower.  The
# command line therefore runs BLAS on one thread unless the user says otherwise.
for _variable in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_variable, "1")

import argparse  # noqa: E402
import sys  # noqa: E402
from collections.abc import Sequence  # noqa: E402
from pathlib import Path  # noqa: E402

from . import __version__  # noqa: E402
from .diagnostics import ModelError, Problem, UsageError  # noqa: E402
from .io.output import parse_assignments, write_output  # noqa: E402

__all__ = ["main", "write_output", "parse_assignments", "UsageError"]

EXIT_OK, EXIT_FAILURE, EXIT_USAGE = 0, 1, 2


def _load(args: argparse.Namespace):
    from .io import load_model
    from .model import with_values
    from .rail.build import with_creep_coefficients

    model = load_model(args.model)
    overrides = parse_assignments(args.set or [])
    return with_creep_coefficients(with_values(model, overrides)) if overrides else model


def _print_warnings(warnings: Sequence[Problem]) -> None:
    for warning in warnings:
        print(f"warning: {warning}", file=sys.stderr)


def _command_generate(args: argparse.Namespace) -> int:
    from .export import FORMATS
    from .rail.build import generate_vehicle

    model = _load(args)
    result = generate_vehicle(model, keep_virtual=args.keep_virtual, with_rail=not args.no_rail)
    _print_warnings(result.warnings)
    equations = result.equations
    exporter = FORMATS[args.format]
    if args.format == "matlab":
        name = Path(args.output).stem if args.output else equations.name
        text = exporter(equations, name=name)
    else:
        text = exporter(equations)
    if args.output:
        output = Path(args.output)
        if args.format == "matlab" and output.suffix != ".m":
            raise UsageError(f"{output}: a MATLAB function file must end in .m")
        write_output(output, text, inputs=[Path(args.model)])
        print(f"wrote {output} ({len(equations.dofs)} DOFs)", file=sys.stderr)
    else:
        sys.stdout.write(text)
    return EXIT_OK


def _command_convert(args: argparse.Namespace) -> int:
    from .io import model_to_toml

    model = _load(args)
    text = model_to_toml(model)
    if args.output:
        write_output(Path(args.output), text, inputs=[Path(args.model)])
    else:
        sys.stdout.write(text)
    return EXIT_OK


def _add_model_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("model", help="model file: classic (.exp) or modern (.toml)")
    parser.add_argument(
        "--set",
        action="append",
        metavar="NAME=VALUE",
        help="override a parameter value, e.g. --set Gamma=0.05 --set 'v=100 km/h' (repeatable)",
    )


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of the ``express`` command."""
    parser = argparse.ArgumentParser(
        prog="express",
        description="Exact symbolic equations of motion and dynamics of rail vehicles.",
    )
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    commands = parser.add_subparsers(dest="command", metavar="COMMAND")
    commands.required = True

    generate = commands.add_parser("generate", help="symbolic M, C, K (and P, Pd) of a model")
    _add_model_arguments(generate)
    generate.add_argument(
        "--format", choices=("json", "matlab", "python", "latex", "text"), default="text"
    )
    generate.add_argument("-o", "--output", help="output file (default: standard output)")
    generate.add_argument(
        "--keep-virtual", action="store_true", help="keep the virtual DOFs (the paper's eq. 6)"
    )
    generate.add_argument(
        "--no-rail", action="store_true", help="ignore the model's rail data (core matrices only)"
    )
    generate.set_defaults(handler=_command_generate)

    convert = commands.add_parser("convert", help="convert a classic model file to the modern TOML format")
    _add_model_arguments(convert)
    convert.add_argument("-o", "--output", help="output .toml file (default: standard output)")
    convert.set_defaults(handler=_command_convert)

    from .analysis.commands import add_analysis_commands

    add_analysis_commands(commands, _add_model_arguments)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run the ``express`` command; returns the exit status."""
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return args.handler(args, **({"load": _load} if getattr(args, "needs_loader", False) else {}))
    except ModelError as error:
        for problem in error.problems:
            print(f"error: {problem}", file=sys.stderr)
        return EXIT_USAGE
    except UsageError as error:
        print(f"error: {error}", file=sys.stderr)
        return EXIT_USAGE
    except BrokenPipeError:  # pragma: no cover - e.g. `express generate ... | head`
        return EXIT_OK
