"""Tests of express.rail.track.reader: track files (TOML), CSV profiles, every problem with its line."""

from __future__ import annotations

import math
import os
from pathlib import Path

import numpy as np
import pytest

from express.base.diagnostics import InputError, ModelError
from express.rail.track import (
    EXCERPT_CHARS,
    FRA_CLASS_5,
    MAX_ROW_PROBLEMS,
    Harmonics,
    ProfileIrregularity,
    SinusoidIrregularity,
    Transition,
    load_track,
    paper_curve,
    read_profile_csv,
    track_from_dict,
)
from express.rail.track import reader as track_reader

EXAMPLES = Path(__file__).resolve().parents[1] / "examples" / "tracks"


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
    with pytest.raises(ModelError) as info:
        read_profile_csv(f)
    problems = info.value.problems
    assert [str(p).split(": ")[0] for p in problems] == [f"{f}:3", f"{f}:4", f"{f}:6"]
    assert [p.item for p in problems] == ["profile"] * 3
    assert "not a number" in problems[0].message
    assert "expected 2 columns (distance, yR), got 3" in problems[1].message
    assert "values must be finite" in problems[2].message
    assert str(f) in str(info.value)


def test_read_profile_csv_order_and_size(tmp_path):
    f = tmp_path / "order.csv"
    f.write_text("0,0\n10,0\n10,0.001\n")
    with pytest.raises(ModelError, match=r"order\.csv:3: profile: distance 10\.0 is not greater than 10\.0 on line 2"):
        read_profile_csv(f)
    g = tmp_path / "short.csv"
    g.write_text("s,y\n0,0\n")
    with pytest.raises(ModelError, match="at least two data rows"):
        read_profile_csv(g)
    with pytest.raises(ModelError, match="cannot read"):
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
    with pytest.raises(ModelError) as info:
        load_track(f)
    err = info.value
    assert isinstance(err, ValueError) and isinstance(err, InputError)
    msg = str(err)
    expected = [  # in line order
        # km/s is a speed unit (express.base.units): refused by the documented range instead
        f"{f}:1: track: 'speed' must be > 0 and at most 1000 km/h (277.8 m/s), got '120 km/s'",
        f"{f}:2: track: unknown key 'colour'",
        f"{f}:11: segment 2 (transition): 'shape' must be one of linear, sine, got 'cosine'",
        f"{f}:16: segment 3 (curve): 'radius' must be > 0 m, got -400.0",
        f"{f}:17: segment 3 (curve): 'direction' must be one of left, right, got 'up'",
        # 95 inch = 2.413 m is a length: refused by the cant limit, MAX_CANT
        f"{f}:18: segment 3 (curve): 'cant' must be at most 0.5 m in size, got 2.413 m",
        f"{f}:21: segment 4: 'type' must be one of straight, transition, curve, got 'strait'",
        f"{f}:28: segment 6 (transition): missing 'length'",
        f"{f}:28: segment 6 (transition): follows another transition (segment 5)",
        f"{f}:30: segment 6 (transition): unknown key 'lenght'",
        f"{f}:32: irregularity (sinusoid): missing 'wavelength'",
    ]
    for line in expected:
        assert line in msg, line
    assert len(err.problems) == len(expected)
    assert [str(p).split(": ")[0] for p in err.problems] == [e.split(": ")[0] for e in expected]
    # one line per problem, nothing else
    assert msg.splitlines() == [str(p) for p in err.problems] == err.lines()
    assert all(p.file == str(f) for p in err.problems)


def test_adjacent_transitions_in_file(tmp_path):
    f = tmp_path / "tt.toml"
    f.write_text('[[segment]]\ntype = "transition"\nlength = 10\n\n'
                 '[[segment]]\ntype = "transition"\nlength = 10\n')
    with pytest.raises(ModelError, match=r"tt\.toml:5: segment 2 \(transition\): follows another transition"):
        load_track(f)


def test_toml_syntax_error_names_line(tmp_path):
    f = tmp_path / "syntax.toml"
    f.write_text('[[segment]]\ntype = "straight"\nlength = = 5\n')
    with pytest.raises(ModelError, match=r"syntax\.toml:3: TOML: not valid TOML"):
        load_track(f)


def test_bad_irregularities_from_dict(tmp_path):
    seg = [{"type": "straight", "length": 10}]
    (tmp_path / "bad.csv").write_text("0,0\n5,x\n")
    cases = [
        ({"type": "spectrum", "spectrum": "fra7"}, "unknown spectrum 'fra7'"),
        ({"type": "spectrum", "spectrum": "fra5", "seed": -1}, "'seed' must be a non-negative integer"),
        ({"type": "spectrum", "spectrum": "fra5", "wavelength_min": 200},
         "'wavelength_min' (200.0) must be <"),
        ({"type": "csv", "file": "bad.csv"}, f"{tmp_path / 'bad.csv'}:2: irregularity (csv): not a number"),
        ({"type": "csv"}, "'file' must be the path of a CSV file"),
        ({"type": "wavy"}, "'type' must be one of none, sinusoid, csv, points, spectrum"),
        ({"type": "sinusoid", "amplitude": "1 mm", "wavelength": "20 km/h"},
         "'wavelength': unit km/h is a speed (m/s), expected a length (m)"),
    ]
    for irr, text in cases:
        with pytest.raises(ModelError) as info:
            track_from_dict({"segment": seg, "irregularity": irr}, source=str(tmp_path / "x.toml"))
        assert text in str(info.value), (irr, str(info.value))
        assert "irregularity" in str(info.value)


def test_no_segments_and_bad_values():
    with pytest.raises(ModelError, match=r"<dict>: track: no \[\[segment\]\] given"):
        track_from_dict({})
    with pytest.raises(ModelError, match="'length' must be finite"):
        track_from_dict({"segment": [{"type": "straight", "length": float("nan")}]})
    with pytest.raises(ModelError, match="must be a number or a string with a unit, got bool"):
        track_from_dict({"segment": [{"type": "straight", "length": True}]})
    with pytest.raises(ModelError, match="is not a number with a unit"):
        track_from_dict({"segment": [{"type": "straight", "length": "ten m"}]})


# --- every problem at once, with its line -----------------------------------------------------

SEVERAL = """\
name = 7
speed = "33.3 m/s"

[[segment]]
type = "straight"
length = "50 kg"

[[segment]]
type = "curve"
length = "1e300 m"
radius = "400 m"
direction = "left"
cant = 95

[irregularity]
type = "spectrum"
spectrum = "erri_low"
seed = true
wavelength_min = "0.1 m"
period = "1000 km"
"""


def test_several_problems_reported_at_once_with_lines(tmp_path):
    f = tmp_path / "several.toml"
    f.write_text(SEVERAL)
    with pytest.raises(ModelError) as info:
        load_track(f)
    lines = info.value.lines()
    assert lines == [
        f"{f}:1: track: 'name' must be a string",
        f"{f}:6: segment 1 (straight): 'length': unit kg is a mass (kg), expected a length (m)",
        f"{f}:10: segment 2 (curve): 'length' must be at most 1e+06 m, got 1e+300",
        f"{f}:13: segment 2 (curve): 'cant' must be at most 0.5 m in size, got 95.0 m (millimetres written as metres?)",
        f"{f}:18: irregularity (spectrum): 'seed' must be a non-negative integer, got True",
        f"{f}:20: irregularity (spectrum): 'period' (1e+06 m) with 'wavelength_min' (0.1 m) and 'wavelength_max' "
        f"(120 m) needs 9.99e+06 harmonics, more than the limit 200000: shorten the period or raise wavelength_min",
    ]
    assert [(p.file, p.line) for p in info.value.problems] == [(str(f), n) for n in (1, 6, 10, 13, 18, 20)]


def test_huge_spectrum_in_a_file_is_refused_fast(tmp_path, monkeypatch):
    # issue 17: "a track spectrum with period 1e6 m and shortest wavelength 0.1 m exhausts memory"
    f = tmp_path / "huge.toml"
    f.write_text('[[segment]]\ntype = "straight"\nlength = 100\n\n[irregularity]\ntype = "spectrum"\n'
                 'spectrum = "fra5"\nperiod = 1e6\nwavelength_min = 0.1\n')
    monkeypatch.setattr(Harmonics, "draw", lambda *a, **k: pytest.fail("harmonics drawn before the check"))
    with pytest.raises(ModelError, match=r"huge\.toml:8: irregularity \(spectrum\): 'period' .* more than the limit"):
        load_track(f)


def test_total_length_and_speed_limits_in_a_file():
    segs = [{"type": "straight", "length": "600 km"}, {"type": "straight", "length": "600 km"}]
    with pytest.raises(ModelError, match=r"<dict>: track: the segments are 1\.2e\+06 m long, more than the limit 1e\+06 m"):
        track_from_dict({"segment": segs})
    ok = [{"type": "straight", "length": 10}]
    for speed, good in (("1000 km/h", True), ("1001 km/h", False), (0, False), (-5, False), ("30 m", False)):
        if good:
            assert track_from_dict({"segment": ok, "speed": speed}).speed == pytest.approx(1000 / 3.6)
        else:
            with pytest.raises(ModelError, match="<dict>: track: 'speed'"):
                track_from_dict({"segment": ok, "speed": speed})


@pytest.mark.parametrize(
    "segment, text",
    [
        ({"type": "curve", "length": 10, "radius": "400 m", "direction": "left", "cant": "95 kg"},
         "'cant': unit kg is a mass (kg), expected a length (m)"),
        ({"type": "curve", "length": 10, "radius": "0.4 km/h", "direction": "left"}, "expected a length"),
        ({"type": "curve", "length": 10, "radius": 400}, "missing 'direction' (one of left, right)"),
        ({"type": "transition", "length": "5 m^400"}, "'length': exponent 400"),
        ({"type": "straight", "length": "1e999 m"}, "out of range"),
        ({"type": "straight", "length": 10**400}, "'length' must be finite, got a number of 401 digits"),
        ({"type": "straight", "length": [1, 2]}, "must be a number or a string with a unit, got list"),
        ({"type": "straight"}, "missing 'length'"),
        ({"length": 10}, "missing 'type' (one of straight, transition, curve)"),
    ],
)
def test_segment_value_mistakes(segment, text):
    with pytest.raises(ModelError) as info:
        track_from_dict({"segment": [segment]})
    assert len(info.value.problems) == 1
    assert text in str(info.value)


def test_bare_number_strings_are_si():
    t = track_from_dict({"segment": [{"type": "curve", "length": "100", "radius": "400", "direction": "right",
                                      "cant": "0.1"}]})
    assert t.curvature(50.0) == pytest.approx(-1 / 400) and t.cant(50.0) == pytest.approx(-0.1)


# --- CSV: bounded messages and files -----------------------------------------------------------


def test_unparsable_csv_quotes_one_short_excerpt(tmp_path):
    # issue 17: a file that is not a profile is not echoed line by line in the error
    secret = "root:x:0:0:root:/root:/bin/bash" + "#" * 200
    f = tmp_path / "notes.csv"
    f.write_text("\n".join(f"{secret}-{i}" for i in range(500)))
    with pytest.raises(ModelError) as info:
        read_profile_csv(f)
    problems = info.value.problems
    assert len(problems) == MAX_ROW_PROBLEMS + 1
    assert [p.line for p in problems[:-1]] == list(range(2, MAX_ROW_PROBLEMS + 2))  # line 1 is a header
    assert problems[-1].message == f"499 bad rows in all, the first {MAX_ROW_PROBLEMS} listed"
    quoted = [p for p in problems if "root" in p.message]
    assert len(quoted) == 1 and quoted[0].line == 2
    excerpt = quoted[0].message.split(": ", 1)[1]
    assert len(excerpt) <= EXCERPT_CHARS + 2 and excerpt.endswith("...'")  # quotes around it
    assert len(str(info.value)) < 3000


def test_excerpt_is_printable_and_short(tmp_path):
    f = tmp_path / "ctrl.csv"
    f.write_text("s,y\n0,0\n1,\x1b[31mred\x07\n")
    with pytest.raises(ModelError) as info:
        read_profile_csv(f)
    (problem,) = info.value.problems
    assert problem.message == "not a number: '1,?[31mred?'"


@pytest.mark.parametrize(
    "content, text",
    [
        (b"\x89PNG\r\n\x1a\n\x00\x00\x00\rIHDR", "not a text file (it holds NUL bytes)"),
        (b"0,0\n1,\xff\xfe\n", "not a UTF-8 text file (byte 7 cannot be decoded)"),
    ],
)
def test_binary_csv_is_one_problem(tmp_path, content, text):
    f = tmp_path / "data.csv"
    f.write_bytes(content)
    with pytest.raises(ModelError) as info:
        read_profile_csv(f)
    assert info.value.lines() == [f"{f}: profile: {text}"]


def test_special_and_large_files_are_refused(tmp_path, monkeypatch):
    with pytest.raises(ModelError, match="profile: not a regular file"):
        read_profile_csv(tmp_path)
    if hasattr(os, "mkfifo"):
        fifo = tmp_path / "pipe.toml"
        os.mkfifo(fifo)
        with pytest.raises(ModelError, match=r"pipe\.toml: track: not a regular file"):
            load_track(fifo)  # would block on open if it were read
    big = tmp_path / "big.csv"
    big.write_text("0,0\n10,0.001\n" * 10)
    monkeypatch.setattr(track_reader, "MAX_PROFILE_BYTES", 100)
    with pytest.raises(ModelError, match=r"big\.csv: profile: the file has 130 bytes, more than the limit 100"):
        read_profile_csv(big)
    monkeypatch.setattr(track_reader, "MAX_TRACK_FILE_BYTES", 10)
    with pytest.raises(ModelError, match="more than the limit 10"):
        load_track(EXAMPLES / "paper_curve.toml")


def test_csv_in_millimetres_is_caught(tmp_path):
    f = tmp_path / "mm.csv"
    f.write_text("s_m,yR_mm\n0,0\n10,2.5\n20,-1.0\n")
    with pytest.raises(ModelError, match=r"mm\.csv: profile: \|yr\| reaches 2\.5 m, more than 0\.1 m"):
        read_profile_csv(f)


def test_csv_problems_from_a_track_file_point_into_the_csv(tmp_path):
    (tmp_path / "p.csv").write_text("s,y\n0,0\n10,zz\n20,0.001,3\n")
    f = tmp_path / "t.toml"
    f.write_text('[[segment]]\ntype = "straight"\nlength = 30\n\n[irregularity]\ntype = "csv"\nfile = "p.csv"\n'
                 'colour = "red"\n')
    with pytest.raises(ModelError) as info:
        load_track(f)
    csv_path = str(tmp_path / "p.csv")
    assert info.value.lines() == [  # the track file's problems first, then the CSV's in its order
        f"{f}:8: irregularity (csv): unknown key 'colour' (allowed: file, type)",
        f"{csv_path}:3: irregularity (csv): not a number: '10,zz'",
        f"{csv_path}:4: irregularity (csv): expected 2 columns (distance, yR), got 3",
    ]


def test_profile_read_is_read_only_and_exact(tmp_path):
    f = tmp_path / "p.csv"
    f.write_text("0;0\n0.25;1e-3\n0.5;-2e-3\n")
    irr = read_profile_csv(f)
    assert isinstance(irr, ProfileIrregularity) and irr.source == str(f)
    with pytest.raises(ValueError):
        irr.distance[0] = 5.0
    assert irr(0.375) == pytest.approx(-0.5e-3) and math.isclose(irr.rate(0.3), -12e-3)
    np.testing.assert_array_equal(irr.yr, [0.0, 1e-3, -2e-3])


def test_track_file_with_a_byte_order_mark(tmp_path):
    f = tmp_path / "bom.toml"
    f.write_bytes(b"\xef\xbb\xbf" + (EXAMPLES / "paper_curve.toml").read_bytes())
    assert load_track(f) == paper_curve()
