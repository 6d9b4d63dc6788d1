"""Figures of studies and sensitivities (pyplot-free, house style of
:mod:`express.analysis.plots`): a critical-speed map over two parameters, a curve over
one, and the ranked tornado chart of a sensitivity."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

__all__ = ["figure_study_map", "figure_tornado"]

from express.base.units import KMH


def figure_study_map(
    axes: Sequence[tuple], values: np.ndarray, *, label: str, title: str,
    scale: float = 1.0, unit: str = "", ax=None,
):
    """A grid study's output over one parameter (a curve) or two (filled contours).

    Parameters
    ----------
    axes : sequence of (name, values, display factor, display unit[, scale])
        One or two parameters: their grid values (SI) and how to show them (the values
        are divided by the factor, e.g. 1e6 for MN/m); ``scale`` ``"log"`` draws that
        axis logarithmically.
    values : numpy.ndarray, shape (len(axes[0][1]),) or (len(axes[0][1]), len(axes[1][1]))
        The output on the grid (SI); nan where it has none.
    label : str
        The output's name for the colour bar / y axis.
    scale, unit : float, str
        Display factor and unit of the output (``1/3.6``, ``"km/h"``).
    ax : matplotlib.axes.Axes, optional
        Draw into this axes and return it (the figure's layout is then the caller's; a
        colour bar takes its room from ``ax``); by default a new figure is made and returned.

    Returns
    -------
    matplotlib.figure.Figure or matplotlib.axes.Axes
    """
    import textwrap

    import matplotlib
    from matplotlib.ticker import ScalarFormatter

    from express.analysis.plots import STYLE, axes_for

    def unpack(entry):
        name, grid, factor, shown_unit = entry[:4]
        return name, np.asarray(grid, dtype=float) / factor, f"{name} [{shown_unit}]" if shown_unit else name, \
            (entry[4] if len(entry) > 4 else "linear")

    with matplotlib.rc_context(STYLE):
        figure, axis = axes_for(ax, figsize=(6.4, 4.8))
        shown = np.asarray(values, dtype=float) / scale
        quantity = f"{label} [{unit}]" if unit else label
        _name0, x, xlabel, xscale = unpack(axes[0])
        if len(axes) == 1:
            axis.plot(x, shown, marker="o", markersize=3)
            axis.set_ylabel(quantity)
        else:
            _name1, y, ylabel, yscale = unpack(axes[1])
            grid_x, grid_y = np.meshgrid(x, y, indexing="ij")
            finite = shown[np.isfinite(shown)]
            masked = np.ma.masked_invalid(shown)
            filled = axis.contourf(grid_x, grid_y, masked, levels=_levels(finite), cmap="viridis")
            lines = axis.contour(grid_x, grid_y, masked, levels=filled.levels[1:-1:2], colors="k", linewidths=0.5)
            axis.clabel(lines, fmt="%.0f", fontsize=7)
            figure.colorbar(filled, ax=axis).set_label(quantity)
            axis.set_ylabel(ylabel)
            axis.set_yscale(yscale)
            axis.grid(False)
        axis.set_xlabel(xlabel)
        axis.set_xscale(xscale)
        for which, chosen in ((axis.xaxis, xscale), (axis.yaxis, yscale if len(axes) > 1 else "linear")):
            if chosen == "log":  # plain numbers on a log axis
                which.set_major_formatter(ScalarFormatter())
                which.set_minor_formatter(ScalarFormatter())
        axis.set_title("\n".join(textwrap.wrap(title, 64)))
        if ax is not None:
            return ax
        figure.tight_layout()
    return figure


def _levels(values: np.ndarray, count: int = 16) -> np.ndarray | int:
    """Contour levels at equal shares of the values (rounded), so that a map whose values
    fall into separate ranges (a region of low-speed instability beside the usual
    hunting) shows detail in each of them."""
    if values.size == 0 or np.ptp(values) == 0:
        return 10
    step = 10.0 ** np.floor(np.log10(np.ptp(values) / 100.0))
    levels = np.unique(np.round(np.quantile(values, np.linspace(0.0, 1.0, count + 1)) / step) * step)
    levels[0], levels[-1] = min(levels[0], values.min()), max(levels[-1], values.max())
    return levels if levels.size >= 3 else 10


def figure_tornado(result, *, top: int = 15, change: float = 0.1, title: str = "", ax=None):
    """Ranked tornado chart of a critical-speed sensitivity.

    Each bar is the first-order change of the critical speed [km/h] when one parameter
    is raised (right of its bar's sign) or lowered by ``change`` (10 %), i.e.
    ``+/- change * p * dV/dp``; the label gives the elasticity ``(p/V) dV/dp``.

    Parameters
    ----------
    result : CriticalSpeedSensitivity
    top : int
        Parameters shown, largest elasticity first.
    change : float
        Relative parameter change of the bars.
    ax : matplotlib.axes.Axes, optional
        Draw into this axes and return it (the figure's layout is then the caller's); by
        default a new figure is made and returned.

    Returns
    -------
    matplotlib.figure.Figure or matplotlib.axes.Axes
    """
    import matplotlib

    from express.analysis.plots import STYLE, axes_for

    ranked = [s for s in result.ranked() if s.elasticity != 0][:top]
    with matplotlib.rc_context(STYLE):
        figure, axis = axes_for(ax, figsize=(6.4, 0.8 + 0.32 * max(len(ranked), 1)))
        positions = np.arange(len(ranked))[::-1]
        for y, s in zip(positions, ranked, strict=True):
            delta = change * s.value * s.derivative / KMH
            axis.barh(y, delta, color="#d62728", height=0.7)
            axis.barh(y, -delta, color="#1f77b4", height=0.7)
            axis.text(abs(delta) * 1.04 if delta else 0, y, f" e = {s.elasticity:+.3f}", va="center", fontsize=7.5)
        axis.set_yticks(positions, [s.name for s in ranked])
        axis.axvline(0.0, color="k", linewidth=0.8)
        axis.set_xlabel(f"change of the critical speed [km/h] for the parameter {change:+.0%} (red) / {-change:+.0%} (blue)")
        span = max((abs(change * s.value * s.derivative / KMH) for s in ranked), default=1.0) or 1.0
        axis.set_xlim(-1.35 * span, 1.6 * span)
        axis.set_title(title or f"critical speed {result.critical_speed / KMH:.1f} km/h: sensitivities (e = elasticity)")
        if ax is not None:
            return ax
        figure.tight_layout()
    return figure
