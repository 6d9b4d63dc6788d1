"""``express report``: one self-contained HTML page about a model (:mod:`express.report`)."""

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
        "report", help="one self-contained HTML report: drawing, parameters, equations, modes, stability",
        description="An HTML file with inline SVG figures and MathML equations, no network needed: the "
        "model drawing, the parameter table with units and sources, the equations, the modes at the "
        "model speed and, with rail data, the stability map, curving and frequency-response summaries.",
    )
    common.add_model_arguments(parser)
    parser.add_argument("--speed", type=common.SPEED, metavar="SPEED", help=common.SPEED.help(
        "speed of the report: the modes table, the curving run (over the track's own speed) and the frequency response",
        "the model's speed (the curving run: the track's speed when it has one)"))
    parser.add_argument("--track", metavar="NAME|FILE", help="track of the curving section: a bundled curve (R250, R400, "
                        "R600, R1000, R3000, paper) or a track file, run at its speed (else the model's); default: "
                        "the paper's curve, said so in the report")
    parser.add_argument("-o", "--output", required=True, metavar="FILE.html", help="output HTML file")
    parser.set_defaults(handler=run, numeric=True)


def run(model: Path, overrides: dict[str, str], *, output: str, speed: float | None = None,
        track: str | None = None) -> int:
    """Write the report; returns the exit status."""
    from express.io.finite import require_finite_text
    from express.io.output import output_transaction, write_text
    from express.numeric.generation import load_generation
    from express.numeric.statespace import load_vehicle
    from express.report.build import report_html

    inputs = [model] + ([Path(track)] if track is not None and Path(track).is_file() else [])
    with output_transaction(inputs=inputs) as outputs:
        outputs.declare(output)
        road, where = common.track_and_name(track)
        vehicle = load_vehicle(model, overrides)
        if track is not None:
            from express.analysis.curving.steady import track_problems
            from express.report.build import curving_speed

            problems = track_problems(vehicle, road, curving_speed(vehicle, road, speed)[0])
            if problems:
                raise UsageError("\n".join(f"report: {problem}" for problem in problems))
        readable = load_generation(model, overrides).equations  # factored for people (docs/cache.md)
        html = report_html(vehicle, speed=speed, track=road if track is not None else None, track_name=where,
                           equations=readable)
        require_finite_text("report", html)  # no nan or inf printed as a result (docs/reliability.md)
        write_text(output, html)
    common.note(f"wrote {output}")
    return 0


def main(argv: Sequence[str] | None = None) -> int:
    """``express report`` with ``argv`` (default ``sys.argv[1:]``) alone: its exit status
    (:func:`express.cli.runner.run_command`, the parsing and errors of :func:`express.cli.main`)."""
    return run_command(sys.modules[__name__], argv)
