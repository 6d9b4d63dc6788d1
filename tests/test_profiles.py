"""Wheel and rail profiles (express.rail.profiles): the S1002 and 60E1 definitions, the
shipped data files, reading, validation (every problem with file:line) and smoothing."""

from __future__ import annotations

import math
from importlib import resources

import numpy as np
import pytest

from express.base.diagnostics import ModelError
from express.rail.profile_formats import read_profile
from express.rail.profiles import (
    _S1002_BREAKS,
    _UIC60_BREAKS,
    Profile,
    parse_inclination,
    parse_profile,
    s1002_height,
    smooth_profile,
    standard_profile,
    standard_profile_text,
    uic60_height,
)


@pytest.mark.parametrize("name, filename", [("S1002", "S1002.csv"), ("60E1", "60E1.csv")])
def test_shipped_files_are_generated_from_the_definitions(name, filename):
    shipped = resources.files("express").joinpath("data").joinpath("profiles").joinpath(filename).read_text()
    assert shipped == standard_profile_text(name)
    assert standard_profile_text(name) == standard_profile_text(name)  # deterministic


def test_s1002_dimensions():
    # taping line at s = 0, flange height 28 mm (flange tip at s = -55)
    assert s1002_height(np.array([0.0]))[0] == pytest.approx(0.0, abs=1e-12)
    assert s1002_height(np.array([-55.0]))[0] == pytest.approx(28.0, abs=1e-9)
    # flange thickness 32.5 mm, measured 10 mm above the taping line from the flange back (-70)
    assert s1002_height(np.array([-70.0 + 32.5]))[0] == pytest.approx(10.0, abs=1e-3)
    # the field-side straight line falls 1:15
    a, b = s1002_height(np.array([40.0, 50.0]))
    assert (a - b) / 10.0 == pytest.approx(1 / 15, rel=1e-6)
    # the flange face (section E) is 70 degrees steep
    f = s1002_height(np.array([-39.2, -39.0]))
    assert math.degrees(math.atan((f[0] - f[1]) / 0.2)) == pytest.approx(70.0, abs=0.01)


@pytest.mark.parametrize("s", _S1002_BREAKS[1:-1])
def test_s1002_sections_join(s):
    """The published coefficients are entered right: the sections meet in value and slope."""
    e, h = 1e-9, 1e-4
    left, right = s1002_height(np.array([s - e, s + e]))
    assert left == pytest.approx(right, abs=2e-4)  # mm
    slope_left = (s1002_height(np.array([s - h]))[0] - s1002_height(np.array([s - 2 * h]))[0]) / h
    slope_right = (s1002_height(np.array([s + 2 * h]))[0] - s1002_height(np.array([s + h]))[0]) / h
    assert slope_left == pytest.approx(slope_right, abs=5e-4)


def test_uic60_head():
    assert uic60_height(np.array([0.0]))[0] == 0.0
    # crown radius 300 mm, symmetric
    z = uic60_height(np.array([-5.0, 5.0]))
    assert z[0] == z[1] == pytest.approx(-300 + math.sqrt(300**2 - 25), abs=1e-12)
    # tangent arcs (R300-R80-R13), then the 1:20 flank from the half-width 36 mm; the
    # published breakpoints (3 decimals) leave the R13 end 0.02 degrees off the flank
    for b in _UIC60_BREAKS:
        h = 1e-6
        s1 = (uic60_height(np.array([b]))[0] - uic60_height(np.array([b - h]))[0]) / h
        s2 = (uic60_height(np.array([b + h]))[0] - uic60_height(np.array([b]))[0]) / h
        assert math.degrees(math.atan(s1)) == pytest.approx(math.degrees(math.atan(s2)), abs=0.02)
    z = uic60_height(np.array([36.5, 36.6]))
    assert (z[0] - z[1]) / 0.1 == pytest.approx(20.0)
    with pytest.raises(ValueError):
        uic60_height(np.array([40.0]))


def test_standard_profiles_load():
    wheel = standard_profile("S1002")
    rail = standard_profile("uic60")
    assert (wheel.kind, rail.kind, rail.name) == ("wheel", "rail", "60E1")
    assert wheel.y[0] == pytest.approx(-0.070) and wheel.y[-1] == pytest.approx(0.060)
    # to pm, except where the definition itself jumps (36 nm at s = -26 mm, which side a
    # rounded y falls on) and at the vertical flange back (rounding of y)
    away = (wheel.y > -0.0699) & (np.abs(wheel.y + 0.026) > 1e-9)
    assert np.allclose(wheel.z[away], -s1002_height(wheel.y[away] * 1e3) * 1e-3, atol=2e-12)
    assert np.allclose(rail.z, uic60_height(rail.y * 1e3) * 1e-3, atol=1e-12)
    assert rail.z.max() == 0.0
    with pytest.raises(ValueError, match="unknown standard profile"):
        standard_profile("S1003")


GOOD = "# a wheel\ny_mm,z_mm\n" + "".join(f"{y:.1f},{0.05 * y:.4f}\n" for y in np.arange(-40, 41, 2.0))


def test_read_good_file_in_mm_and_m(tmp_path):
    path = tmp_path / "w.csv"
    path.write_text(GOOD)
    profile = read_profile(path, "wheel")
    assert profile.y[0] == pytest.approx(-0.040) and profile.z[-1] == pytest.approx(0.002)
    assert profile.name == "w" and profile.source == str(path)
    bare = tmp_path / "w.txt"
    bare.write_text("".join(f"{y * 1e-3:.4f} {0.05 * y * 1e-3:.6f}\n" for y in np.arange(-40, 41, 2.0)))
    assert np.allclose(read_profile(bare, "wheel", units="m").y, profile.y)


def test_descending_file_is_reversed():
    text = "y_mm,z_mm\n" + "".join(f"{y:.1f};{0.05 * y:.4f}\n" for y in np.arange(40, -41, -2.0))
    profile = parse_profile(text, "wheel")
    assert np.all(np.diff(profile.y) > 0) and profile.z[0] == pytest.approx(-0.002)


def lines_of(error: ModelError) -> list[str]:
    return [str(problem) for problem in error.problems]


@pytest.mark.parametrize("text, units, expected", [
    ("", None, ["f.csv: no profile points"]),
    ("y,z\n1,2\n", None, ["f.csv:1: header: 'y, z': expected the columns y_mm,z_mm or y_m,z_m",
                         "f.csv: 1 points: a wheel profile needs at least 10"]),
    ("y_mm,z_m\n", None, ["f.csv:1: header: both columns must have the same unit", "f.csv: no profile points"]),
    (GOOD.replace("# a wheel\ny_mm,z_mm\n", ""), None, ["f.csv: units: unknown unit"]),
    (GOOD, "m", ["f.csv: units: the header says mm but m was asked for"]),
    (GOOD.replace("-38.0,-1.9000", "-38.0,abc"), None, ["f.csv:4: vertical coordinate: 'abc' is not a number"]),
    (GOOD.replace("-38.0,-1.9000", "-38.0,nan"), None, ["f.csv:4: vertical coordinate: 'nan' is not a finite number"]),
    (GOOD.replace("-38.0,-1.9000", "-38.0,-1.9,7"), None, ["f.csv:4: expected 2 columns (lateral, vertical), found 3"]),
    (GOOD.replace("-36.0,", "-39.0,"), None, ["f.csv:5: lateral coordinate: y = -39 does not increase (line 4 has y = -38)"]),
    (GOOD.replace("0.0,0.0000", "0.0,0.9000"), None, ["f.csv:23: spike: z = 0.9 mm at y = 0 mm is 0.8 mm off its neighbours"]),
    ("y_mm,z_mm\n-1,0\n0,0\n1,0\n", None, ["f.csv: 3 points: a wheel profile needs at least 10",
                                           "f.csv: units: the profile spans only 2 mm laterally"]),
    (GOOD.replace("y_mm,z_mm", "y_m,z_m"), None, ["f.csv: units: the profile spans 80 m x 4 m, too large for a wheel (the values look like mm)"]),
    (GOOD.replace("y_mm,z_mm\n", "y_mm,z_mm\n-45,-2.25\n").replace("\n" + "".join(f"{y:.1f},{0.05 * y:.4f}\n" for y in np.arange(-40, 41, 2.0) if y > -10), "\n"),
     None, ["f.csv: origin: y = 0 (the taping line) lies outside the profile"]),
])
def test_bad_profiles_report_file_and_line(text, units, expected):
    with pytest.raises(ModelError) as info:
        parse_profile(text, "wheel", file="f.csv", units=units)
    got = lines_of(info.value)
    assert len(got) == len(expected), got
    for line, start in zip(got, expected, strict=True):
        assert line.startswith(start), (line, start)


def test_every_problem_at_once():
    text = GOOD.replace("-38.0,-1.9000", "-38.0,x").replace("-30.0,-1.5000", "-30.0,1,2").replace("\n12.0,", "\n8.0,")
    with pytest.raises(ModelError) as info:
        parse_profile(text, "wheel", file="f.csv")
    got = lines_of(info.value)
    assert [line.split(":")[1] for line in got] == ["4", "8", "29"]


def test_unreadable_file(tmp_path):
    with pytest.raises(ModelError, match="cannot read profile"):
        read_profile(tmp_path / "missing.csv", "rail")


def test_smoothing_removes_noise_and_keeps_cubics():
    y = np.linspace(-0.03, 0.03, 601)
    cubic = 2.0 * y**3 - 0.5 * y**2 + 0.03 * y
    noisy = cubic + 5e-6 * np.random.default_rng(0).standard_normal(len(y))
    smooth = smooth_profile(Profile("p", "wheel", y, noisy), window=3e-3)
    exact = np.interp(smooth.y, y, cubic)
    assert np.std(smooth.z - exact) < 0.35 * np.std(noisy - cubic)
    clean = smooth_profile(Profile("p", "wheel", y, cubic), window=3e-3)
    assert np.allclose(clean.z, np.interp(clean.y, y, cubic), atol=1e-9)


@pytest.mark.parametrize("text, value", [("1:40", 0.025), ("1:20", 0.05), ("1:inf", 0.0), ("0", 0.0), (0.025, 0.025)])
def test_parse_inclination(text, value):
    assert parse_inclination(text) == pytest.approx(value)


@pytest.mark.parametrize("text", ["1:2", "2:40", "abc", "1:x", "-0.1"])
def test_parse_inclination_rejects(text):
    with pytest.raises(ValueError, match="inclination"):
        parse_inclination(text)
