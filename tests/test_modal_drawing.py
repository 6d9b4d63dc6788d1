"""A flexible car body drawn deformed (issue 34 item 3): its modes move its points by
their shape values and bend its outline, in ``express draw --mode``, ``express eigen
--plot`` and the report's mode figures (``express.drawing.geometry``)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from cli_support import EXAMPLES, run
from express.cli.draw import model_geometry_of
from express.drawing.geometry import displaced_geometry
from express.io import load_model

FLEXIBLE = EXAMPLES / "manchester-flexible.toml"


@pytest.fixture(scope="module")
def coach():
    model = load_model(FLEXIBLE)
    return model, model_geometry_of(model)


def test_points_move_by_the_mode_shape(coach):
    """``q`` on ``CB.vb1`` moves the car body's seat ``CB_T1L`` by ``(0, 0, q phi)`` with
    ``phi`` the parameter ``CB_vb1_CB_T1L`` (to 1e-12 m), the bogies not at all; ``q`` on
    the torsion moves the seat at (lT, b2, h2 - hc) by ``(0, -psi lz q, psi ly q)``."""
    model, geometry = coach
    values = model.values()
    q = 100.0
    moved = displaced_geometry(geometry, {"CB.vb1": q})
    shift = np.subtract(moved.points["CB_T1L"], geometry.points["CB_T1L"])
    assert shift == pytest.approx([0.0, 0.0, q * values["CB_vb1_CB_T1L"]], abs=1e-12)
    assert abs(shift[2]) > 0.5
    for point, host in geometry.hosts.items():
        if host != "CB":
            assert moved.points[point] == geometry.points[point], point
    twisted = displaced_geometry(geometry, {"CB.to1": q})
    psi, ly, lz = values["CB_to1_CB_T1L"], values["b2"], values["h2"] - values["hc"]
    shift = np.subtract(twisted.points["CB_T1L"], geometry.points["CB_T1L"])
    assert shift == pytest.approx([0.0, -psi * lz * q, psi * ly * q], abs=1e-12)


def test_outline_bends_with_the_beam_shape(coach):
    """The car body's bent centre line is the beam's closed form times ``q``: ``2 q /
    sqrt(m)`` at both ends (``W(0) = W(L) = 2``) and ``q`` times the floor centre's shape
    value at the middle (to 1e-12), the side view's outline drawn through it (its top edge
    rises by the same difference from the middle to the beam's ends, to the 3 digits of
    the amplitude in the title; beyond them, over the drawn box's longer estimated length,
    it continues straight)."""
    from matplotlib.patches import Polygon

    from express.drawing.modes import figure_flexible_mode

    model, geometry = coach
    values = model.values()
    q = 100.0
    body = next(b for b in displaced_geometry(geometry, {"CB.vb1": q}).bodies if b.id == "CB")
    bend = np.array(body.bend)
    assert bend[0, 0] == pytest.approx(-values["CB_length"] / 2) and bend[-1, 0] == pytest.approx(values["CB_length"] / 2)
    assert bend[[0, -1], 2] == pytest.approx(2 * q / math.sqrt(values["mc"]), rel=1e-12)
    middle = bend[np.argmin(np.abs(bend[:, 0])), 2]
    assert middle == pytest.approx(q * values["CB_vb1_floor_centre"], rel=1e-12)
    assert np.all(bend[:, 1] == 0.0)
    figure = figure_flexible_mode(geometry, "CB.vb1")
    side = next(axis for axis in figure.axes if axis.get_title().startswith("side"))
    outlines = [p for p in side.patches if isinstance(p, Polygon) and len(p.get_xy()) > 20]
    assert len(outlines) == 1  # the bent car body (the rigid one drawn faintly is a box)
    xy = outlines[0].get_xy()
    top = xy[: len(xy) // 2]
    end = top[np.argmin(np.abs(top[:, 0] - values["CB_length"] / 2)), 1]
    rise = end - top[np.argmin(np.abs(top[:, 0])), 1]
    amplitude = float(figure._suptitle.get_text().split("q = ")[1].split()[0])
    expected = amplitude * (2 / math.sqrt(values["mc"]) - values["CB_vb1_floor_centre"])
    assert rise == pytest.approx(expected, rel=2e-3)  # the amplitude printed to 3 digits


@pytest.mark.slow  # four figures drawn: 27 s on a loaded shared machine
def test_draw_eigen_and_report_draw_the_bending(coach, tmp_path, capsys):
    """``express draw --mode CB.vb1`` writes the figure (an unknown mode: exit 2 naming
    the modes, nothing written); ``express eigen --mode N --plot`` of the bending mode
    writes its deformed shape; the report's mode figures add the first bending; the
    drawing geometry keeps the modes through the cache's data."""
    from express.analysis.stability.stability import eigen_analysis
    from express.drawing.geometry_data import geometry_data, geometry_from_data
    from express.numeric.statespace import load_vehicle
    from express.report.figures import mode_figures

    _, geometry = coach
    figure = tmp_path / "vb1.png"
    status, _, err = run(capsys, "draw", FLEXIBLE, "--mode", "CB.vb1", "-o", figure)
    assert status == 0 and figure.stat().st_size > 10_000, err
    bad = tmp_path / "bad.png"
    status, _, err = run(capsys, "draw", FLEXIBLE, "--mode", "CB.vb9", "-o", bad)
    assert status == 2 and "CB.vb1, CB.vb2, CB.to1" in err and not bad.exists()
    vehicle = load_vehicle(FLEXIBLE)
    modes = eigen_analysis(vehicle, 160 / 3.6).modes
    number = next(k for k, m in enumerate(modes, start=1) if m.kind == "car body first vertical bending")
    shape = tmp_path / "shape.png"
    status, _, err = run(capsys, "eigen", FLEXIBLE, "--speed", "160", "--mode", number, "--plot", shape)
    assert status == 0 and shape.exists(), err
    captions = [caption for _, caption in mode_figures(vehicle, geometry, 160 / 3.6, modes)]
    assert any("flexible body's first mode" in c and "car body first vertical bending" in c for c in captions)
    import json

    again = geometry_from_data(json.loads(json.dumps(geometry_data(geometry))))  # as the cache keeps it
    assert again.modes == geometry.modes and len(again.modes) == 3
