"""``express report``: one self-contained HTML page about a model (:mod:`express.report`)."""

from __future__ import annotations

from pathlib import Path

from express.cli import common

__all__ = ["add_parser", "run"]


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser(
        "report", help="one self-contained HTML report: drawing, parameters, equations, modes, stability",
        description="An HTML file with inline SVG figures and MathML equations, no network needed: the "
        "model drawing, the parameter table with units and sources, the equations, the modes at the "
        "model speed and, with rail data, the stability map, curving and frequency-response summaries.",
    )
    common.add_model_arguments(parser)
    parser.add_argument("--speed", type=common.SPEED, metavar="SPEED", help=common.SPEED.help("speed of the modes table", "the model's speed"))
    parser.add_argument("-o", "--output", required=True, metavar="FILE.html", help="output HTML file")
    parser.set_defaults(handler=run, numeric=True)


def run(model: Path, overrides: dict[str, str], *, output: str, speed: float | None = None) -> int:
    """Write the report; returns the exit status."""
    from express.io.output import output_transaction, write_text
    from express.numeric.statespace import load_vehicle
    from express.report.build import report_html

    with output_transaction(inputs=[model]) as outputs:
        outputs.declare(output)
        vehicle = load_vehicle(model, overrides)
        write_text(output, report_html(vehicle, speed=speed))
    common.note(f"wrote {output}")
    return 0
