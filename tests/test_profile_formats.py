"""Profiles in the formats of contact software (express.rail.profile_formats): SIMPACK
``.prr``/``.prw`` and MiniProf ``.ban``/``.whl`` as CONTACT reads them.

``tests/data/S1002.prw``, ``60E1.prr``, ``S1002.whl`` and ``60E1.ban`` have the layout of
CONTACT's example files (github.com/eve70a/CONTACT, ``examples/MBench_S1002_v3.prw``,
``MBench_UIC60_v3.prr``, ``MBench_UIC60_v3.ban``; header of each file) and hold every
fifth point of the shipped S1002 and 60E1 profiles, written in each format's own axes
(y toward the flange with ``mirror.y = 1``, z down, metres or mm, X toward the flange
and Y up for MiniProf): reading them must give the shipped points back, and the same
contact geometry and conicity as the same points in a two-column file.
"""

from __future__ import annotations

import json
from importlib import resources
from pathlib import Path

import numpy as np
import pytest

from express.base.diagnostics import ModelError
from express.io.toml_model import parse_toml_model
from express.rail.conicity import equivalent_conicity
from express.rail.contact_geometry import ContactSetup, contact_geometry
from express.rail.profile_formats import parse_profile_format, profile_format
from express.rail.profile_formats import read_profile
from express.rail.profiles import standard_profile

DATA = Path(__file__).resolve().parent / "data"
Y = np.arange(-10.0, 10.001, 0.1) * 1e-3
AMPLITUDES = np.array([1.0, 2.0, 3.0, 4.0, 5.0, 6.0]) * 1e-3


def two_column_twin(folder: Path, name: str) -> Path:
    """Every fifth point of the shipped file (the points of the test data), two columns."""
    text = resources.files("express").joinpath("data", "profiles", f"{name}.csv").read_text(encoding="utf-8")
    rows = [line for line in text.splitlines() if line and not line.startswith(("#", "y_"))]
    kept = rows[::5] if (len(rows) - 1) % 5 == 0 else [*rows[::5], rows[-1]]
    path = folder / f"{name}_twin.csv"
    path.write_text("y_mm,z_mm\n" + "\n".join(kept) + "\n", encoding="utf-8")
    return path


@pytest.mark.parametrize("file, kind, standard, form", ids=["prw", "prr", "whl", "ban"], argvalues=[
    ("S1002.prw", "wheel", "S1002", "simpack"),
    ("60E1.prr", "rail", "60E1", "simpack"),
    ("S1002.whl", "wheel", "S1002", "miniprof"),
    ("60E1.ban", "rail", "60E1", "miniprof"),
])
def test_files_give_the_shipped_points_in_the_side_frame(file, kind, standard, form):
    assert profile_format(DATA / file) == (form, kind)
    profile, shipped = read_profile(DATA / file, kind), standard_profile(standard)
    assert profile.kind == kind and profile.name == Path(file).stem
    assert np.all(np.diff(profile.y) > 0) and profile.y[0] == shipped.y[0] and profile.y[-1] == pytest.approx(shipped.y[-1])
    assert np.isin(np.round(profile.y, 12), np.round(shipped.y, 12)).all()  # points of the shipped file
    assert np.abs(profile.z - np.interp(profile.y, shipped.y, shipped.z)).max() < 1e-12  # [m], z up
    if kind == "wheel":  # flange at negative y, below the taping line; the field side rises
        assert profile.y[np.argmin(profile.z)] == pytest.approx(-0.0549, abs=1e-3) and profile.z.min() < -0.0279
        assert profile.z[-1] == pytest.approx(0.0026357, abs=1e-6)


@pytest.mark.parametrize("wheel, rail", [("S1002.prw", "60E1.prr"), ("S1002.whl", "60E1.ban"), ("S1002.prw", "60E1.ban")])
def test_round_trip_same_geometry_and_conicity_as_two_columns(tmp_path, wheel, rail):
    setup = ContactSetup(inclination=1.0 / 40.0)
    formats = contact_geometry(read_profile(DATA / wheel, "wheel"), read_profile(DATA / rail, "rail"), Y, setup)
    columns = contact_geometry(read_profile(two_column_twin(tmp_path, "S1002"), "wheel"),
                               read_profile(two_column_twin(tmp_path, "60E1"), "rail"), Y, setup)
    for name in ("delta_r", "roll", "contact_angle", "radius", "wheel_position", "rail_position"):
        assert np.abs(getattr(formats, name) - getattr(columns, name)).max() < 1e-12, name
    assert [(j.side, j.y_before) for j in formats.jumps] == [(j.side, j.y_before) for j in columns.jumps]
    got, expected = (equivalent_conicity(t.y, t.delta_r, AMPLITUDES) for t in (formats, columns))
    assert got == pytest.approx(expected, abs=1e-10)
    # and close to the full shipped pair (every point): the thinning costs < 0.005 in tan(gamma_e)
    full = contact_geometry(standard_profile("S1002"), standard_profile("60E1"), Y, setup)
    assert got == pytest.approx(equivalent_conicity(full.y, full.delta_r, AMPLITUDES), abs=5e-3)


def miniprof_variant(text: str, flip_x: bool, flip_y: bool) -> str:
    head, _, body = text.partition("\n\n")
    rows = []
    for line in body.splitlines():
        x, y = (float(v) for v in line.split())
        rows.append(f"{-x if flip_x else x:.9f} {-y if flip_y else y:.9f}")
    return head + "\n\n" + "\n".join(rows) + "\n"


@pytest.mark.parametrize("flip_x, flip_y", [(False, False), (True, False), (False, True), (True, True)])
def test_miniprof_wheel_side_and_vertical_direction_are_found(flip_x, flip_y):
    # MiniProf fixes neither: the flange tells the side, the side faces the direction of Y
    text = miniprof_variant((DATA / "S1002.whl").read_text(encoding="utf-8"), flip_x, flip_y)
    profile = parse_profile_format(text, "wheel", file="w.whl")
    shipped = standard_profile("S1002")
    assert np.abs(profile.z - np.interp(profile.y, shipped.y, shipped.z)).max() < 1e-12


def test_simpack_settings_shift_bound_and_units(tmp_path):
    text = (DATA / "60E1.prr").read_text(encoding="utf-8")
    shifted = text.replace("    inversion      =  0", "    inversion      =  0\n    shift.y = 0.001\n"
                           "    bound.y.min = -0.030\n    bound.y.max = 0.035\n    units.len.f = 1")
    profile = parse_profile_format(shifted, "rail", file="r.prr")
    base = read_profile(DATA / "60E1.prr", "rail")
    assert profile.y[0] >= -0.030 and profile.y[-1] <= 0.035
    assert np.interp(0.011, profile.y, profile.z) == pytest.approx(np.interp(0.010, base.y, base.z), abs=1e-12)


def test_model_file_keys_accept_the_formats(tmp_path):
    from test_profile_contact import WHEELSET

    for name in ("S1002.prw", "60E1.prr", "S1002.whl", "60E1.ban"):
        (tmp_path / name).write_bytes((DATA / name).read_bytes())
    twins = [two_column_twin(tmp_path, "S1002").name, two_column_twin(tmp_path, "60E1").name]
    values = []
    for wheel, rail in [("S1002.prw", "60E1.prr"), ("S1002.whl", "60E1.ban"), tuple(twins)]:
        text = WHEELSET.replace('wheel = "S1002", rail = "60E1"', f'wheel = "{wheel}", rail = "{rail}"')
        model = parse_toml_model(text, str(tmp_path / "wheelset.toml"))
        values.append(model.values()["Gamma_e"])
    assert values[0] == pytest.approx(values[2], abs=1e-10) and values[1] == pytest.approx(values[2], abs=1e-10)
    assert values[0] == pytest.approx(0.177, abs=1e-3)  # regression guard: S1002 on 60E1 1:40 at 3 mm (docs/contact.md)


def test_cli_reads_the_formats_like_two_columns(tmp_path, capsys):
    from express.cli import main

    twins = [str(two_column_twin(tmp_path, "S1002")), str(two_column_twin(tmp_path, "60E1"))]
    results = []
    for pair in ([str(DATA / "S1002.prw"), str(DATA / "60E1.prr")], [str(DATA / "S1002.whl"), str(DATA / "60E1.ban")], twins):
        out = tmp_path / "t.csv"
        assert main(["contact-geometry", *pair, "--y-range=-8:8:0.5", "-o", str(out)]) == 0
        capsys.readouterr()
        assert main(["conicity", *pair, "--amplitudes", "1:6:1", "--json"]) == 0
        results.append((out.read_text(), json.loads(capsys.readouterr().out)))
    reference = np.genfromtxt(results[2][0].splitlines(), delimiter=",", skip_header=1)
    for table, conicity in results[:2]:
        assert table.splitlines()[0] == results[2][0].splitlines()[0]
        values = np.genfromtxt(table.splitlines(), delimiter=",", skip_header=1)
        assert np.allclose(values, reference, rtol=1e-9, atol=1e-12, equal_nan=True)
        # ulp-level differences of the points move the flange jump's interpolation by < 1e-6
        assert conicity["tan_gamma_e"] == pytest.approx(results[2][1]["tan_gamma_e"], abs=1e-6)


# --- bad files ----------------------------------------------------------------------------

PRW = (DATA / "S1002.prw").read_text(encoding="utf-8")
PRR = (DATA / "60E1.prr").read_text(encoding="utf-8")
BAN = (DATA / "60E1.ban").read_text(encoding="utf-8")
LINE_OF = {text: {line: number for number, line in enumerate(text.splitlines(), start=1)} for text in (PRW, PRR, BAN)}
PRW_POINT = "54.719724841\t27.996726463"


def prw_line(text: str) -> int:
    return LINE_OF[PRW][text]


BAD_FILES = [
    ("", "w.prw", "wheel", ["w.prw: no profile points"]),
    ("! only comments\n", "w.prw", "wheel", ["w.prw: no profile points"]),
    (PRW.replace(PRW_POINT, "54.719724841"), "w.prw", "wheel", ["w.prw:{n}: expected y, z and an optional weight, found 1 values"]),
    (PRW.replace(PRW_POINT, "54.719724841\tnan"), "w.prw", "wheel", ["w.prw:{n}: point: '54.719724841\\tnan' is not a finite number"]),
    (PRW.replace(PRW_POINT, "54.719724841\t27.9x"), "w.prw", "wheel", ["w.prw:{n}: point: '54.719724841\\t27.9x' is not a number"]),
    (PRW.replace(PRW_POINT, "10.0\t27.996726463"), "w.prw", "wheel", ["w.prw:", "lateral coordinate"]),
    (PRW.replace("type          =  1", "type          =  0"), "w.prw", "wheel", ["w.prw: type: header type = 0 (rail) in a wheel profile file"]),
    (PRW.replace("units.len.f    = +1.000000000000000e+03", "units.len.f    = +1.0"), "w.prw", "wheel",
     ["w.prw: units: the profile spans 130 m x", "too large for a wheel (the values look like mm)"]),
    (PRW.replace("rotate         = +0.000000000000000e+00", "rotate = 0.01"), "w.prw", "wheel", ["w.prw: rotate: a rotated profile is not supported"]),
    (PRW.replace("mirror.y       =  1", "mirror.y       =  0"), "w.prw", "wheel", ["w.prw: mirror.y: the flange (lowest point, y = 55.2"]),
    (PRW.replace("mirror.y       =  1", "mirror.y       =  2"), "w.prw", "wheel", ["w.prw:{m}: mirror.y: must be 0 (no mirroring) or 1"]),
    (PRW.replace("    point.end\n  spline.end\n", ""), "w.prw", "wheel", ["w.prw:", "the file ends inside the point section"]),
    (PRW.replace("  header.begin", "  heading.begin"), "w.prw", "wheel", ["w.prw:", "heading.begin: unknown section"]),
    (PRW, "w.prr", "rail", ["w.prr: type: header type = 1 (wheel) in a rail profile file"]),
    (PRR, "r.prr", "wheel", ["r.prr: a .prr file holds a rail profile, given as the wheel"]),
    (BAN.replace("ColumnDef=X,Y,A", "ColumnDef=X,Y"), "r.ban", "rail", ["r.ban:", "expected 2 columns (X,Y), found 3 numbers"]),
    (BAN.replace("ColumnDef=X,Y,A", "ColumnDef=A,C"), "r.ban", "rail", ["r.ban: ColumnDef: 'A,C': expected letters"]),
    (BAN.replace("XOffset=", "XOffset=abc"), "r.ban", "rail", ["r.ban: XOffset: expected a number [mm], found 'abc'"]),
    (BAN + "Gauge=1435\n", "r.ban", "rail", ["r.ban:", "Gauge: a header line after the points"]),
    (BAN.replace("\n\n", "\n\n0.0, nan, 0.0\n", 1), "r.ban", "rail", ["r.ban:", "point: '0.0 nan 0.0' is not a finite number"]),
]
BAD_IDS = ["empty", "comments-only", "one-column", "nan", "not-a-number", "non-monotonic", "type-mismatch", "wrong-unit",
           "rotated", "left-side-wheel", "mirror-value", "unclosed-section", "unknown-section", "prw-as-prr",
           "rail-as-wheel", "wrong-columns", "bad-columndef", "bad-offset", "header-after-points", "miniprof-nan"]


@pytest.mark.parametrize("text, file, kind, expected", BAD_FILES, ids=BAD_IDS)
def test_bad_files_report_every_problem_with_file_and_line(text, file, kind, expected):
    with pytest.raises(ModelError) as info:
        parse_profile_format(text, kind, file=file)
    got = [str(p) for p in info.value.problems]
    first = expected[0].format(n=prw_line(PRW_POINT),
                               m=next((i for i, line in enumerate(text.splitlines(), 1) if line.startswith("    mirror.y")), 0))
    assert got[0].startswith(first), got
    for part in expected[1:]:
        assert part in got[0], got


def test_every_problem_of_a_file_at_once():
    text = PRW.replace(PRW_POINT, "54.719724841\tnan").replace("type          =  1", "type          =  0").replace(
        "rotate         = +0.000000000000000e+00", "rotate = 0.5")
    with pytest.raises(ModelError) as info:
        parse_profile_format(text, "wheel", file="w.prw")
    got = " | ".join(str(p) for p in info.value.problems)
    assert f"w.prw:{prw_line(PRW_POINT)}: point:" in got and "header type = 0" in got and "rotated profile" in got


def test_units_asked_for_must_agree_with_the_file():
    with pytest.raises(ModelError, match="the file gives its points in mm, but m was asked for"):
        parse_profile_format(PRW, "wheel", file="w.prw", units="m")
    assert parse_profile_format(PRR, "rail", file="r.prr", units="m").kind == "rail"  # SIMPACK's default: metres


@pytest.mark.parametrize("command", [["contact-geometry"], ["conicity"]])
def test_cli_bad_format_file_exit_2_nothing_written(tmp_path, capsys, command):
    from express.cli import main

    bad = tmp_path / "w.prw"
    bad.write_text(PRW.replace(PRW_POINT, "54.719724841\tnan"), encoding="utf-8")
    out = tmp_path / "t.csv"
    assert main([*command, str(bad), str(DATA / "60E1.prr"), "-o", str(out)]) == 2
    assert capsys.readouterr().err.splitlines() == [
        f"error: {bad}:{prw_line(PRW_POINT)}: point: '54.719724841\\tnan' is not a finite number"]
    assert not out.exists()


def test_model_with_a_bad_format_file_exits_2_naming_both_files(tmp_path, capsys):
    from express.cli import main
    from test_profile_contact import WHEELSET

    (tmp_path / "bad.prw").write_text(PRW.replace(PRW_POINT, "54.719724841\tnan"), encoding="utf-8")
    model = tmp_path / "m.toml"
    model.write_text(WHEELSET.replace('wheel = "S1002"', 'wheel = "bad.prw"'), encoding="utf-8")
    assert main(["eigen", str(model), "--speed", "100"]) == 2
    err = capsys.readouterr().err
    assert f"{model}:" in err and f"{tmp_path / 'bad.prw'}:{prw_line(PRW_POINT)}:" in err and "not a finite number" in err


# --- fuzzing: mutated files end cleanly (status 0, 1 or 2, no traceback, nothing written when refused)


def _fuzz_run(folder: Path, argv: list) -> None:
    from fuzz_support import assert_untouched, check, snapshot

    target = folder / "out.csv"
    target.write_text("an earlier result\n")
    before = snapshot(folder)
    status, _, _ = check([*argv, "-o", target])
    if status != 0:
        assert_untouched(before, folder, argv)


@pytest.mark.slow
@pytest.mark.parametrize("name, command", [("S1002.prw", ["conicity", "{path}", "60E1"]),
                                           ("60E1.ban", ["contact-geometry", "S1002", "{path}", "--y-range=-8:8:0.5"])])
def test_mutated_format_files_end_cleanly(tmp_path_factory, name, command):
    from hypothesis import given
    from hypothesis import strategies as st

    from fuzz_support import fuzz, mutated

    text = (DATA / name).read_text(encoding="utf-8")

    @fuzz(15)
    @given(data=st.data())
    def run(data):
        folder = tmp_path_factory.mktemp("format")
        path = folder / name
        path.write_text(data.draw(mutated(text), label=name), encoding="utf-8")
        _fuzz_run(folder, [str(path) if part == "{path}" else part for part in command])

    run()
