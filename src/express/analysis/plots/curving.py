"""Figure of steady-state curving results against the swept quantity (``docs/curving.md``)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

__all__ = ["figure_steady_curving", "sweep_axis"]


def sweep_axis(results: Sequence[Any]) -> tuple[np.ndarray, str]:
    """The quantity the results vary in (radius, else speed, else cant) and its label."""
    radius = np.array([r.curve.radius for r in results])
    speed = np.array([r.speed for r in results])
    if np.ptp(radius) > 0:
        return radius, "curve radius R [m]"
    if np.ptp(speed) > 0:
        return speed * 3.6, "speed [km/h]"
    return np.array([r.unbalanced_acceleration for r in results]), "cant deficiency [m/s²]"


def figure_steady_curving(results: Sequence[Any], *, title: str = "", labels: Sequence[str] | None = None,
                          groups: Sequence[Sequence[Any]] | None = None, ax=None):
    """Four panels against the sweep: angle of attack, the largest Y/Q, the track shift
    force of each wheelset, and the wheel unloading ΔQ/Q0.

    Parameters
    ----------
    results : sequence of SteadyCurving
        One sweep (ignored when ``groups`` is given).
    title : str
    labels, groups : sequences, optional
        Several sweeps drawn together (solid, dashed, dotted, ...), each with a label.
    ax : sequence of matplotlib.axes.Axes, optional
        Draw into these axes (four: a 2 x 2 grid's, row by row) and return them (the figure's layout, title
        and caption are then the caller's); by default a new figure is made and returned.
    """
    import matplotlib

    from express.analysis.plots import STYLE, axes_for

    sweeps = list(groups) if groups is not None else [results]
    names = list(labels) if labels is not None else [""] * len(sweeps)
    styles = ("-", "--", ":", "-.")
    with matplotlib.rc_context(STYLE):
        figure, axes = axes_for(ax, 2, 2, figsize=(8.0, 6.4), sharex=True)
        axes = axes.ravel()
        for k, (sweep, name) in enumerate(zip(sweeps, names, strict=True)):
            x, xlabel = sweep_axis(sweep)
            out = [r.wheel_rail for r in sweep]
            count = out[0].wheelsets
            for j in range(count):
                color = f"C{j}"
                label = f"{name} ws{j + 1}".strip()
                style = styles[k % len(styles)]
                axes[0].plot(x, [o.angle_of_attack[0, j] * 1e3 for o in out], style, color=color, label=label)
                axes[1].plot(x, [o.y_over_q[0, j].max() for o in out], style, color=color)
                axes[2].plot(x, [abs(o.track_shift_force[0, j]) / 1e3 for o in out], style, color=color)
            axes[3].plot(x, [o.vehicle_unloading[0] for o in out], styles[k % len(styles)], color="k", label=name or None)
        axes[0].set_ylabel("angle of attack [mrad]")
        axes[1].set_ylabel("largest Y/Q of the wheelset [-]")
        axes[2].set_ylabel("|ΣY| track shift force [kN]")
        axes[3].set_ylabel("wheel unloading ΔQ/Q0 [-]")
        for axis in axes[2:]:
            axis.set_xlabel(xlabel)
        for axis in axes:
            axis.grid(True, alpha=0.3)
        axes[0].legend(fontsize="small", ncol=2)
        if ax is not None:
            return ax
        if title:
            figure.suptitle(title)
        figure.tight_layout()
    return figure
