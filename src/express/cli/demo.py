"""``express demo``: the paper's results with the bundled vehicles
(:func:`express.paper.demo.run_demo`), written all together or not at all."""

from __future__ import annotations

import sys
from collections.abc import Sequence
from pathlib import Path

from express.base.diagnostics import UsageError
from express.cli import common
from express.cli.runner import run_command

__all__ = ["add_parser", "main", "run"]


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser(
        "demo", help="reproduce the paper's results with the bundled vehicles (figures, data, summary)",
        description="Writes the symbolic matrices of the bundled vehicles, the paper's Figs. 3, 9, 10 and 11 "
        "(PNG and SVG) with their data (CSV), and summary.md comparing key numbers with the paper's. "
        "Files already in OUTDIR are replaced only when every new one has been written.",
    )
    parser.add_argument("outdir", nargs="?", type=Path, default=Path("demo-out"), help="output directory (default demo-out/)")
    parser.add_argument("--examples", type=Path, metavar="DIR", help="directory of the bundled models (default: found automatically)")
    parser.set_defaults(handler=run, numeric=True)


def run(outdir: Path, *, examples: Path | None = None) -> int:
    """Run the demo inside one output transaction; returns the exit status."""
    from express.io.output import check_destination, output_transaction
    from express.paper.demo import find_examples, run_demo

    if outdir.exists() and not outdir.is_dir():
        raise UsageError(f"{outdir}: is a file, not a directory")
    check_destination(outdir / "summary.md")  # the directory can be made and written
    if examples is not None and not (examples / "forced-steering.toml").is_file():
        raise UsageError(f"--examples {examples}: no forced-steering.toml there")
    examples = find_examples(examples)  # ArgumentError when not found: the user must say where
    with output_transaction(inputs=sorted(p for p in examples.iterdir() if p.is_file())):
        summary = run_demo(outdir, examples=examples, log=common.note)
    cwd = Path.cwd()
    print(f"wrote {summary.relative_to(cwd) if summary.is_absolute() and summary.is_relative_to(cwd) else summary}")
    return 0


def main(argv: Sequence[str] | None = None) -> int:
    """``express demo`` with ``argv`` (default ``sys.argv[1:]``) alone: its exit status
    (:func:`express.cli.runner.run_command`, the parsing and errors of :func:`express.cli.main`)."""
    return run_command(sys.modules[__name__], argv)
