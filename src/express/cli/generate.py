"""``express generate``: the symbolic M, C, K (and P, Pd) of a model, exported."""

from __future__ import annotations

import sys
from collections.abc import Sequence
from pathlib import Path

from express.base.diagnostics import UsageError
from express.cli import common
from express.cli.runner import run_command

__all__ = ["add_parser", "main", "run"]

FORMATS = ("json", "matlab", "python", "latex", "text")


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser(
        "generate", help="symbolic M, C, K (and P, Pd) of a model",
        description="Exact symbolic equations of motion of a model, with its rail terms when it has "
        "rail data, as text, JSON (docs/conventions.md), MATLAB/Octave, Python or LaTeX.",
    )
    common.add_model_arguments(parser)
    parser.add_argument("--format", dest="fmt", choices=FORMATS, default="text", help="export format (default text)")
    parser.add_argument("-o", "--output", help="output file; '-' or none: standard output")
    parser.add_argument("--keep-virtual", action="store_true", help="keep the virtual DOFs (the paper's eq. 6)")
    parser.add_argument("--no-rail", action="store_true", help="ignore the model's rail data (core matrices only)")
    parser.set_defaults(handler=run)


def run(
    model: Path, overrides: dict[str, str], *, fmt: str = "text", output: str | None = None,
    keep_virtual: bool = False, no_rail: bool = False,
) -> int:
    """Generate and write the equations; returns the exit status."""
    from express.io.output import STDOUT, output_transaction, write_text

    output = output or STDOUT
    if fmt == "matlab" and output != STDOUT and Path(output).suffix != ".m":
        raise UsageError(f"{output}: a MATLAB function file must end in .m")
    with output_transaction(inputs=[model]) as outputs:
        outputs.declare(output)
        text, dofs = _export(model, overrides, fmt, output, keep_virtual=keep_virtual, with_rail=not no_rail)
        write_text(output, text)
    if output != STDOUT:
        common.note(f"wrote {output} ({dofs} DOFs)")
    return 0


def _export(model: Path, overrides: dict[str, str], fmt: str, output: str, *, keep_virtual: bool,
            with_rail: bool) -> tuple[str, int]:
    """The export's text and number of DOFs, written from the derivation (read back from
    the cache's generation entry when there is one, :mod:`express.numeric.generation`);
    an export's text is never copied from the cache (``docs/cache.md``)."""
    from express.export import FORMATS as EXPORTERS
    from express.export import to_matlab
    from express.io.output import STDOUT
    from express.numeric.generation import load_generation

    name = Path(output).stem if fmt == "matlab" and output != STDOUT else None
    result = load_generation(model, overrides, keep_virtual=keep_virtual, with_rail=with_rail)
    equations = result.equations
    text = to_matlab(equations, name or equations.name) if fmt == "matlab" else EXPORTERS[fmt](equations)
    common.print_warnings(tuple(str(w) for w in result.warnings))
    return text, len(equations.dofs)


def main(argv: Sequence[str] | None = None) -> int:
    """``express generate`` with ``argv`` (default ``sys.argv[1:]``) alone: its exit status
    (:func:`express.cli.runner.run_command`, the parsing and errors of :func:`express.cli.main`)."""
    return run_command(sys.modules[__name__], argv)
