"""Figures are pure functions of arrays: what they draw, and how they are written."""

from __future__ import annotations

import sys

import numpy as np
import pytest
from matplotlib.collections import PathCollection
from matplotlib.figure import Figure

from express.analysis import plots


def _lines(axis, colour=None):
    """Drawn data lines (not the reference lines spanning the axes)."""
    from matplotlib.colors import to_hex

    found = []
    for line in axis.get_lines():
        if line.get_linestyle() in ("None", "none", " ", ""):
            continue
        if colour is not None and to_hex(line.get_color()) != to_hex(colour):
            continue
        found.append(line)
    return found


def _locus(speeds):
    """Two oscillatory modes whose real parts cross (so their sort order swaps), one real pair."""
    v = np.asarray(speeds)
    hunting = (-0.5 + 0.01 * v) + 2j * np.pi * 1.0
    body = (-0.1 - 0.002 * v) + 2j * np.pi * 3.0
    real = np.stack([-5.0 - 0 * v, -7.0 - 0 * v], axis=1)
    values = np.concatenate([np.stack([hunting, hunting.conj(), body, body.conj()], axis=1), real], axis=1)
    order = np.lexsort((-values.imag, -values.real), axis=-1)
    return np.take_along_axis(values, order, axis=-1)


def test_figures_are_plain_figures_and_leave_the_backend_alone():
    import matplotlib

    backend = matplotlib.get_backend()
    rc_before = dict(matplotlib.rcParams)
    speeds = np.linspace(10.0, 100.0, 20)
    figure = plots.figure_eigen_locus(speeds, _locus(speeds), title="t")
    assert isinstance(figure, Figure)
    assert figure.canvas.manager is None  # not registered with pyplot
    assert matplotlib.get_backend() == backend
    assert dict(matplotlib.rcParams) == rc_before  # the style is applied locally only
    pyplot = sys.modules.get("matplotlib.pyplot")
    assert pyplot is None or figure.number not in pyplot.get_fignums() if hasattr(figure, "number") else True


def test_source_never_switches_the_backend():
    from pathlib import Path

    text = Path(plots.__file__).read_text(encoding="utf-8")
    assert "matplotlib.use(" not in text and "import matplotlib.pyplot" not in text


@pytest.mark.parametrize(
    ("speeds", "unstable", "segments", "crosses"),
    [
        ([300, 320, 340, 360, 380], [0, 0, 0, 0, 0], 1, 0),
        ([5, 5, 340, 360, 380], [1, 1, 0, 0, 0], 1, 2),  # unstable at the smallest conicities
        ([300, 320, 3.6, 360, 380], [0, 0, 1, 0, 0], 2, 1),  # an unstable window breaks the line
        ([300, np.nan, 340, 3.6, 380], [0, 0, 0, 1, 0], 3, 1),  # nan (stable to the limit) breaks it too
    ],
)
def test_critical_speed_curve_breaks_where_no_finite_stable_point(speeds, unstable, segments, crosses):
    conicity = np.linspace(0.02, 0.10, 5)
    figure = plots.figure_critical_speed(
        [{"label": "car", "conicity": conicity, "speed_kmh": np.array(speeds, float),
          "unstable_at_min": np.array(unstable, bool), "color": "#123456"}])
    axis = figure.axes[0]
    drawn = _lines(axis, "#123456")
    assert len(drawn) == segments
    # no segment spans a flagged or nan point
    flagged = {float(c) for c, s, u in zip(conicity, speeds, unstable, strict=True) if u or not np.isfinite(s)}
    for line in drawn:
        xs = line.get_xdata()
        assert not (flagged & {float(x) for x in xs})
        assert np.all(np.diff(np.flatnonzero(np.isin(conicity, xs))) == 1)  # consecutive points only
    markers = [line for line in axis.get_lines() if line.get_marker() == "X"]
    assert sum(len(line.get_xdata()) for line in markers) == crosses
    labels = [t.get_text() for t in axis.get_legend().get_texts()]
    assert labels.count("car") == 1  # one legend entry however many segments
    assert axis.get_xlabel().startswith("tread conicity") and "km/h" in axis.get_ylabel()


@pytest.mark.parametrize(
    ("tops", "segments", "bars"),
    [
        ([np.nan] * 5, 1, 0),  # nothing known: one line
        ([np.nan, np.nan, 140.0, np.inf, np.nan], 2, 1),  # 78-140 km/h window closes before 335: a jump
        ([np.nan, np.nan, 400.0, np.inf, np.nan], 1, 1),  # the ranges overlap: the same instability, joined
        ([np.nan, np.nan, np.inf, np.inf, np.nan], 1, 0),  # unstable up to the top at both: joined
    ],
)
def test_critical_speed_curve_breaks_where_a_window_closes(tops, segments, bars):
    from matplotlib.collections import LineCollection

    conicity = np.array([0.04, 0.05, 0.06, 0.07, 0.08])
    speeds = np.array([51.0, 71.0, 78.0, 335.0, 351.0])
    figure = plots.figure_critical_speed(
        [{"label": "car", "conicity": conicity, "speed_kmh": speeds, "window_end_kmh": np.array(tops),
          "color": "#123456"}])
    axis = figure.axes[0]
    assert len(_lines(axis, "#123456")) == segments
    drawn = [c for c in axis.collections if isinstance(c, LineCollection)]
    assert sum(len(c.get_segments()) for c in drawn) == bars
    if bars:
        assert axis.get_ylim()[1] >= 140.0


def test_root_locus_complex_plane():
    speeds = np.linspace(10.0, 100.0, 30)
    locus = _locus(speeds)
    figure = plots.figure_root_locus_complex(speeds, locus, title="car", critical_kmh=50.0)
    axis, colourbar = figure.axes
    scatters = [c for c in axis.collections if isinstance(c, PathCollection)]
    assert len(scatters) == 1
    points = scatters[0].get_offsets()
    # the upper half plane only: two complex modes and the two real eigenvalues, at every speed
    assert len(points) == 4 * speeds.size
    assert np.all(points[:, 1] >= 0)
    assert np.allclose(sorted(set(np.round(points[:, 1], 6))), [0.0, 1.0, 3.0])
    assert np.allclose(np.sort(scatters[0].get_array()), np.sort(np.repeat(speeds, 4)))
    assert axis.get_xlabel() == "real part of eigenvalue [1/s]"
    assert axis.get_ylabel().startswith("frequency") and "[Hz]" in axis.get_ylabel()
    assert colourbar.get_ylabel() == "speed V [km/h]"
    star = [line for line in axis.get_lines() if line.get_marker() == "*"]
    assert len(star) == 1


def test_mode_branches_follow_modes_through_a_change_of_order():
    speeds = np.linspace(10.0, 100.0, 40)
    locus = _locus(speeds)
    # the sort order swaps where the real parts cross (v = 100/3): column 0 changes mode
    assert np.ptp(np.abs(locus[:, 0].imag)) > 1.0
    branches = plots.mode_branches(locus)
    assert branches.shape == (speeds.size, 2)  # one per conjugate pair; the real pair dropped
    frequencies = branches.imag / (2 * np.pi)
    assert np.allclose(np.ptp(frequencies, axis=0), 0.0)  # each column keeps its mode
    assert sorted(np.round(frequencies[0], 6)) == [1.0, 3.0]


def test_damping_vs_speed_one_line_per_mode():
    speeds = np.linspace(10.0, 100.0, 40)
    branches = plots.mode_branches(_locus(speeds))
    figure = plots.figure_damping_vs_speed(speeds, branches, labels=["a", "b"], critical_kmh=50.0)
    axis = figure.axes[0]
    drawn = [line for line in axis.get_lines() if len(line.get_xdata()) == speeds.size]
    assert len(drawn) == 2
    for line, branch in zip(sorted(drawn, key=lambda line: line.get_label()), branches.T[np.argsort(["a", "b"])], strict=True):
        assert np.allclose(line.get_ydata(), -branch.real / np.abs(branch))
    assert axis.get_xlabel() == "speed V [km/h]"
    assert axis.get_ylabel().startswith("damping ratio")
    labels = [t.get_text() for t in axis.get_legend().get_texts()]
    assert labels[:2] == ["a", "b"] or labels[:2] == ["b", "a"]
    assert any("critical speed" in label for label in labels)
    # the hunting mode turns unstable: its damping ratio crosses zero
    hunting = next(line for line in drawn if np.min(line.get_ydata()) < 0)
    assert np.max(hunting.get_ydata()) > 0


def test_damping_vs_speed_limits_frequency_and_checks_labels():
    speeds = np.linspace(10.0, 100.0, 40)
    branches = plots.mode_branches(_locus(speeds))
    figure = plots.figure_damping_vs_speed(speeds, branches, max_frequency_hz=2.0, highlight=0)
    drawn = [line for line in figure.axes[0].get_lines() if len(line.get_xdata()) == speeds.size]
    assert len(drawn) == 1  # the 3 Hz mode is left out
    with pytest.raises(ValueError, match="labels"):
        plots.figure_damping_vs_speed(speeds, branches, labels=["only one"])
    with pytest.raises(ValueError, match="shape"):
        plots.figure_damping_vs_speed(speeds[:-1], branches)


def test_save_figure_is_deterministic_and_whole(tmp_path):
    speeds = np.linspace(10.0, 100.0, 20)
    paths = [tmp_path / "a.svg", tmp_path / "a.png", tmp_path / "a.pdf"]
    first = plots.save_figure(plots.figure_root_locus_complex(speeds, _locus(speeds)), paths)
    assert first == paths
    data = [p.read_bytes() for p in paths]
    plots.save_figure(plots.figure_root_locus_complex(speeds, _locus(speeds)), paths)
    assert [p.read_bytes() for p in paths] == data
    svg = data[0].decode("utf-8")
    assert "<dc:date>" not in svg and "Matplotlib" not in svg.split("<svg", 1)[1][:400]
    assert data[1][:8] == b"\x89PNG\r\n\x1a\n" and data[2][:5] == b"%PDF-"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.pdf", "a.png", "a.svg"]  # no temporary left


def test_save_figure_refuses_an_unknown_format_before_writing(tmp_path):
    figure = plots.figure_eigen_locus(np.linspace(1, 2, 3), _locus(np.linspace(1, 2, 3)), title="t")
    with pytest.raises(ValueError, match="unknown figure format"):
        plots.save_figure(figure, [tmp_path / "ok.png", tmp_path / "bad.gif"])
    assert not list(tmp_path.iterdir())
