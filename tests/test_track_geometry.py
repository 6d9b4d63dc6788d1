"""Tests of express.rail.track.geometry: layout, curvature and cant, exact geometry, limits."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from scipy.integrate import quad

from express.rail.track import (
    MAX_CANT,
    MAX_TRACK_LENGTH,
    Curve,
    SinusoidIrregularity,
    Straight,
    Track,
    Transition,
    paper_curve,
)
from express.rail.track.tables import CentrelineTable, SegmentTables

R, CANT, LT, LC = 400.0, 0.095, 95.0, 170.0
SHAPES = ("linear", "sine")


# --- layout ------------------------------------------------------------------------------


def test_paper_curve_layout():
    t = paper_curve()
    assert t.length == pytest.approx(460.0)
    np.testing.assert_allclose(t.boundaries, [0, 50, 145, 315, 410, 460])
    assert [type(sg).__name__ for sg in t.segments] == [
        "Straight", "Transition", "Curve", "Transition", "Straight"]
    assert all(sg.shape == "sine" for sg in t.segments if isinstance(sg, Transition))
    assert t.speed == pytest.approx(120 / 3.6)
    assert paper_curve(lead_in=0).length == pytest.approx(360.0)
    assert paper_curve(lead_in=20, lead_out=80).boundaries[-1] == pytest.approx(460.0)


@pytest.mark.parametrize("direction, sign", [("left", 1.0), ("right", -1.0)])
def test_steady_curve_values(direction, sign):
    t = paper_curve(direction)
    s = np.linspace(145.0, 314.99, 50)
    np.testing.assert_allclose(t.curvature(s), sign / R, rtol=1e-14)
    np.testing.assert_allclose(t.cant(s), sign * CANT, rtol=1e-14)
    np.testing.assert_array_equal(t.curvature_rate(s), 0.0)
    np.testing.assert_array_equal(t.cant_rate(s), 0.0)


def test_outside_is_straight():
    t = paper_curve()
    s = np.array([-100.0, -1e-9, 460.0, 1000.0])
    for f in (t.curvature, t.cant, t.curvature_rate, t.cant_rate):
        np.testing.assert_array_equal(f(s), 0.0)
    assert isinstance(t.curvature(100.0), float)


@pytest.mark.parametrize("shape", SHAPES)
@pytest.mark.parametrize("direction", ["left", "right"])
def test_curvature_and_cant_continuous_at_joins(shape, direction):
    t = paper_curve(direction, shape=shape)
    eps = 1e-7
    for b in t.boundaries:
        for f, scale in ((t.curvature, 1 / R), (t.cant, CANT)):
            assert abs(f(b + eps) - f(b - eps)) < 1e-5 * scale, (f.__name__, b)


def test_transition_between_two_curves_continuous():
    # reverse curves joined by a transition: curvature ramps from +1/300 to -1/500
    t = Track((Curve(50, 300, "left", 0.08), Transition(60, "linear"), Curve(50, 500, "right", 0.05)))
    np.testing.assert_allclose(t.curvature([50, 80, 110]), [1 / 300, (1 / 300 - 1 / 500) / 2, -1 / 500])
    np.testing.assert_allclose(t.cant([50, 80, 110]), [0.08, 0.015, -0.05])
    for b in (50.0, 110.0):
        assert t.curvature(b + 1e-7) == pytest.approx(t.curvature(b - 1e-7), abs=1e-10)


@pytest.mark.parametrize(
    "shape, fraction, expected",
    [
        ("linear", 0.5, 0.5),
        ("sine", 0.5, 0.5),
        ("linear", 0.25, 0.25),
        ("sine", 0.25, (1 - math.cos(math.pi / 4)) / 2),
        ("sine", 0.75, (1 - math.cos(3 * math.pi / 4)) / 2),
    ],
)
def test_ramp_values(shape, fraction, expected):
    t = paper_curve(shape=shape)
    s_in = 50 + fraction * LT  # entry transition
    s_out = 315 + (1 - fraction) * LT  # exit transition, mirrored
    assert t.curvature(s_in) * R == pytest.approx(expected, rel=1e-12)
    assert t.cant(s_in) / CANT == pytest.approx(expected, rel=1e-12)
    assert t.curvature(s_out) * R == pytest.approx(expected, rel=1e-12)


@pytest.mark.parametrize("shape", SHAPES)
@pytest.mark.parametrize("which", ["curvature", "cant"])
def test_rates_match_finite_differences(shape, which):
    t = paper_curve("right", shape=shape)
    value, rate = getattr(t, which), getattr(t, which + "_rate")
    s = np.linspace(-10, 470, 2401)
    s = s[np.min(np.abs(s[:, None] - t.boundaries[None, :]), axis=1) > 1e-3]
    h = 1e-4
    fd = (value(s + h) - value(s - h)) / (2 * h)
    scale = np.max(np.abs(rate(s)))
    np.testing.assert_allclose(rate(s), fd, atol=1e-7 * scale)


def test_rate_end_values():
    lin, sine = paper_curve(shape="linear"), paper_curve(shape="sine")
    assert lin.curvature_rate(60.0) == pytest.approx(1 / (R * LT))
    assert lin.cant_rate(400.0) == pytest.approx(-CANT / LT)
    assert sine.curvature_rate(50.0) == pytest.approx(0.0, abs=1e-15)
    assert sine.curvature_rate(97.5) == pytest.approx(math.pi / 2 / (R * LT))


def test_segment_validation():
    with pytest.raises(ValueError, match="length"):
        Straight(0.0)
    with pytest.raises(ValueError, match="shape"):
        Transition(10, "cubic")
    with pytest.raises(ValueError, match=r"radius.*direction"):
        Curve(10, -5, "up")
    with pytest.raises(ValueError, match="segments 2 and 3 are both transitions"):
        Track((Straight(10), Transition(10), Transition(10)))


# --- exact geometry ----------------------------------------------------------------------


@pytest.mark.parametrize("direction, sign", [("left", 1.0), ("right", -1.0)])
def test_circle_heading_and_centreline(direction, sign):
    radius, length = 250.0, 600.0  # more than a quarter turn
    t = Track((Curve(length, radius, direction),))
    s = np.linspace(0, length, 997)
    np.testing.assert_allclose(t.heading(s), sign * s / radius, rtol=1e-14, atol=1e-15)
    x, y = t.centreline(s)
    np.testing.assert_allclose(x, radius * np.sin(s / radius), atol=1e-10)
    np.testing.assert_allclose(y, sign * radius * (1 - np.cos(s / radius)), atol=1e-10)
    # straight continuation after the end, and before the start
    th = sign * length / radius
    x1, y1 = t.centreline(length + 10.0)
    assert x1 == pytest.approx(radius * np.sin(length / radius) + 10 * np.cos(th), abs=1e-10)
    assert y1 == pytest.approx(sign * radius * (1 - np.cos(length / radius)) + 10 * np.sin(th), abs=1e-10)
    assert t.centreline(-5.0) == (-5.0, 0.0)
    # lateral offset of the track ahead/behind from the tangent: R (1 - cos(lx / R))
    for lx in (7.2, -7.2, 1.15, 30.0):
        inner = s[(s > abs(lx)) & (s < length - abs(lx))]
        off = t.lateral_offset_exact(inner, lx)
        np.testing.assert_allclose(off, sign * radius * (1 - np.cos(lx / radius)), atol=1e-11)


@pytest.mark.parametrize("shape", SHAPES)
def test_heading_and_centreline_against_quadrature(shape):
    t = paper_curve(shape=shape)
    pts = list(t.boundaries)
    for s in (30.0, 97.3, 145.0, 222.2, 380.0, 460.0, 470.0):
        th = quad(t.curvature, -10, s, points=[p for p in pts if p < s], epsabs=1e-14, limit=200)[0]
        assert t.heading(s) == pytest.approx(th, abs=1e-12)
        kw = {"points": [p for p in pts if p < s], "epsabs": 1e-13, "limit": 200}
        x = quad(lambda u: math.cos(t.heading(u)), 0, s, **kw)[0]
        y = quad(lambda u: math.sin(t.heading(u)), 0, s, **kw)[0]
        xs, ys = t.centreline(s)
        assert xs == pytest.approx(x, abs=1e-9) and ys == pytest.approx(y, abs=1e-9)
    assert t.heading(1e3) == pytest.approx(LT / R + LC / R)  # two half ramps + arc


def test_offset_sign_convention():
    left, right = paper_curve("left"), paper_curve("right")
    for lx in (7.2, -7.2):
        assert left.lateral_offset_exact(230.0, lx) > 0 > right.lateral_offset_exact(230.0, lx)
        assert left.lateral_offset_first_order(230.0, lx) == pytest.approx(lx**2 / (2 * R))


# Max |approximation - exact| along the paper's curve (s from -20 m to length + 20 m,
# every 0.01 m), in metres, as recorded in docs/track.md.
APPROXIMATION_ERRORS = [
    # shape, lx, first order, second order, two-station
    ("sine", 7.2, 2.569e-3, 1.545e-4, 1.519e-4),
    ("sine", -7.2, 2.569e-3, 1.545e-4, 1.519e-4),
    ("sine", 1.15, 1.048e-5, 1.008e-7, 9.96e-8),
    ("linear", 7.2, 1.639e-3, 1.632e-3, 6.301e-4),
    ("linear", -7.2, 1.639e-3, 1.639e-3, 6.301e-4),
    ("linear", 1.15, 6.672e-6, 6.499e-6, 2.567e-6),
]


@pytest.mark.parametrize("shape, lx, first, second, two", APPROXIMATION_ERRORS)
def test_offset_approximation_errors(shape, lx, first, second, two):
    t = paper_curve(shape=shape)
    s = np.arange(-20.0, t.length + 20.0, 0.01)
    exact = t.lateral_offset_exact(s, lx)
    for method, recorded in (
        (t.lateral_offset_first_order, first),
        (t.lateral_offset_second_order, second),
        (t.lateral_offset_two_station, two),
    ):
        err = np.max(np.abs(method(s, lx) - exact))
        assert err == pytest.approx(recorded, rel=0.01), method.__name__
    steady = lx**2 / (2 * R)
    assert np.max(np.abs(t.lateral_offset_first_order(s, lx) - exact)) / steady < 0.04
    # in the steady curve only the neglected heading nonlinearity remains: ~ lx^4 / (24 R^3)
    mid = (s > 145 + abs(lx)) & (s < 315 - abs(lx))
    err_mid = np.max(np.abs(t.lateral_offset_first_order(s[mid], lx) - exact[mid]))
    assert err_mid == pytest.approx(lx**4 / (24 * R**3), rel=0.01)


# --- limits and records --------------------------------------------------------------------


@pytest.mark.parametrize(
    "make, text",
    [
        (lambda: Straight(MAX_TRACK_LENGTH * 1.001), "'length' must be at most 1e+06 m"),
        (lambda: Straight(float("inf")), "'length' must be a finite number"),
        (lambda: Straight(10**400), "'length' must be a finite number"),  # an int beyond float range
        (lambda: Transition(1e300), "'length' must be at most"),
        (lambda: Curve(100, 400, "left", 95.0), "'cant' must be at most 0.5 m in size, got 95.0 m"),
        (lambda: Curve(100, 400, "right", -0.6), "'cant' must be at most 0.5 m"),
        (lambda: Curve(100, float("nan"), "left"), "'radius' must be a finite number"),
    ],
)
def test_segment_limits(make, text):
    with pytest.raises(ValueError, match=re.escape(text)):
        make()


def test_segment_limits_are_inclusive():
    assert Straight(MAX_TRACK_LENGTH).length == MAX_TRACK_LENGTH
    assert Curve(10, 400, "left", MAX_CANT).signed_cant == MAX_CANT
    assert Curve(10, 400, "right", -MAX_CANT).signed_cant == MAX_CANT  # adverse cant in a right curve


def test_total_length_limit():
    half = Straight(MAX_TRACK_LENGTH / 2)
    assert Track((half, half)).length == MAX_TRACK_LENGTH
    with pytest.raises(ValueError, match=r"Track: the segments are 1\.5e\+06 m long, more than the limit 1e\+06 m"):
        Track((half, half, half))


def test_track_field_problems_name_each_field():
    problems = Track.field_problems([Straight(10), "curve"], irregularity=3, speed=-1.0)
    assert [key for key, _ in problems] == ["segments", "irregularity", "speed"]
    assert "segment 2 is not a Straight, Transition or Curve" in problems[0][1]
    assert Track.field_problems((Straight(10),)) == []


def test_tables_are_typed_records():
    t = paper_curve()
    assert isinstance(t.tables, SegmentTables) and isinstance(t.centreline_table, CentrelineTable)
    assert t.tables is t.tables  # computed once
    np.testing.assert_allclose(t.tables.starts, [0, 50, 145, 315, 410, 460])
    np.testing.assert_allclose(t.tables.rho0, [0, 0, 1 / R, 1 / R, 0])
    np.testing.assert_allclose(t.tables.rho1, [0, 1 / R, 1 / R, 0, 0])
    np.testing.assert_allclose(t.tables.cant1, [0, CANT, CANT, 0, 0])
    assert list(t.tables.shape) == [0, 2, 0, 2, 0]
    # knots at most 10 m apart, every joint among them
    knots = t.centreline_table.knots
    assert np.max(np.diff(knots)) <= 10.0 + 1e-12
    assert set(t.boundaries) <= set(np.round(knots, 9))
    # no private attributes set behind the dataclass's back: fields and the two cached tables only
    assert set(vars(t)) == {"segments", "irregularity", "speed", "vertical", "cross_level", "gauge", "tables",
                            "centreline_table"}


def test_track_is_an_immutable_value():
    t = paper_curve()
    with pytest.raises(AttributeError):
        t.speed = 1.0  # type: ignore[misc]
    assert t == paper_curve() and hash(t) == hash(paper_curve())
    other = t.with_irregularity(SinusoidIrregularity(0.001, 20.0))
    assert other != t and other.tables.length == t.length
    # a list of segments is accepted (as before) and gives the same geometry
    listed = Track([Straight(50.0), Curve(100.0, 300.0, "right", 0.05)])
    assert listed.curvature(75.0) == pytest.approx(-1 / 300)
    assert Track(()).length == 0.0 and Track(()).curvature(3.0) == 0.0
