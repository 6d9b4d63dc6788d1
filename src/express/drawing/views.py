"""Plan, side and end views of a model with the usual symbols.

Springs are zigzags, dampers dashpots, parallel spring-dampers both side by side, series
(Maxwell) elements a spring followed by a dashpot, bump stops (clearance elements) a
spring facing its stop across a gap, pinned joints a filled dot in a ring (the paper's
hinge, Fig. 2), anti-roll bars (roll springs between two bodies) a torsion bar: a U-shaped
bar with a drop link at each end,
levers thick bars, grounds dark triangles.  A body is drawn by its outline (the uniform box
of its mass and inertias, :func:`express.drawing.geometry.estimated_outline`), else as the
box around its points; a wheelset as its wheels: circles of the rolling radius in the side
view, discs seen edge-on at the contact points in the plan and end views, on the axle.
Labels are placed where they overlap no other label (:func:`place_labels`); those with no
free place are listed under the figure instead.  An
element whose two points coincide in a view is drawn as a short symbol along its
direction at that point, or as a ring when its direction points out of the view; any other
rotational element is a small arc.  Anti-roll bars and pins are artists of their own whose
``gid`` names their kind and id (``"anti-roll-bar:T1_roll_bar"``, ``"pin:P1"``).

The functions build a :class:`matplotlib.figure.Figure` without touching pyplot's state.
"""

from __future__ import annotations

import numpy as np

from express.drawing.geometry import DrawnElement, ModelGeometry, points_by_host

__all__ = ["VIEWS", "draw_view", "figure_model", "label_boxes", "place_labels", "svg_with_tooltips"]

#: Width of a wheel drawn edge-on [m].
WHEEL_WIDTH = 0.14

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
    elif kind == "stop":  # a bump stop: a spring that meets its stop across a gap
        along = (b - a) / max(np.linalg.norm(b - a), 1e-12)
        normal = np.array([-along[1], along[0]]) * 1.5 * width
        spring_end, stop = a + 0.55 * (b - a), a + 0.7 * (b - a)
        lines.append(_zigzag(a, spring_end, width, turns=3))
        lines += [[spring_end + normal, spring_end - normal], [stop + normal, stop - normal], [stop, b]]
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


def _anti_roll_bar(axis, centre: np.ndarray, size: float, name: str, alpha: float) -> None:
    """Draw a torsion bar of half width ``size`` at ``centre``: a U-shaped bar (the tube
    and its two arms) with a thin drop link on each arm, jointed by small circles."""
    x, y = centre
    bar = np.array([[-size, 0.5 * size], [-size, -0.3 * size], [size, -0.3 * size], [size, 0.5 * size]])
    axis.plot(x + bar[:, 0], y + bar[:, 1], color=_ELEMENT_COLOUR, lw=1.4, alpha=alpha, gid=f"anti-roll-bar:{name}")
    for side in (-size, size):
        axis.plot([x + side, x + side], [y + 0.5 * size, y + 1.1 * size], color=_ELEMENT_COLOUR, lw=0.6,
                  marker="o", ms=1.5, mfc="white", alpha=alpha, gid=f"anti-roll-bar:{name}:drop-link")


def _is_anti_roll_bar(geometry: ModelGeometry, element: DrawnElement) -> bool:
    """A roll spring (stiffness only, about x) between two bodies, neither of them ground."""
    return (element.axis == 3 and element.kind == "spring"
            and not {element.s_point, element.t_point} & set(geometry.ground_points))


def _element(axis, lines: list, rings: list, geometry: ModelGeometry, element: DrawnElement,
             view: tuple[int, int], size: float, alpha: float, label: bool) -> None:
    h, v = view
    start, end = (np.asarray(p, dtype=float) for p in geometry.ends(element))
    a, b = start[[h, v]], end[[h, v]]
    if _is_anti_roll_bar(geometry, element):
        _anti_roll_bar(axis, 0.5 * (a + b), size, element.id, alpha)
    elif element.axis >= 3:  # rotational: an arc about the element's axis
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
                      xytext=(2, 2), textcoords="offset points", gid=f"label:{element.id}")


def _corners(body, size: tuple[float, float, float]) -> np.ndarray:
    """The 8 corners of a box of ``size`` on the body's centre, turned by its small
    rotation (``u = theta x r``), shape (8, 3)."""
    half = 0.5 * np.asarray(size)
    signs = np.array([[i, j, k] for i in (-1, 1) for j in (-1, 1) for k in (-1, 1)], dtype=float)
    offsets = signs * half
    return np.asarray(body.centre) + offsets + np.cross(np.asarray(body.turn), offsets)


def _hull(points: np.ndarray) -> np.ndarray:
    """Convex hull of 2-D points, closed (monotone chain)."""
    ordered = sorted({(round(float(x), 9), round(float(y), 9)) for x, y in points})
    if len(ordered) < 3:
        return np.array(ordered + ordered[:1])

    def half(seq):
        out: list = []
        for p in seq:
            while len(out) >= 2 and ((out[-1][0] - out[-2][0]) * (p[1] - out[-2][1])
                                     - (out[-1][1] - out[-2][1]) * (p[0] - out[-2][0])) <= 0:
                out.pop()
            out.append(p)
        return out

    lower, upper = half(ordered), half(ordered[::-1])
    loop = lower[:-1] + upper[:-1]
    return np.array(loop + loop[:1])


def _extended(x: np.ndarray, xp: np.ndarray, fp: np.ndarray) -> np.ndarray:
    """``np.interp`` continued by the end segments' straight lines beyond ``xp``."""
    y = np.interp(x, xp, fp)
    if xp.size >= 2:
        low, high = x < xp[0], x > xp[-1]
        y[low] = fp[0] + (x[low] - xp[0]) * (fp[1] - fp[0]) / (xp[1] - xp[0])
        y[high] = fp[-1] + (x[high] - xp[-1]) * (fp[-1] - fp[-2]) / (xp[-1] - xp[-2])
    return y


def _bent_outline(body, view: tuple[int, int], pad: float) -> np.ndarray:
    """The plan (``view`` (0, 1)) or side ((0, 2)) outline of a body bent by its modes
    (``body.bend``: (lx, u_y, u_z) samples, continued straight beyond them): its two long
    edges through the samples within its length, turned with the body, shape (2 K, 2)."""
    h, v = view
    if body.outline is not None:
        size, centre = np.asarray(body.outline), np.asarray(body.centre)
    else:
        low, high = np.asarray(body.low) - pad, np.asarray(body.high) + pad
        size, centre = high - low, np.asarray(body.centre)
    samples = np.array(body.bend)
    half = 0.5 * size[0]
    inside = samples[np.abs(samples[:, 0]) < half, 0]
    stations = np.concatenate([[-half], inside, [half]])
    deflection = np.stack([np.zeros_like(stations), _extended(stations, samples[:, 0], samples[:, 1]),
                           _extended(stations, samples[:, 0], samples[:, 2])], axis=1)
    edges = []
    for side in (1.0, -1.0):
        offsets = np.zeros((stations.size, 3))
        offsets[:, 0] = stations
        offsets[:, v] = side * 0.5 * size[v]
        edge = centre + offsets + np.cross(np.asarray(body.turn), offsets) + deflection
        edges.append(edge[:, [h, v]] if side > 0 else edge[::-1, [h, v]])
    return np.concatenate(edges)


def _draw_body(axis, geometry: ModelGeometry, body, view: tuple[int, int], pad: float, colour: str, alpha: float,
               hosted: dict[str, list[str]]) -> None:
    """Draw ``body`` (``hosted``: each body's points, :func:`express.drawing.geometry.points_by_host`)."""
    from matplotlib.patches import Circle, Polygon, Rectangle

    h, v = view
    if body.role == "lever":
        own = np.array([geometry.points[p] for p in hosted.get(body.id, ())] or [body.centre])
        bar = own[:, [h, v]]
        order = np.lexsort((bar[:, 1], bar[:, 0]))
        axis.plot(bar[order, 0], bar[order, 1], color=colour, lw=2.5, alpha=alpha, solid_capstyle="round")
    elif body.radius is not None and body.radius > 0:  # a wheelset: its wheels on the axle
        centre = np.asarray(body.centre)
        if (h, v) == (0, 2):
            axis.add_patch(Circle((centre[0], centre[2]), body.radius, fill=False, ec=colour, lw=1.2, alpha=alpha))
        else:
            half = body.gauge_half or 0.75
            ends = []
            for side in (-1.0, 1.0):
                wheel = np.array([centre[0], centre[1] + side * half, centre[2]])
                wheel = wheel + np.cross(np.asarray(body.turn), wheel - centre)
                x, y = wheel[[h, v]]
                length = 2 * body.radius if h == 0 else WHEEL_WIDTH
                height = WHEEL_WIDTH if h == 0 else 2 * body.radius
                axis.add_patch(Rectangle((x - 0.5 * length, y - 0.5 * height), length, height, fill=False,
                                         ec=colour, lw=1.2, alpha=alpha))
                ends.append((x, y))
            axis.plot(*np.array(ends).T, color=colour, lw=1.0, alpha=alpha)
    elif body.bend and (h, v) in ((0, 1), (0, 2)):  # a flexible body bent by its modes
        axis.add_patch(Polygon(_bent_outline(body, (h, v), pad), closed=True, fill=False, ec=colour, lw=1.2, alpha=alpha))
    elif body.outline is not None:
        corners = _corners(body, body.outline)[:, [h, v]]
        axis.add_patch(Polygon(_hull(corners), closed=True, fill=False, ec=colour, lw=1.2, alpha=alpha))
    else:
        low, high = np.asarray(body.low)[[h, v]] - pad, np.asarray(body.high)[[h, v]] + pad
        axis.add_patch(Rectangle(tuple(low), *(high - low), fill=False, ec=colour, lw=1.2, alpha=alpha))


def label_boxes(figure) -> dict:
    """Axis -> the window extents of its visible labels (body and element ids), drawn
    with the Agg renderer."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    canvas = figure.canvas if isinstance(figure.canvas, FigureCanvasAgg) else FigureCanvasAgg(figure)
    renderer = canvas.get_renderer()
    return {axis: [(text, text.get_window_extent(renderer)) for text in axis.texts
                   if text.get_visible() and str(text.get_gid() or "").startswith("label:")]
            for axis in figure.axes}


#: Offsets [points] a label may take from its anchor, tried in order.
_CANDIDATES = ((2, 2), (2, -8), (-14, 2), (-14, -8), (2, 9), (2, -15), (-22, 9), (-22, -15), (10, 16), (10, -22))


#: The same for a body's id (centred on the body's centre).
_BODY_CANDIDATES = ((0, 0), (0, 9), (0, -9), (12, 0), (-12, 0), (0, 18), (0, -18))


#: Side [pixels] of the cells that index the placed labels (:class:`_PlacedBoxes`).
_CELL = 48.0
#: How far [pixels] a label's box found by shifting may lie from the one matplotlib
#: measures (a few 1e-13 in practice): only a candidate that is ruled out with this
#: margin to spare is ruled out without measuring it.
_MARGIN = 1e-6


class _PlacedBoxes:
    """The window extents of the labels placed so far, indexed by grid cells: a box is
    compared with the boxes in the cells it covers only (the same overlaps as comparing
    it with every placed box, without the work growing with their square)."""

    def __init__(self) -> None:
        self.cells: dict[tuple[int, int], list] = {}

    @staticmethod
    def _cells(x0: float, y0: float, x1: float, y1: float):
        import math

        for i in range(math.floor(x0 / _CELL), math.floor(x1 / _CELL) + 1):
            for j in range(math.floor(y0 / _CELL), math.floor(y1 / _CELL) + 1):
                yield i, j

    def add(self, box) -> None:
        for cell in self._cells(box.x0, box.y0, box.x1, box.y1):
            self.cells.setdefault(cell, []).append(box)

    def near(self, x0: float, y0: float, x1: float, y1: float) -> list:
        """The placed boxes in the cells of the box ``(x0, y0)``-``(x1, y1)``."""
        found: dict[int, object] = {}
        for cell in self._cells(x0, y0, x1, y1):
            for box in self.cells.get(cell, ()):
                found[id(box)] = box
        return list(found.values())

    def hit(self, x0: float, y0: float, x1: float, y1: float) -> bool:
        """Whether the box overlaps a placed box (touching counts, as in
        ``matplotlib.transforms.Bbox.overlaps``)."""
        return any(x0 <= b.x1 and b.x0 <= x1 and y0 <= b.y1 and b.y0 <= y1 for b in self.near(x0, y0, x1, y1))


def place_labels(figure) -> list[str]:
    """Move every label to the first offset (:data:`_CANDIDATES`) where it overlaps no
    label placed before it (body labels first), in each axis; hide those with no free
    place. Returns the hidden labels' names, for a list under the figure.

    A label's box is measured once; its box at another offset is that one shifted, and an
    offset the shifted box rules out with :data:`_MARGIN` to spare (outside the axes, or
    over a placed label) is not measured again; the others are measured by matplotlib and
    decided exactly as before (the same places on every drawing, in a fraction of the time
    on a long train)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    if not isinstance(figure.canvas, FigureCanvasAgg):
        FigureCanvasAgg(figure)
    figure.draw_without_rendering()  # the layout, measured with the Agg renderer, nothing painted
    figure.set_layout_engine("none")  # keep the laid-out axes: the boxes measured stay true
    renderer = figure.canvas.get_renderer()
    pixels = figure.dpi / 72.0  # per point of offset
    hidden: dict[str, None] = {}  # in order, once each
    for axis in figure.axes:
        placed = _PlacedBoxes()
        frame = axis.get_window_extent(renderer)
        texts = [t for t in axis.texts if str(t.get_gid() or "").startswith("label:")]
        texts.sort(key=lambda t: t.get_fontsize(), reverse=True)  # body ids (larger) first
        for text in texts:
            offsets = (_BODY_CANDIDATES if text.get_fontsize() >= 6 else _CANDIDATES)
            text.xyann = offsets[0]
            first = text.get_window_extent(renderer)
            for number, offset in enumerate(offsets):
                dx, dy = (offset[0] - offsets[0][0]) * pixels, (offset[1] - offsets[0][1]) * pixels
                x0, y0 = first.x0 + dx + _MARGIN, first.y0 + dy + _MARGIN
                x1, y1 = first.x1 + dx - _MARGIN, first.y1 + dy - _MARGIN
                if not (frame.x0 <= x0 and x1 <= frame.x1 and frame.y0 <= y0 and y1 <= frame.y1) or placed.hit(x0, y0, x1, y1):
                    continue  # ruled out whatever the last bits of the measured box
                text.xyann = offset
                box = first if number == 0 else text.get_window_extent(renderer)
                inside = frame.x0 <= box.x0 and box.x1 <= frame.x1 and frame.y0 <= box.y0 and box.y1 <= frame.y1
                if inside and not any(box.overlaps(other) for other in placed.near(box.x0, box.y0, box.x1, box.y1)):
                    placed.add(box)
                    break
            else:
                text.xyann = offsets[-1]
                text.set_visible(False)
                hidden[str(text.get_gid())[6:]] = None
    return list(hidden)


def draw_view(axis, geometry: ModelGeometry, view: str, *, alpha: float = 1.0, labels: bool = True,
              limits: tuple | None = None) -> None:
    """Draw one view (``"plan"``, ``"side"`` or ``"end"``) of ``geometry`` on ``axis``;
    ``limits`` ``((x0, x1), (y0, y1))`` fixes the axes (animations)."""
    h, v, title = VIEWS[view]
    span = geometry.span((h, v))
    size = 0.025 * span
    pad = 0.008 * span

    hosted = points_by_host(geometry.hosts)
    for body in geometry.bodies:
        colour = _COLOURS.get(body.role, _COLOURS["body"])
        _draw_body(axis, geometry, body, (h, v), pad, colour, alpha, hosted)
        if labels:
            centre = np.asarray(body.centre)[[h, v]]
            axis.annotate(body.id, centre, fontsize=6, color=colour, weight="bold", ha="center", va="center",
                          alpha=alpha, gid=f"label:{body.id}", xytext=(0, 0), textcoords="offset points")
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
    for pin, point in geometry.pins:  # a hinge: a filled dot in a ring
        position = np.asarray(geometry.points[point])[[h, v]]
        axis.plot(*position, marker="o", ms=6, mfc="white", mec="black", mew=0.8, alpha=alpha, zorder=5,
                  gid=f"pin:{pin}")
        axis.plot(*position, marker="o", ms=2.4, mfc="black", mec="black", mew=0, alpha=alpha, zorder=6,
                  gid=f"pin:{pin}:dot")
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
    engine = figure.get_layout_engine()
    if engine is not None:  # room for the list of labels left out
        engine.set(rect=(0, 0.035, 1, 0.965))  # type: ignore[call-arg]
    hidden = place_labels(figure)
    if hidden:
        figure.text(0.01, 0.005, _wrap("not labelled for lack of space: " + ", ".join(hidden)), fontsize=5,
                    color="#555555", va="bottom")
    return figure


def _wrap(text: str, width: int = 260) -> str:
    import textwrap

    return "\n".join(textwrap.wrap(text, width))


def svg_with_tooltips(figure, geometry: ModelGeometry) -> str:
    """The figure as SVG text in which every drawn label carries its element's name and
    values (or its body's) as a tooltip (an SVG ``<title>``), deterministic."""
    import html
    import io
    import re

    import matplotlib

    tips = {element.id: element.description for element in geometry.elements}
    roles = {"body": "car body", "bogie": "bogie frame", "wheelset": "wheelset", "lever": "steering lever"}
    tips.update({body.id: f"{body.id}: {roles.get(body.role, body.role)}" + (
        f", outline {' x '.join(f'{side:.2f}' for side in body.outline)} m (from its mass and inertias)"
        if body.outline else "") for body in geometry.bodies})
    buffer = io.StringIO()
    with matplotlib.rc_context({"svg.hashsalt": "express-drawing", "svg.fonttype": "none"}):
        figure.savefig(buffer, format="svg", metadata={"Date": None})

    def titled(match) -> str:
        name = html.unescape(match.group(1))
        tip = tips.get(name)
        return match.group(0) + (f"\n   <title>{html.escape(tip)}</title>" if tip else "")

    return re.sub(r'<g id="label:([^"]*)">', titled, buffer.getvalue())
