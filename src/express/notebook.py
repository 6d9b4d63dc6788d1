"""EXPRESS in Jupyter: ``%load_ext express.notebook``.

Most results display themselves without it: the equations as LaTeX
(:meth:`express.assembly.equations.EquationsOfMotion._repr_latex_`), the modes and the
track responses as tables with units (:meth:`express.analysis.modes.modes.EigenResult.to_pandas`,
:meth:`express.analysis.frequency.track_response.TrackFrequencyResponse.to_xarray`).  A vehicle
(:class:`express.numeric.statespace.VehicleModel`) draws itself as SVG once this
extension is loaded: the drawing is a later stage than the numerical model, so the
numerical model cannot import it (``docs/architecture.md``); the extension registers the
drawing with IPython instead.  ``docs/notebook.md`` and ``examples/notebook.ipynb`` show a
session from a model file to a critical-speed map.
"""

from __future__ import annotations

from typing import Any

__all__ = ["load_ipython_extension", "vehicle_svg"]


def vehicle_svg(vehicle: Any) -> str:
    """The plan, side and end views of a vehicle's model as SVG text with tooltips
    (:func:`express.drawing.views.svg_with_tooltips`)."""
    from express.drawing.geometry import model_geometry
    from express.drawing.views import figure_model, svg_with_tooltips
    from express.model.parameters import expression_value
    from express.model.topology import classify_bodies

    model = vehicle.model
    if model is None:
        raise ValueError("this VehicleModel has no model to draw")
    values = model.values()
    geometry = model_geometry(model, lambda e: expression_value(e, values), classify_bodies(model).role)
    svg = svg_with_tooltips(figure_model(geometry), geometry)
    return svg[svg.index("<svg"):]


def load_ipython_extension(ipython: Any) -> None:
    """Register the vehicle drawing as the SVG display of a ``VehicleModel``."""
    from express.numeric.statespace import VehicleModel

    formatter = ipython.display_formatter.formatters["image/svg+xml"]
    formatter.for_type(VehicleModel, vehicle_svg)
