"""``express draw``: plan, side and end views of a model (:mod:`express.drawing`)."""

from __future__ import annotations

import sys
from collections.abc import Sequence
from pathlib import Path

from express.cli import common
from express.cli.runner import run_command

__all__ = ["add_parser", "main", "run"]


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser(
        "draw", help="draw a model: plan, side and end views with its elements",
        description="Plan, side and end views from the body positions, connection points and elements, "
        "with springs, dampers, series elements, pins and levers as the usual symbols, labelled: "
        "how a user checks the geometry. Parameters without a value are given with --set.",
    )
    common.add_model_arguments(parser)
    parser.add_argument("-o", "--output", type=common.figure_path, required=True, metavar="FILE",
                        help="figure file (.svg, .png or .pdf)")
    parser.add_argument("--mode", metavar="BODY.MODE",
                        help="a flexible body's mode, e.g. CB.vb1: the body drawn deformed by that free-free mode "
                        "over the undeformed model (docs/model-format.md, 'Flexible bodies')")
    parser.set_defaults(handler=run)


def run(model: Path, overrides: dict[str, str], *, output: Path, mode: str | None = None) -> int:
    """Draw the model to ``output``; returns the exit status."""
    from express.analysis.plots import save_figure
    from express.drawing.views import figure_model
    from express.io.output import output_transaction

    with output_transaction(inputs=[model]) as outputs:
        outputs.declare(output, binary=True)
        geometry = _geometry(model, overrides)
        if mode is not None:
            from express.base.diagnostics import ArgumentError, UsageError
            from express.drawing.modes import figure_flexible_mode

            try:
                figure = figure_flexible_mode(geometry, mode)
            except ArgumentError as error:
                raise UsageError(str(error)) from None
            save_figure(figure, output)
        elif Path(output).suffix.lower() == ".svg":  # with each element's name and values as a tooltip
            from express.drawing.views import svg_with_tooltips
            from express.io.output import write_text

            write_text(output, svg_with_tooltips(figure_model(geometry), geometry))
        else:
            save_figure(figure_model(geometry), output)
    common.note(f"wrote {output}")
    return 0


def _geometry(model: Path, overrides: dict[str, str]):
    """The drawing geometry of the model file; without overrides through the cache's copy
    of an earlier drawing of the same files (:mod:`express.drawing.geometry_data`)."""
    if overrides:
        return model_geometry_of(common.load_model_with(model, overrides))
    from express.drawing.geometry_data import cached_geometry

    return cached_geometry(model, lambda: model_geometry_of(common.load_model_with(model, overrides)))


def model_geometry_of(model):
    """The drawing geometry of a model at its parameter values (shared with ``eigen --plot``)."""
    from express.drawing.geometry import model_geometry
    from express.model.parameters import expression_value
    from express.model.topology import classify_bodies

    values = model.values()
    return model_geometry(model, lambda expression: expression_value(expression, values), classify_bodies(model).role)


def main(argv: Sequence[str] | None = None) -> int:
    """``express draw`` with ``argv`` (default ``sys.argv[1:]``) alone: its exit status
    (:func:`express.cli.runner.run_command`, the parsing and errors of :func:`express.cli.main`)."""
    return run_command(sys.modules[__name__], argv)
