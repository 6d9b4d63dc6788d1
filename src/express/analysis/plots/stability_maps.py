"""Stability maps: the root locus as real parts against speed and in the complex plane
(speed as colour), and the damping ratio of each mode against speed.

The figures take the eigenvalues of :func:`express.analysis.stability.stability.root_locus` (rows
of speeds, in any order); :func:`mode_branches` follows each mode from one speed to the
next for the damping-ratio figure.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from express.analysis.plots._base import BLUE, GREEN, GREY, ORANGE, PURPLE, RED, axes_for, styled
from express.base.diagnostics import ArgumentError

__all__ = ["figure_damping_vs_speed", "figure_eigen_locus", "figure_root_locus_complex", "mode_branches"]

# --------------------------------------------------------------------------------------
# stability maps: root locus (real parts; complex plane) and damping ratios
# --------------------------------------------------------------------------------------


def _locus_arrays(speeds_kmh, eigenvalues) -> tuple[np.ndarray, np.ndarray]:
    speeds = np.asarray(speeds_kmh, dtype=float)
    values = np.asarray(eigenvalues, dtype=complex)
    if speeds.ndim != 1 or values.ndim != 2 or values.shape[0] != speeds.size or speeds.size < 2:
        raise ArgumentError(f"expected speeds of shape (S,) with S >= 2 and eigenvalues of shape (S, N); got "
                         f"{speeds.shape} and {values.shape}")
    return speeds, values


def _real_window(values: np.ndarray) -> tuple[float, float]:
    """Real-part range shown: the unstable side, and the slowly decaying modes."""
    top = max(1.0, 1.3 * float(np.nanmax(values.real)))
    return -max(10.0, 3 * top), top


@styled
def figure_eigen_locus(speeds_kmh: np.ndarray, eigenvalues: np.ndarray, *, title: str,
                       critical_kmh: float | None = None, ax=None):
    """Real part of every eigenvalue against speed, the largest one bold.

    Parameters
    ----------
    speeds_kmh : numpy.ndarray, shape (S,)
        Speeds [km/h].
    eigenvalues : numpy.ndarray, complex, shape (S, N)
        Row ``i``: the eigenvalues [1/s] at ``speeds_kmh[i]``
        (:func:`express.analysis.stability.stability.root_locus`).
    title : str
    critical_kmh : float, optional
        Marked with a dashed vertical line.
    ax : matplotlib.axes.Axes, optional
        Draw into this axes and return it (the figure's layout is then the caller's); by
        default a new figure is made and returned.
    """
    speeds, values = _locus_arrays(speeds_kmh, eigenvalues)
    figure, axis = axes_for(ax, figsize=(7.0, 4.4))
    real = values.real
    for column in range(real.shape[1]):
        axis.plot(speeds, real[:, column], color=GREY, linewidth=0.6, alpha=0.6)
    largest = real.max(axis=1)
    axis.plot(speeds, largest, color=RED, linewidth=2.0, label="largest real part")
    axis.axhline(0.0, color="black", linewidth=0.8)
    if critical_kmh is not None:
        axis.axvline(critical_kmh, color=BLUE, linestyle="--", linewidth=1.2,
                     label=f"critical speed {critical_kmh:.1f} km/h")
    axis.set_xlabel("speed V [km/h]")
    axis.set_ylabel("real part of eigenvalue [1/s]")
    axis.set_ylim(*_real_window(values))
    axis.set_xlim(float(speeds[0]), float(speeds[-1]))
    axis.set_title(title)
    axis.legend(loc="lower left", framealpha=0.9)
    if ax is not None:
        return ax
    figure.tight_layout()
    return figure


@styled
def figure_root_locus_complex(
    speeds_kmh: np.ndarray,
    eigenvalues: np.ndarray,
    *,
    title: str = "root locus",
    critical_kmh: float | None = None,
    max_frequency_hz: float | None = None,
    ax=None,
):
    """Root locus in the complex plane: real part against frequency, speed as colour.

    Only the eigenvalues with ``Im >= 0`` are drawn (the others are their conjugates).
    A mode crosses into instability where its points cross the vertical zero line.

    Parameters
    ----------
    speeds_kmh : numpy.ndarray, shape (S,)
        Speeds [km/h], S >= 2.
    eigenvalues : numpy.ndarray, complex, shape (S, N)
        Row ``i``: the eigenvalues [1/s] at ``speeds_kmh[i]``; need not be tracked.
    title : str
    critical_kmh : float, optional
        The least stable eigenvalue at the speed nearest to it is marked.
    max_frequency_hz : float, optional
        Upper limit of the frequency axis; default: the highest frequency shown.
    ax : matplotlib.axes.Axes, optional
        Draw into this axes and return it (the figure's layout is then the caller's; the colour bar takes its room from ``ax``); by
        default a new figure is made and returned.

    Returns
    -------
    matplotlib.figure.Figure or matplotlib.axes.Axes
        One axes with one scatter (the eigenvalues) and a colour bar of speed (``ax`` when given).
    """
    speeds, values = _locus_arrays(speeds_kmh, eigenvalues)
    left, right = _real_window(values)
    colour = np.broadcast_to(speeds[:, None], values.shape)
    shown = (values.imag >= 0) & (values.real >= left)
    frequency = values.imag / (2 * np.pi)
    figure, axis = axes_for(ax, figsize=(7.0, 4.8))
    points = axis.scatter(values.real[shown], frequency[shown], c=colour[shown], s=5, cmap="viridis",
                          vmin=float(speeds.min()), vmax=float(speeds.max()), linewidths=0, rasterized=True)
    figure.colorbar(points, ax=axis, label="speed V [km/h]")
    axis.axvline(0.0, color="black", linewidth=0.8)
    if critical_kmh is not None:
        row = int(np.argmin(np.abs(speeds - critical_kmh)))
        k = int(np.argmax(np.where(values[row].imag >= 0, values[row].real, -np.inf)))
        axis.plot(values[row, k].real, frequency[row, k], marker="*", markersize=13, color=RED, linestyle="none",
                  markeredgecolor="black", label=f"critical speed {critical_kmh:.1f} km/h")
        axis.legend(loc="upper left", framealpha=0.9)
    top = max_frequency_hz if max_frequency_hz is not None else float(np.max(frequency[shown], initial=1.0))
    axis.set_xlim(left, right)
    axis.set_ylim(0.0, 1.05 * top)
    axis.set_xlabel("real part of eigenvalue [1/s]")
    axis.set_ylabel("frequency Im/2π [Hz]")
    axis.set_title(title)
    if ax is not None:
        return ax
    figure.tight_layout()
    return figure


def mode_branches(eigenvalues: np.ndarray) -> np.ndarray:
    """Follow every oscillatory mode from one speed to the next.

    Row ``i + 1`` is matched to row ``i`` (extrapolated linearly from rows ``i - 1`` and
    ``i``) by the assignment of least total distance in the complex plane, so a branch
    keeps its identity where the eigenvalues' sort order changes.  Of each conjugate
    pair the branch with ``Im >= 0`` is kept; branches that are real at every speed
    (no oscillation) are dropped.

    Parameters
    ----------
    eigenvalues : numpy.ndarray, complex, shape (S, N)
        Row ``i``: the eigenvalues [1/s] at the ``i``-th speed, in any order (as
        :func:`express.analysis.stability.stability.root_locus` returns them).

    Returns
    -------
    numpy.ndarray, complex, shape (S, M)
        Column ``j``: one mode at every speed, M <= N / 2 (+ real pairs that split).
    """
    from scipy.optimize import linear_sum_assignment

    values = np.asarray(eigenvalues, dtype=complex)
    if values.ndim != 2:
        raise ArgumentError(f"expected eigenvalues of shape (S, N), got {values.shape}")
    tracked = values.copy()
    for i in range(1, values.shape[0]):
        guess = 2 * tracked[i - 1] - tracked[i - 2] if i >= 2 else tracked[i - 1]
        _, columns = linear_sum_assignment(np.abs(guess[:, None] - values[i][None, :]))
        tracked[i] = values[i][columns]
    tolerance = 1e-9 * max(1.0, float(np.max(np.abs(values), initial=0.0)))
    upper = np.all(tracked.imag >= -tolerance, axis=0) & np.any(tracked.imag > tolerance, axis=0)
    return tracked[:, upper]


@styled
def figure_damping_vs_speed(
    speeds_kmh: np.ndarray,
    branches: np.ndarray,
    *,
    labels: Sequence[str] | None = None,
    highlight: int = 4,
    title: str = "damping ratio against speed",
    critical_kmh: float | None = None,
    max_frequency_hz: float | None = None,
    ax=None,
):
    """Damping ratio ``zeta = -Re(lambda) / |lambda|`` of each mode against speed.

    Parameters
    ----------
    speeds_kmh : numpy.ndarray, shape (S,)
        Speeds [km/h], S >= 2.
    branches : numpy.ndarray, complex, shape (S, M)
        Column ``j``: one mode followed across the speeds (:func:`mode_branches`).
        Where a branch is real (no oscillation) it is not drawn.
    labels : sequence of str, optional
        One per column; default: the frequency at its least damped speed.
    highlight : int
        The ``highlight`` least damped modes are drawn in colour with a legend entry;
        the others thin and grey.
    title : str
    critical_kmh : float, optional
        Marked with a dashed vertical line.
    max_frequency_hz : float, optional
        Modes whose frequency exceeds it at every speed are left out.
    ax : matplotlib.axes.Axes, optional
        Draw into this axes and return it (the figure's layout is then the caller's); by
        default a new figure is made and returned.

    Returns
    -------
    matplotlib.figure.Figure or matplotlib.axes.Axes
        One axes, one line per mode drawn, plus the zero line (``ax`` when given).
    """
    speeds, values = _locus_arrays(speeds_kmh, branches)
    if labels is not None and len(labels) != values.shape[1]:
        raise ArgumentError(f"{len(labels)} labels for {values.shape[1]} modes")
    magnitude = np.abs(values)
    oscillating = np.abs(values.imag) > 1e-9 * np.maximum(magnitude, 1.0)
    zeta = np.where(oscillating, -values.real / np.where(magnitude > 0, magnitude, 1.0), np.nan)
    frequency = np.abs(values.imag) / (2 * np.pi)
    drawn = [j for j in range(values.shape[1]) if np.any(oscillating[:, j])
             and (max_frequency_hz is None or np.nanmin(np.where(oscillating[:, j], frequency[:, j], np.inf))
                  <= max_frequency_hz)]
    drawn.sort(key=lambda j: float(np.nanmin(zeta[:, j])))
    figure, axis = axes_for(ax, figsize=(7.0, 4.6))
    palette = (RED, BLUE, GREEN, ORANGE, PURPLE)
    for rank, j in enumerate(drawn):
        if rank < highlight:
            at = int(np.nanargmin(zeta[:, j]))
            label = labels[j] if labels is not None else f"{frequency[at, j]:.2f} Hz (least damped at {speeds[at]:.0f} km/h)"
            axis.plot(speeds, zeta[:, j], color=palette[rank % len(palette)], linewidth=1.8, label=label,
                      zorder=3 + highlight - rank)
        else:
            axis.plot(speeds, zeta[:, j], color=GREY, linewidth=0.6, alpha=0.6, label="_other")
    axis.axhline(0.0, color="black", linewidth=0.8)
    if critical_kmh is not None:
        axis.axvline(critical_kmh, color=BLUE, linestyle="--", linewidth=1.2,
                     label=f"critical speed {critical_kmh:.1f} km/h")
    lowest = min((float(np.nanmin(zeta[:, j])) for j in drawn), default=0.0)
    axis.set_ylim(min(-0.05, 1.2 * lowest), 1.0)
    axis.set_xlim(float(speeds[0]), float(speeds[-1]))
    axis.set_xlabel("speed V [km/h]")
    axis.set_ylabel("damping ratio ζ [-]")
    axis.set_title(title)
    if (drawn and highlight > 0) or critical_kmh is not None:
        axis.legend(loc="upper right", framealpha=0.9)
    if ax is not None:
        return ax
    figure.tight_layout()
    return figure
