"""Figures of the ride analysis: acceleration PSDs with their comfort-weighted curves.

Figure functions take plain arrays and return a :class:`matplotlib.figure.Figure` built
without pyplot (the house style of :mod:`express.analysis.plots` applied locally);
save them with :func:`express.analysis.plots.save_figure`.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
from numpy.typing import ArrayLike

from express.analysis.ride.weighting import WB, WD, sperling_weighting
from express.base.diagnostics import ArgumentError

__all__ = ["figure_ride_spectra"]

_TITLES = {"x": "longitudinal", "y": "lateral", "z": "vertical"}
_EN12299 = {"x": WD, "y": WD, "z": WB}
_SPERLING = {"y": "lateral", "z": "vertical"}
_COLOURS = ("#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#555555")


def figure_ride_spectra(
    frequencies: ArrayLike,
    spectra: Mapping[str, Mapping[str, ArrayLike]],
    *,
    title: str = "car-body acceleration PSDs",
    caption: str | None = None,
    ax=None,
):
    """Acceleration PSDs of output points, one panel per direction, log-log.

    Each point's PSD ``G`` is drawn solid, the EN 12299 weighted ``|W|^2 G`` (Wd for x
    and y, Wb for z) dashed and Sperling's ``B^2 G`` (lateral ``B_y`` for y, vertical
    ``B_z`` for z) dotted, in the same colour.

    Parameters
    ----------
    frequencies : array_like, shape (F,)
        [Hz] > 0.
    spectra : mapping of str to mapping of str to array_like
        Point name -> axis (``"x"``, ``"y"``, ``"z"``) -> PSD [(m/s^2)^2/Hz], shape (F,).
        Axes absent from every point get no panel.
    title, caption : str
    ax : matplotlib.axes.Axes or sequence of them, optional
        Draw into these axes (one per panel drawn, in the order y, z, x) and return them
        (the figure's layout, title and caption are then the caller's); by default a new
        figure is made and returned.
    """
    import matplotlib

    from express.analysis.plots import STYLE, axes_for

    f = np.asarray(frequencies, dtype=float)
    axes_used = [axis for axis in ("y", "z", "x") if any(axis in by_axis for by_axis in spectra.values())]
    if not axes_used:
        raise ArgumentError("figure_ride_spectra: no spectrum to draw")
    with matplotlib.rc_context(STYLE):
        figure, panels = axes_for(ax, 1, len(axes_used), figsize=(4.4 * len(axes_used) + 0.8, 4.4), sharey=False)
        panels = np.atleast_1d(panels)
        for panel, axis in zip(panels, axes_used, strict=True):
            for k, (point, by_axis) in enumerate(spectra.items()):
                if axis not in by_axis:
                    continue
                g = np.asarray(by_axis[axis], dtype=float)
                colour = _COLOURS[k % len(_COLOURS)]
                panel.loglog(f, g, color=colour, label=f"{point}")
                panel.loglog(f, _EN12299[axis].magnitude(f) ** 2 * g, color=colour, linestyle="--", linewidth=1.1,
                             label=f"{point}, |{_EN12299[axis].name}|²G")
                if axis in _SPERLING:
                    panel.loglog(f, sperling_weighting(f, _SPERLING[axis]) ** 2 * g, color=colour, linestyle=":",
                                 linewidth=1.2, label=f"{point}, B²G (Sperling)")
            _limits(panel, f, [np.asarray(b[axis], dtype=float) for b in spectra.values() if axis in b])
            panel.set_xlabel("frequency f [Hz]")
            panel.set_ylabel("PSD [(m/s²)²/Hz]")
            panel.set_title(f"{_TITLES[axis]} ({axis})")
            panel.grid(True, which="minor", alpha=0.15)
            panel.legend(loc="lower left", fontsize=7.0, framealpha=0.9)
        if ax is not None:
            return ax
        figure.suptitle(title)
        figure.tight_layout(rect=(0, 0.05 if caption else 0, 1, 1))
        if caption:
            figure.text(0.01, 0.005, caption, fontsize=7.5, color="#555555", ha="left", va="bottom", wrap=True)
    return figure


def _limits(panel, f: np.ndarray, curves: list[np.ndarray]) -> None:
    """Frequency range of the data; six decades below the highest PSD."""
    panel.set_xlim(float(f[0]), float(f[-1]))
    top = max((float(np.max(c)) for c in curves), default=0.0)
    if top > 0:
        panel.set_ylim(top * 1e-6, top * 3.0)
