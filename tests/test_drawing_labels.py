"""Label placement of model drawings (``express.drawing.views.place_labels``) on crowded
drawings: the same places as measuring every candidate offset and comparing with every
placed label (the rule as first written, kept here as the reference), and the grid index
of placed boxes finds exactly the overlaps of the full comparison."""

from __future__ import annotations

import numpy as np
import pytest
from matplotlib.transforms import Bbox

from express.drawing import views
from express.drawing.geometry import DrawnBody, DrawnElement, ModelGeometry
from express.drawing.views import _PlacedBoxes, figure_model


def _crowd(count: int, seed: int) -> ModelGeometry:
    """``count`` boxes scattered over a few metres, most labels in each other's way."""
    rng = np.random.default_rng(seed)
    bodies, points, hosts = [], {}, {}
    for i, (x, y, z) in enumerate(rng.uniform((-6.0, -1.5, 0.0), (6.0, 1.5, 3.0), size=(count, 3))):
        centre = (float(x), float(y), float(z))
        low, high = tuple(c - 0.2 for c in centre), tuple(c + 0.2 for c in centre)
        bodies.append(DrawnBody(f"B{i}", ("body", "bogie")[i % 2], centre, low, high))
        points[f"P{i}"], hosts[f"P{i}"] = centre, f"B{i}"
    # springs between neighbours; their (smaller) labels are drawn up to 120 elements
    elements = tuple(DrawnElement(f"E{i}", f"P{i}", f"P{i + 1}", i % 3, "spring") for i in range(min(count - 1, 110)))
    return ModelGeometry("crowd", tuple(bodies), points, hosts, elements, (), ())


def _reference_placement(figure) -> list[str]:
    """The rule measured candidate by candidate against every placed label."""
    renderer = figure.canvas.get_renderer()
    hidden: list[str] = []
    for axis in figure.axes:
        placed: list = []
        texts = [t for t in axis.texts if str(t.get_gid() or "").startswith("label:")]
        texts.sort(key=lambda t: t.get_fontsize(), reverse=True)
        for text in texts:
            text.set_visible(True)
            frame = axis.get_window_extent(renderer)
            offsets = views._BODY_CANDIDATES if text.get_fontsize() >= 6 else views._CANDIDATES
            for offset in offsets:
                text.xyann = offset
                box = text.get_window_extent(renderer)
                inside = frame.x0 <= box.x0 and box.x1 <= frame.x1 and frame.y0 <= box.y0 and box.y1 <= frame.y1
                if inside and not any(box.overlaps(other) for other in placed):
                    placed.append(box)
                    break
            else:
                text.set_visible(False)
                name = str(text.get_gid())[6:]
                if name not in hidden:
                    hidden.append(name)
    return hidden


def _labels(figure) -> list[tuple]:
    return [(str(t.get_gid()), t.get_visible(), tuple(t.xyann)) for axis in figure.axes for t in axis.texts
            if str(t.get_gid() or "").startswith("label:")]


@pytest.mark.parametrize(("count", "seed"), [(40, 1), (150, 2), (250, 3)])
def test_placement_equals_the_reference_rule(count, seed, monkeypatch):
    hidden: list = []
    original = views.place_labels
    monkeypatch.setattr(views, "place_labels", lambda figure: hidden.extend(original(figure)) or list(hidden))
    figure = figure_model(_crowd(count, seed))
    placed = _labels(figure)
    assert any(not visible for _, visible, _ in placed) and any(visible for _, visible, _ in placed)
    assert _reference_placement(figure) == hidden
    assert _labels(figure) == placed


def test_grid_index_finds_every_overlap():
    rng = np.random.default_rng(5)
    boxes = [Bbox.from_bounds(*rng.uniform(0, 400, 2), *rng.uniform(5, 60, 2)) for _ in range(300)]
    boxes += [Bbox.from_extents(96.0, 10.0, 144.0, 20.0), Bbox.from_extents(144.0, 20.0, 150.0, 30.0)]  # touching a cell edge
    index = _PlacedBoxes()
    for box in boxes[::2]:
        index.add(box)
    for box in boxes[1::2]:
        expected = any(box.overlaps(other) for other in boxes[::2])
        assert index.hit(box.x0, box.y0, box.x1, box.y1) == expected
        assert any(box.overlaps(other) for other in index.near(box.x0, box.y0, box.x1, box.y1)) == expected
