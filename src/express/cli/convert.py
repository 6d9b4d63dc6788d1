"""``express convert``: a model (classic or modern) written in the modern TOML format."""

from __future__ import annotations

import sys
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from express.cli import common
from express.cli.runner import run_command

__all__ = ["add_parser", "main", "run"]


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser(
        "convert", help="convert a classic model file to the modern TOML format",
        description="Read a model (classic .exp or modern .toml, with --set overrides) and write it "
        "in the modern TOML format (docs/model-format.md).",
    )
    common.add_model_arguments(parser)
    parser.add_argument("-o", "--output", help="output .toml file; '-' or none: standard output")
    parser.set_defaults(handler=run)


def run(model: Path, overrides: dict[str, str], *, output: str | None = None) -> int:
    """Convert and write; returns the exit status."""
    from express.io import model_to_toml
    from express.io.output import STDOUT, output_transaction, write_text

    output = output or STDOUT
    with output_transaction(inputs=[model]) as outputs:
        outputs.declare(output)
        folder = Path.cwd() if output == STDOUT else Path(output).parent
        original = common.load_model_with(model, overrides)
        text = model_to_toml(original, folder)
        _check_loads_back(text, output, original)
        write_text(output, text)
    if output != STDOUT:
        common.note(f"wrote {output}")
    return 0


def _check_loads_back(text: str, output: str, original: Any) -> None:
    """Every file ``convert`` writes loads back; one that would not is a bug of the
    writer, reported as an internal error before anything is written."""
    from express.base.diagnostics import ModelError
    from express.io import parse_toml_model
    from express.model.parameters import undefined_name_problems

    try:
        model = parse_toml_model(text, source=output)
    except ModelError as error:
        raise RuntimeError(f"the converted model does not load back: {error.lines()[0]}") from None
    # names the original leaves undefined (a classic file's values come with the run) may
    # stay so; any other is a name the writer lost
    before = {p.message for p in undefined_name_problems(original)}
    lost = [p for p in undefined_name_problems(model) if p.message not in before]
    if lost:
        raise RuntimeError(f"the converted model does not load back: {lost[0].message}")


def main(argv: Sequence[str] | None = None) -> int:
    """``express convert`` with ``argv`` (default ``sys.argv[1:]``) alone: its exit status
    (:func:`express.cli.runner.run_command`, the parsing and errors of :func:`express.cli.main`)."""
    return run_command(sys.modules[__name__], argv)
