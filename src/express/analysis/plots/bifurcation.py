"""Bifurcation diagram of hunting: the limit-cycle amplitude against speed from the
ramp-down (:func:`express.analysis.stability.nonlinear_stability.nonlinear_critical_speed`), with
the centred running's stability and the linear and nonlinear critical speeds."""

from __future__ import annotations

import numpy as np

from express.analysis.plots._base import BLUE, GREY, ORANGE, RED, axes_for, styled
from express.base.diagnostics import ArgumentError

__all__ = ["figure_bifurcation"]


@styled
def figure_bifurcation(speeds_kmh, amplitudes_mm, alive, *, title: str, nonlinear_kmh: float | None = None,
                       linear_kmh: float | None = None, flange_clearance_mm: float | None = None, ax=None):
    """Limit-cycle amplitude against speed.

    Parameters
    ----------
    speeds_kmh, amplitudes_mm : array_like, shape (P,)
        Every run of the ramp-down: speed [km/h] and amplitude [mm] (largest |y| of the
        watched wheelset in the run's last third).
    alive : array_like of bool, shape (P,)
        Whether the run held a limit cycle (filled markers; hollow: the motion died).
    title : str
    nonlinear_kmh, linear_kmh : float, optional
        The nonlinear and linear critical speeds [km/h], marked; the centred running is
        drawn stable (solid) below the linear one and unstable (dashed) above.
    flange_clearance_mm : float, optional
        Where the flanges touch (centred wheelset), a horizontal guide.
    ax : matplotlib.axes.Axes, optional
        Draw into this axes and return it (the figure's layout, title and caption are then
        the caller's); by default a new figure is made and returned.
    """
    speeds = np.asarray(speeds_kmh, dtype=float)
    amplitudes = np.asarray(amplitudes_mm, dtype=float)
    live = np.asarray(alive, dtype=bool)
    if speeds.ndim != 1 or speeds.shape != amplitudes.shape or speeds.shape != live.shape or not speeds.size:
        raise ArgumentError("speeds, amplitudes and alive must be 1-D arrays of one length >= 1")
    figure, axis = axes_for(ax, figsize=(7.0, 4.4))
    order = np.argsort(speeds[live])
    axis.plot(speeds[live][order], amplitudes[live][order], color=RED, linewidth=1.0, alpha=0.6)
    axis.plot(speeds[live], amplitudes[live], "o", color=RED, markersize=4, label="limit cycle (ramp-down)")
    if (~live).any():
        axis.plot(speeds[~live], amplitudes[~live], "o", markerfacecolor="none", color=GREY, markersize=4,
                  label="motion dies out")
    low, high = float(speeds.min()), float(speeds.max())
    span = max(high - low, 1.0)
    low, high = low - 0.05 * span, high + 0.05 * span
    if linear_kmh is not None:
        axis.plot([low, min(linear_kmh, high)], [0, 0], color="black", linewidth=2.0, label="centred running stable")
        if linear_kmh < high:
            axis.plot([linear_kmh, high], [0, 0], color="black", linewidth=1.5, linestyle="--",
                      label="centred running unstable")
        axis.axvline(linear_kmh, color=BLUE, linestyle="--", linewidth=1.2,
                     label=f"linear critical speed {linear_kmh:.1f} km/h")
    if nonlinear_kmh is not None:
        axis.axvline(nonlinear_kmh, color=ORANGE, linestyle="-", linewidth=1.4,
                     label=f"nonlinear critical speed {nonlinear_kmh:.1f} km/h")
    if flange_clearance_mm is not None:
        axis.axhline(flange_clearance_mm, color=GREY, linestyle=":", linewidth=1.0,
                     label=f"flange contact ({flange_clearance_mm:.2f} mm)")
    axis.set_xlim(low, high)
    axis.set_ylim(bottom=-0.3)
    axis.set_xlabel("speed V [km/h]")
    axis.set_ylabel("limit-cycle amplitude, leading wheelset [mm]")
    axis.set_title(title)
    axis.legend(loc="upper left", framealpha=0.9, fontsize="small")
    if ax is not None:
        return ax
    figure.tight_layout()
    return figure
