"""Plan, side and end views of a model with the usual symbols.

Springs are zigzags, dampers dashpots, parallel spring-dampers both side by side, series
(Maxwell) elements a spring followed by a dashpot, pinned joints small open circles,
levers thick bars, grounds dark triangles; bodies are boxes around their points, labelled with their ids.  An
element whose two points coincide in a view is drawn as a short symbol along its
direction at that point, or as a ring when its direction points out of the view; a
rotational element is a small arc.

The functions build a :class:`matplotlib.figure.Figure` without touching pyplot's state.
"""

from __future__ import annotations

import numpy as np

from express.drawing.geometry import DrawnElement, ModelGeometry

__all__ = ["VIEWS", "draw_view", "figure_model"]

#: View name -> (horizontal axis, vertical axis, title).
VIEWS = {
    "plan": (0, 1, "plan (x forward, y left)"),
    "side": (0, 2, "side (x forward, z up)"),
    "end": (1, 2, "end (y left, z up)"),
}
_COLOURS = {"body": "#7f7f7f", "bogie": "#1f77b4", "wheelset": "#2ca02c", "lever": "#ff7f0e"}
_ELEMENT_COLOUR = "#333333"


def _zigzag(a: np.ndarray, b: np.ndarray, width: float, turns: int = 6) -> np.ndarray:
    length = np.linalg.norm(b - a)
    if length == 0:
        return np.array([a, b])
    along = (b - a) / length
    normal = np.array([-along[1], along[0]])
    s = np.linspace(0.2, 0.8, 2 * turns + 1)
    offsets = np.zeros_like(s)
    offsets[1:-1:2], offsets[2:-1:2] = width, -width
    middle = a + np.outer(s, b - a) + np.outer(offsets, normal)
    return np.vstack([a, middle, b])


def _dashpot(lines: list, a: np.ndarray, b: np.ndarray, width: float) -> None:
    length = np.linalg.norm(b - a)
    if length == 0:
        return
    along = (b - a) / length
    normal = np.array([-along[1], along[0]])
    cup0, cup1 = a + 0.35 * (b - a), a + 0.7 * (b - a)
    plate = a + 0.55 * (b - a)
    lines += [
        [a, cup0],
        [cup0 + width * normal, cup0 - width * normal],
        [cup0 + width * normal, cup1 + width * normal],
        [cup0 - width * normal, cup1 - width * normal],
        [plate + 0.7 * width * normal, plate - 0.7 * width * normal],
        [plate, b],
    ]


def _symbol(lines: list, kind: str, a: np.ndarray, b: np.ndarray, width: float) -> None:
    """Append the polylines of an element symbol from ``a`` to ``b`` to ``lines``."""
    if kind == "spring":
        lines.append(_zigzag(a, b, width))
    elif kind == "damper":
        _dashpot(lines, a, b, width)
    elif kind == "series":
        middle = 0.5 * (a + b)
        lines.append(_zigzag(a, middle, width, turns=3))
        _dashpot(lines, middle, b, width)
    else:  # spring and damper in parallel
        along = (b - a) / max(np.linalg.norm(b - a), 1e-12)
        normal = np.array([-along[1], along[0]]) * 1.2 * width
        lines += [[end + normal, end - normal] for end in (a, b)]
        lines.append(_zigzag(a + normal, b + normal, 0.6 * width, turns=4))
        _dashpot(lines, a - normal, b - normal, 0.6 * width)


def _element(axis, lines: list, rings: list, geometry: ModelGeometry, element: DrawnElement,
             view: tuple[int, int], size: float, alpha: float, label: bool) -> None:
    h, v = view
    start, end = (np.asarray(p, dtype=float) for p in geometry.ends(element))
    a, b = start[[h, v]], end[[h, v]]
    if element.axis >= 3:  # rotational: an arc about the element's axis
        angle = np.linspace(0.3, 1.7 * np.pi, 30)
        lines.append(0.5 * (a + b) + 0.5 * size * np.column_stack([np.cos(angle), np.sin(angle)]))
    elif np.linalg.norm(b - a) > 0.5 * size:
        _symbol(lines, element.kind, a, b, 0.12 * size)
    elif element.axis in (h, v):  # coincident ends: a short symbol along the direction
        direction = np.zeros(2)
        direction[0 if element.axis == h else 1] = 1.0
        centre = 0.5 * (a + b)
        _symbol(lines, element.kind, centre - 0.5 * size * direction, centre + 0.5 * size * direction, 0.12 * size)
    else:  # acting out of the view: a ring
        rings.append(0.5 * (a + b))
    if label:
        middle = 0.5 * (a + b)
        axis.annotate(element.id, middle, fontsize=4, color="#555555", alpha=alpha,
                      xytext=(2, 2), textcoords="offset points")


def draw_view(axis, geometry: ModelGeometry, view: str, *, alpha: float = 1.0, labels: bool = True,
              limits: tuple | None = None) -> None:
    """Draw one view (``"plan"``, ``"side"`` or ``"end"``) of ``geometry`` on ``axis``;
    ``limits`` ``((x0, x1), (y0, y1))`` fixes the axes (animations)."""
    h, v, title = VIEWS[view]
    span = geometry.span((h, v))
    size = 0.025 * span
    pad = 0.008 * span
    from matplotlib.patches import Rectangle

    for body in geometry.bodies:
        colour = _COLOURS.get(body.role, _COLOURS["body"])
        low, high = np.asarray(body.low)[[h, v]] - pad, np.asarray(body.high)[[h, v]] + pad
        if body.role == "lever":
            own = np.array([geometry.points[p] for p, host in geometry.hosts.items() if host == body.id] or [body.centre])
            bar = own[:, [h, v]]
            order = np.lexsort((bar[:, 1], bar[:, 0]))
            axis.plot(bar[order, 0], bar[order, 1], color=colour, lw=2.5, alpha=alpha, solid_capstyle="round")
        else:
            axis.add_patch(Rectangle(tuple(low), *(high - low), fill=False, ec=colour, lw=1.2, alpha=alpha))
        if labels:
            centre = np.asarray(body.centre)[[h, v]]
            axis.annotate(body.id, centre, fontsize=6, color=colour, weight="bold", ha="center", va="center", alpha=alpha)
    from matplotlib.collections import LineCollection

    lines: list = []
    rings: list = []
    for element in geometry.elements:
        _element(axis, lines, rings, geometry, element, (h, v), size, alpha, labels and len(geometry.elements) <= 120)
    axis.add_collection(LineCollection([np.asarray(line) for line in lines], colors=_ELEMENT_COLOUR,
                                       linewidths=0.8, alpha=alpha))
    if rings:
        ring = np.array(rings)
        axis.plot(ring[:, 0], ring[:, 1], ls="none", marker="o", ms=3, mfc="none", color=_ELEMENT_COLOUR, alpha=alpha)
    if geometry.ground_points:
        anchors = np.array([geometry.points[p] for p in geometry.ground_points])[:, [h, v]]
        axis.plot(anchors[:, 0], anchors[:, 1], ls="none", marker="v", ms=6, color="#444444", alpha=alpha)
    for _, point in geometry.pins:
        position = np.asarray(geometry.points[point])[[h, v]]
        axis.plot(*position, marker="o", ms=4, mfc="white", mec="black", mew=0.8, alpha=alpha, zorder=5)
    axis.set_title(title, fontsize=8)
    axis.grid(False)  # whatever the global style: a drawing has no grid
    if limits is None:
        axis.autoscale_view()
        axis.set_aspect("equal", adjustable="datalim")
    else:
        axis.set_xlim(limits[0])
        axis.set_ylim(limits[1])
        axis.set_aspect("equal", adjustable="box")
    axis.tick_params(labelsize=6)
    axis.set_xlabel("xyz"[h] + " [m]", fontsize=7)
    axis.set_ylabel("xyz"[v] + " [m]", fontsize=7)


def figure_model(geometry: ModelGeometry, *, title: str | None = None, deformed: ModelGeometry | None = None):
    """The plan, side and end views of a model (``deformed``: a displaced copy drawn
    over the undisplaced one in grey, for mode shapes). Returns a ``Figure``."""
    from matplotlib.figure import Figure

    figure = Figure(figsize=(11, 7.5), layout="constrained")
    grid = figure.add_gridspec(2, 2, width_ratios=(3, 1.2))
    axes = {"plan": figure.add_subplot(grid[0, 0]), "side": figure.add_subplot(grid[1, 0]),
            "end": figure.add_subplot(grid[:, 1])}
    for view, axis in axes.items():
        if deformed is None:
            draw_view(axis, geometry, view)
        else:
            draw_view(axis, geometry, view, alpha=0.25, labels=False)
            draw_view(axis, deformed, view)
    figure.suptitle(title or geometry.name, fontsize=10)
    return figure
