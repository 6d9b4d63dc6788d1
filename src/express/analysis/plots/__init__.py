"""Figures of the analyses: the paper's Figs. 3, 9, 10 and 11, runs and stability maps.

Every ``figure_*`` function takes plain arrays (SI units unless the name says km/h) and
returns a :class:`matplotlib.figure.Figure` built without pyplot: no global state, no
backend switch, so a notebook user's backend is left alone and figures are garbage
collected like any object.  The house style (:data:`STYLE`) is applied while a figure is
built and while :func:`save_figure` renders it.

:func:`save_figure` writes PNG, SVG or PDF through the project's whole-file writer
(:func:`express.io.output.write_bytes`).  Output is deterministic: fixed
``svg.hashsalt``, no date or software name in the metadata, text kept as paths.

Modules: ``_base`` (style, figure creation, saving), ``paper_figures`` (Figs. 3, 9, 10,
11 and a simulation run), ``stability_maps`` (root locus, damping ratios).

Every ``figure_*`` function also takes ``ax=``: a Matplotlib ``Axes`` (or, for a figure of
several panels, a sequence of them) to draw into; it then returns ``ax`` and leaves the
figure's layout, title and caption to the caller (:func:`axes_for`).
"""

from express.analysis.plots._base import FIGURE_SUFFIXES, STYLE, axes_for, new_figure, save_figure
from express.analysis.plots.paper_figures import (
    figure_critical_speed,
    figure_curving,
    figure_frequency_response,
    figure_frequency_responses,
    figure_lever_step,
    figure_simulation,
)
from express.analysis.plots.stability_maps import (
    figure_damping_vs_speed,
    figure_eigen_locus,
    figure_root_locus_complex,
    mode_branches,
)

__all__ = [
    "FIGURE_SUFFIXES",
    "STYLE",
    "axes_for",
    "figure_critical_speed",
    "figure_curving",
    "figure_damping_vs_speed",
    "figure_eigen_locus",
    "figure_frequency_response",
    "figure_frequency_responses",
    "figure_lever_step",
    "figure_root_locus_complex",
    "figure_simulation",
    "mode_branches",
    "new_figure",
    "save_figure",
]
