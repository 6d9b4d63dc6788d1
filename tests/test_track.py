"""Tests of express.rail.track: layout, exact geometry, irregularities, track files."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import quad

from express.rail.track import (
    ERRI_HIGH,
    ERRI_LOW,
    FRA_CLASS_5,
    FRA_CLASS_6,
    SPECTRA,
    Curve,
    NoIrregularity,
    ProfileIrregularity,
    SinusoidIrregularity,
    SpectrumIrregularity,
    Straight,
    Track,
    TrackError,
    Transition,
    get_spectrum,
    load_track,
    paper_curve,
    read_profile_csv,
    track_from_dict,
)

EXAMPLES = Path(__file__).resolve().parents[1] / "examples" / "tracks"
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
    with pytest.raises(ValueError, match="radius.*direction"):
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
        kw = dict(points=[p for p in pts if p < s], epsabs=1e-13, limit=200)
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


# --- spectra and irregularities ---------------------------------------------------------


def test_spectrum_constants():
    assert FRA_CLASS_5.A_a == pytest.approx(0.0762e-4)
    assert FRA_CLASS_6.A_a == pytest.approx(0.0339e-4)
    assert FRA_CLASS_5.omega_c == FRA_CLASS_6.omega_c == 0.8245
    assert FRA_CLASS_5.k == 0.25
    assert (ERRI_LOW.A, ERRI_HIGH.A) == (2.119e-7, 6.125e-7)
    assert (ERRI_LOW.omega_c, ERRI_LOW.omega_r) == (0.8246, 0.0206)
    assert get_spectrum("ERRI-High") is ERRI_HIGH
    with pytest.raises(KeyError, match="fra5"):
        get_spectrum("fra4")


@pytest.mark.parametrize("f, tabulated", [(0.02, 2.3194e-4), (0.1, 6.1608e-6), (0.2, 7.3333e-7)])
def test_erri_high_against_gensys_table(f, tabulated):
    # GENSYS TRC_IPSD manual, "ORE B176 high level" PSD_LAT in m^2/(1/m) = 2 pi S(Omega)
    assert 2 * np.pi * ERRI_HIGH.psd(2 * np.pi * f) == pytest.approx(tabulated, rel=2e-3)


@pytest.mark.parametrize("name", sorted(SPECTRA))
def test_closed_form_band_variance(name):
    sp = SPECTRA[name]
    lo, hi = 2 * np.pi / 120, 2 * np.pi / 3
    assert sp.variance(lo, hi) == pytest.approx(quad(sp.psd, lo, hi, limit=200)[0], rel=1e-9)


@pytest.mark.parametrize("name", sorted(SPECTRA))
def test_random_profile_variance_matches_psd(name):
    period = 2000.0
    irr = SpectrumIrregularity(name, seed=7, period=period)
    target = quad(SPECTRA[name].psd, 2 * np.pi / 120, 2 * np.pi / 3, limit=200)[0]
    n = 8192  # > 2 * highest harmonic (period / 3 m = 667)
    s = np.arange(n) * (period / n)
    y = irr(s)
    assert np.mean(y**2) == pytest.approx(target, rel=0.02)  # exact over one period
    assert np.mean(y**2) == pytest.approx(irr.band_variance, rel=1e-9)
    # the spectral shape: one-sided periodogram over the period vs the PSD
    spec = np.abs(np.fft.rfft(y)) ** 2 / n**2 * 2 / (2 * np.pi / period)
    k = np.rint(irr.wavenumbers / (2 * np.pi / period)).astype(int)
    inner = slice(1, -1)  # the outer bins also hold the band's fractional ends
    np.testing.assert_allclose(spec[k][inner], SPECTRA[name].psd(irr.wavenumbers)[inner], rtol=0.01)
    # a window shorter than the period still has about the right variance
    assert np.var(irr(np.arange(0, 1000, 0.5))) == pytest.approx(target, rel=0.5)


def test_random_profile_is_reproducible_and_periodic():
    s = np.linspace(0, 300, 601)
    a = SpectrumIrregularity("fra6", seed=3)
    b = SpectrumIrregularity("fra6", seed=3)
    c = SpectrumIrregularity("fra6", seed=4)
    np.testing.assert_array_equal(a(s), b(s))
    assert np.max(np.abs(a(s) - c(s))) > 1e-4
    np.testing.assert_allclose(a(s + a.period), a(s), atol=1e-12)
    h = 1e-4
    np.testing.assert_allclose(a.rate(s), (a(s + h) - a(s - h)) / (2 * h), atol=1e-8)
    tab = a.tabulate(0, 300, 0.05)
    assert np.max(np.abs(tab(s[1:-1] + 0.013) - a(s[1:-1] + 0.013))) < 2e-5


def test_spectrum_irregularity_validation():
    with pytest.raises(ValueError, match="wavelength_min"):
        SpectrumIrregularity("erri_low", wavelength_min=50, wavelength_max=20)
    with pytest.raises(ValueError, match="unknown spectrum"):
        SpectrumIrregularity("fra9")


def test_sinusoid_and_none():
    irr = SinusoidIrregularity(0.002, 25.0, phase=0.3)
    s = np.linspace(0, 60, 7)
    np.testing.assert_allclose(irr(s), 0.002 * np.sin(2 * np.pi * s / 25 + 0.3))
    np.testing.assert_allclose(irr.rate(s), 0.002 * 2 * np.pi / 25 * np.cos(2 * np.pi * s / 25 + 0.3))
    t = paper_curve(irregularity=irr)
    assert t.lateral_irregularity(10.0) == pytest.approx(irr(10.0))
    assert t.with_irregularity(NoIrregularity()).lateral_irregularity(10.0) == 0.0
    with pytest.raises(ValueError, match="wavelength"):
        SinusoidIrregularity(0.001, 0.0)


# --- CSV profiles -------------------------------------------------------------------------


def test_read_profile_csv(tmp_path):
    f = tmp_path / "profile.csv"
    f.write_text("# measured alignment\ndistance_m, yR_m\n0, 0\n10, 0.002\n\n20; -0.001\n30\t0.0\n")
    irr = read_profile_csv(f)
    assert isinstance(irr, ProfileIrregularity)
    np.testing.assert_allclose(irr([0, 5, 15, 25, 30]), [0, 0.001, 0.0005, -0.0005, 0.0])
    np.testing.assert_allclose(irr([-10, 50]), [0.0, 0.0])  # end values held
    np.testing.assert_allclose(irr.rate([5, 15, 40]), [2e-4, -3e-4, 0.0])


def test_read_profile_csv_reports_every_bad_row(tmp_path):
    f = tmp_path / "bad.csv"
    f.write_text("s,yR\n0,0\n10,abc\n20,0.001,7\n15,0.0\n30,nan\n40,0.001\n")
    with pytest.raises(TrackError) as info:
        read_profile_csv(f)
    problems = info.value.problems
    assert [p.split(": ")[0] for p in problems] == [f"{f}:3", f"{f}:4", f"{f}:6"]
    assert "not a number" in problems[0]
    assert "expected 2 columns (distance, yR), got 3" in problems[1]
    assert "values must be finite" in problems[2]
    assert str(f) in str(info.value)


def test_read_profile_csv_order_and_size(tmp_path):
    f = tmp_path / "order.csv"
    f.write_text("0,0\n10,0\n10,0.001\n")
    with pytest.raises(TrackError, match=r"order\.csv:3: distance 10\.0 is not greater than 10\.0 on line 2"):
        read_profile_csv(f)
    g = tmp_path / "short.csv"
    g.write_text("s,y\n0,0\n")
    with pytest.raises(TrackError, match="at least two data rows"):
        read_profile_csv(g)
    with pytest.raises(TrackError, match="cannot read"):
        read_profile_csv(tmp_path / "missing.csv")


# --- track files ----------------------------------------------------------------------------


@pytest.mark.parametrize("path", sorted(EXAMPLES.glob("*.toml")), ids=lambda p: p.name)
def test_examples_load(path):
    t = load_track(path)
    assert t.length > 0 and t.speed is not None


def test_paper_curve_file_matches_factory():
    assert load_track(EXAMPLES / "paper_curve.toml") == paper_curve()
    sinus = load_track(EXAMPLES / "straight_sinusoid.toml")
    assert sinus.irregularity == SinusoidIrregularity(0.001, 20.0, 0.0)


def test_units_and_irregularities_from_dict(tmp_path):
    (tmp_path / "p.csv").write_text("0,0\n100,0.003\n")
    d = {
        "speed": "36 km/h",
        "segment": [
            {"type": "straight", "length": "0.1 km"},
            {"type": "transition", "length": 40},
            {"type": "curve", "length": "60 m", "radius": 600, "direction": "right", "cant": "50 mm"},
        ],
        "irregularity": {"type": "csv", "file": "p.csv"},
    }
    t = track_from_dict(d, source=str(tmp_path / "t.toml"))
    assert t.speed == pytest.approx(10.0)
    assert t.segments[1] == Transition(40.0, "linear")
    assert t.curvature(150.0) == pytest.approx(-1 / 600) and t.cant(150.0) == pytest.approx(-0.05)
    assert t.lateral_irregularity(50.0) == pytest.approx(0.0015)
    d["irregularity"] = {"type": "sinusoid", "amplitude": "2 mm", "wavelength": 30, "phase": "90 deg"}
    assert track_from_dict(d).irregularity == SinusoidIrregularity(0.002, 30.0, math.pi / 2)
    d["irregularity"] = {"type": "spectrum", "spectrum": "FRA5", "seed": 2, "wavelength_max": "80 m"}
    irr = track_from_dict(d).irregularity
    assert irr.spectrum is FRA_CLASS_5 and irr.seed == 2 and irr.wavelength_max == 80.0


BAD_TRACK = """\
speed = "120 km/s"
colour = "red"

[[segment]]
type = "straight"
length = 50.0

[[segment]]
type = "transition"
length = 95.0
shape = "cosine"

[[segment]]
type = "curve"
length = 170.0
radius = -400.0
direction = "up"
cant = "95 inch"

[[segment]]
type = "strait"
length = 10

[[segment]]
type = "transition"
length = 20

[[segment]]
type = "transition"
lenght = 20

[irregularity]
type = "sinusoid"
amplitude = 0.001
"""


def test_bad_track_file_reports_everything(tmp_path):
    f = tmp_path / "bad.toml"
    f.write_text(BAD_TRACK)
    with pytest.raises(TrackError) as info:
        load_track(f)
    err = info.value
    assert isinstance(err, ValueError)
    msg = str(err)
    expected = [  # in line order
        f"{f}:1: track: 'speed' unit 'km/s' in '120 km/s' is not a speed unit",
        f"{f}:2: track: unknown key 'colour'",
        f"{f}:11: segment 2 (transition): 'shape' must be one of linear, sine, got 'cosine'",
        f"{f}:16: segment 3 (curve): 'radius' must be > 0 m, got -400.0",
        f"{f}:17: segment 3 (curve): 'direction' must be one of left, right, got 'up'",
        f"{f}:18: segment 3 (curve): 'cant' unit 'inch' in '95 inch' is not a length unit",
        f"{f}:21: segment 4: 'type' must be one of straight, transition, curve, got 'strait'",
        f"{f}:28: segment 6 (transition): missing 'length'",
        f"{f}:28: segment 6 (transition): follows another transition (segment 5)",
        f"{f}:30: segment 6 (transition): unknown key 'lenght'",
        f"{f}:32: irregularity (sinusoid): missing 'wavelength'",
    ]
    for line in expected:
        assert line in msg, line
    assert len(err.problems) == len(expected)
    assert [p.split(": ")[0] for p in err.problems] == [e.split(": ")[0] for e in expected]
    assert msg.startswith(f"invalid track input {f} ({len(expected)} problems)")


def test_adjacent_transitions_in_file(tmp_path):
    f = tmp_path / "tt.toml"
    f.write_text('[[segment]]\ntype = "transition"\nlength = 10\n\n'
                 '[[segment]]\ntype = "transition"\nlength = 10\n')
    with pytest.raises(TrackError, match=r"tt\.toml:5: segment 2 \(transition\): follows another transition"):
        load_track(f)


def test_toml_syntax_error_names_line(tmp_path):
    f = tmp_path / "syntax.toml"
    f.write_text('[[segment]]\ntype = "straight"\nlength = = 5\n')
    with pytest.raises(TrackError, match=r"syntax\.toml:3: not valid TOML"):
        load_track(f)


def test_bad_irregularities_from_dict(tmp_path):
    seg = [{"type": "straight", "length": 10}]
    (tmp_path / "bad.csv").write_text("0,0\n5,x\n")
    cases = [
        ({"type": "spectrum", "spectrum": "fra4"}, "unknown spectrum 'fra4'"),
        ({"type": "spectrum", "spectrum": "fra5", "seed": -1}, "'seed' must be a non-negative integer"),
        ({"type": "spectrum", "spectrum": "fra5", "wavelength_min": 200},
         "'wavelength_min' (200.0) must be <"),
        ({"type": "csv", "file": "bad.csv"}, f"{tmp_path / 'bad.csv'}:2: not a number"),
        ({"type": "csv"}, "'file' must be the path of a CSV file"),
        ({"type": "wavy"}, "'type' must be one of none, sinusoid, csv, spectrum"),
        ({"type": "sinusoid", "amplitude": "1 mm", "wavelength": "20 km/h"}, "not a length unit"),
    ]
    for irr, text in cases:
        with pytest.raises(TrackError) as info:
            track_from_dict({"segment": seg, "irregularity": irr}, source=str(tmp_path / "x.toml"))
        assert text in str(info.value), (irr, str(info.value))
        assert "irregularity" in str(info.value)


def test_no_segments_and_bad_values():
    with pytest.raises(TrackError, match=r"<dict>: track: no \[\[segment\]\] given"):
        track_from_dict({})
    with pytest.raises(TrackError, match="'length' must be finite"):
        track_from_dict({"segment": [{"type": "straight", "length": float("nan")}]})
    with pytest.raises(TrackError, match="must be a number or a string with a unit, got bool"):
        track_from_dict({"segment": [{"type": "straight", "length": True}]})
    with pytest.raises(TrackError, match="is not a number with a unit"):
        track_from_dict({"segment": [{"type": "straight", "length": "ten m"}]})
