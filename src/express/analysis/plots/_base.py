"""The figures' house style, pyplot-free figure creation, and :func:`save_figure`.

Figures are built with :class:`matplotlib.figure.Figure` inside ``rc_context(STYLE)``;
nothing here touches pyplot's state or switches the backend.  :func:`save_figure` writes
through :func:`express.io.output.write_bytes` (whole or not at all), deterministically:
fixed ``svg.hashsalt``, no date or software name in the metadata, text kept as paths.
"""

from __future__ import annotations

import functools
import io
import sys
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any, TypeVar

import numpy as np

from express.base.diagnostics import ArgumentError

__all__ = ["CONVENTIONAL", "FIGURE_SUFFIXES", "STEERED", "STYLE", "axes_for", "save_figure"]

#: Figure formats written by :func:`save_figure`.
FIGURE_SUFFIXES = (".png", ".svg", ".pdf")

#: Matplotlib settings of every figure (applied locally, never to ``matplotlib.rcParams``).
STYLE: dict[Any, Any] = {
    "font.size": 9.5,
    "axes.titlesize": 10.5,
    "axes.labelsize": 9.5,
    "legend.fontsize": 8.5,
    "axes.grid": True,
    "grid.alpha": 0.35,
    "grid.linewidth": 0.6,
    "lines.linewidth": 1.5,
    "figure.dpi": 110,
    "savefig.dpi": 130,
    "svg.hashsalt": "express",
    "svg.fonttype": "path",
    "path.simplify": True,
}

_METADATA = {
    ".svg": {"Date": None, "Creator": None},
    ".png": {"Software": None},
    ".pdf": {"CreationDate": None, "Creator": None, "Producer": None},
}

# one colour per axle / bogie position, one line style per vehicle
BLUE, ORANGE, GREEN, RED, PURPLE, GREY = (
    "#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#555555",
)
STEERED = {"linestyle": "-"}
CONVENTIONAL = {"linestyle": (0, (5, 2.5)), "linewidth": 1.3}

_F = TypeVar("_F", bound=Callable[..., Any])


def styled(function: _F) -> _F:
    """Build the figure inside ``rc_context(STYLE)`` (fonts, grid and line widths are
    read when the artists are made)."""

    @functools.wraps(function)
    def wrapper(*args, **kwargs):
        import matplotlib

        with matplotlib.rc_context(STYLE):
            return function(*args, **kwargs)

    return wrapper  # type: ignore[return-value]


def new_figure(nrows: int = 1, ncols: int = 1, *, figsize: tuple[float, float], **kwargs):
    """A pyplot-free ``Figure`` and its axes (as :meth:`Figure.subplots` returns them)."""
    from matplotlib.figure import Figure

    figure = Figure(figsize=figsize)
    return figure, figure.subplots(nrows, ncols, **kwargs)


def axes_for(ax: Any, nrows: int = 1, ncols: int = 1, *, figsize: tuple[float, float], squeeze: bool = True,
             **kwargs: Any) -> tuple[Any, Any]:
    """The figure and axes a ``figure_*`` function draws into: a new figure
    (:func:`new_figure`) when ``ax`` is None, else ``ax``'s figure and ``ax`` itself (one
    :class:`matplotlib.axes.Axes`, or a sequence of ``nrows * ncols`` of them for a figure of
    several panels, shaped as :meth:`Figure.subplots` would give them; ``kwargs`` such as
    ``sharex`` are then the caller's business).

    Raises
    ------
    express.base.diagnostics.ArgumentError
        When ``ax`` holds another number of axes.
    """
    if ax is None:
        return new_figure(nrows, ncols, figsize=figsize, squeeze=squeeze, **kwargs)
    count = nrows * ncols
    items = list(np.ravel(np.asarray(ax, dtype=object))) if isinstance(ax, (list, tuple, np.ndarray)) else [ax]
    flat = np.empty(len(items), dtype=object)
    flat[:] = items
    if flat.size != count or not all(hasattr(a, "plot") and hasattr(a, "figure") for a in flat):
        raise ArgumentError(f"ax: this figure draws {count} panel(s) ({nrows} x {ncols}): give "
                            f"{'one matplotlib Axes' if count == 1 else f'a sequence of {count} Axes'}, got {ax!r}")
    axes: Any = flat.reshape(nrows, ncols)
    if squeeze:
        axes = axes[0, 0] if count == 1 else axes.ravel()
    return flat[0].figure, axes


def save_figure(figure, path: str | Path | Sequence[str | Path]) -> list[Path]:
    """Write ``figure`` to ``path`` (.png, .svg or .pdf by suffix), whole or not at all.

    Parameters
    ----------
    figure : matplotlib.figure.Figure
    path : path or sequence of paths
        One figure in several formats when a sequence is given.

    Returns
    -------
    list of Path
        The paths written, in order.

    Raises
    ------
    express.base.diagnostics.ArgumentError
        For another suffix (checked before anything is written).
    express.base.diagnostics.OutputError
        When a destination cannot be written.
    """
    import matplotlib

    from express.io.output import write_bytes

    paths = [Path(path)] if isinstance(path, (str, Path)) else [Path(p) for p in path]
    for target in paths:
        if target.suffix.lower() not in FIGURE_SUFFIXES:
            raise ArgumentError(f"{target}: unknown figure format {target.suffix or '(none)'!r}; use .png, .svg or .pdf")
    for target in paths:
        suffix = target.suffix.lower()
        buffer = io.BytesIO()
        with matplotlib.rc_context(STYLE):
            figure.savefig(buffer, format=suffix[1:], metadata=_METADATA[suffix])
        write_bytes(target, buffer.getvalue())
    pyplot = sys.modules.get("matplotlib.pyplot")
    if pyplot is not None and getattr(figure.canvas, "manager", None) is not None:
        pyplot.close(figure)  # a figure the caller made with pyplot: release it as before
    return paths


def add_caption(figure, text: str | None) -> None:
    if text:
        figure.text(0.01, 0.005, text, fontsize=7.5, color=GREY, ha="left", va="bottom", wrap=True)


def runs(mask: np.ndarray) -> list[slice]:
    """Slices of the consecutive ``True`` stretches of a boolean vector."""
    edges = np.flatnonzero(np.diff(np.concatenate(([0], mask.astype(np.int8), [0]))))
    return [slice(int(start), int(stop)) for start, stop in zip(edges[::2], edges[1::2], strict=True)]


