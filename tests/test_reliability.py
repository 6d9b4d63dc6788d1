"""The kinds of abuse of issue 26, each as a class of inputs rather than one file:
angular units, profiles in the wrong role, studies too big to finish, truncated files,
input that used to end as an internal error, and messages a person can read
(``docs/reliability.md`` lists each guarantee with its test here)."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from cli_support import CONVENTIONAL, LEVER, STEERED, assert_input_error, run, run_json
from express.base.units import UnitError, parse_quantity

# ------------------------------------------------------------------ angles are a dimension


@pytest.mark.parametrize(("text", "hertz"), [
    ("20 rad/s", 20 / (2 * math.pi)),  # the issue: ran to 20 Hz
    ("600 rpm", 10.0),  # the issue: ran to 62.8 Hz
    ("360 deg/s", 1.0),
    ("5 Hz", 5.0),
    ("120 1/min", 2.0),  # cycles per minute: no angle in it
    ("3 kHz", 3000.0),
])
def test_a_frequency_in_angular_units_converts_with_its_two_pi(text: str, hertz: float) -> None:
    assert parse_quantity(text, "frequency")[0] == pytest.approx(hertz, rel=1e-15)


@pytest.mark.parametrize("text", ["5 rad^2/s", "5 rad/s^2", "5 1/(rad*s)"])
def test_other_powers_of_the_angle_are_not_frequencies(text: str) -> None:
    with pytest.raises(UnitError):
        parse_quantity(text, "frequency")


@pytest.mark.parametrize("text", ["3 deg", "0.05 rad", "1 arcmin", "2 grade"])
def test_a_pure_number_refuses_an_angle_with_the_tangent_as_a_hint(text: str) -> None:
    with pytest.raises(UnitError, match=r"is an angle.*tan\(") as caught:
        parse_quantity(text, "dimensionless")
    angle = parse_quantity(text, "angle")[0]
    assert f"{math.tan(angle):.6g}" in str(caught.value)


def test_frf_and_ride_fmax_in_rad_s_and_rpm_are_converted_to_hertz(capsys) -> None:
    frf = run_json(capsys, "frf", CONVENTIONAL, "--fmax", "20 rad/s", "--points", "50")
    assert max(frf["frequencies"]) == pytest.approx(20 / (2 * math.pi), rel=1e-12)
    ride = run_json(capsys, "ride", CONVENTIONAL, "--track", "ERRI-low", "--fmax", "600 rpm", "--points", "64")
    assert ride["frequency_band_hz"][1] == pytest.approx(10.0, rel=1e-12)


def test_a_conicity_set_in_degrees_is_refused_with_a_hint(capsys) -> None:
    err = assert_input_error(capsys, "eigen", STEERED, "--set", "Gamma=5 deg", mentions="is an angle")
    assert "tan(5 deg) = 0.0874887" in err


def test_a_classic_models_set_is_checked_by_the_dimension_of_its_use(capsys) -> None:
    assert_input_error(capsys, "convert", LEVER, "--set", "m=5 s", mentions="expected a mass")
    assert_input_error(capsys, "convert", LEVER, "--set", "m=5 kg/m", mentions="expected a mass")


def test_convert_keeps_the_unit_written_in_set(capsys) -> None:
    status, out, err = run(capsys, "convert", LEVER, "--set", "m=5 t", "--set", "kLL=5 kN/mm")
    assert status == 0, err
    assert 'm = { value = 5.0, unit = "t" }' in out
    assert 'kLL = { value = 5.0, unit = "kN/mm" }' in out


# ------------------------------------------------------------------ no internal error from input


@pytest.mark.parametrize(("kind", "words"), [
    ("directory", "not a regular file but a directory"),
    ("/dev/null", "not a regular file but a character device"),
    ("/dev/zero", "not a regular file but a character device"),
    ("fifo", "a FIFO (named pipe) that nobody writes into"),
    ("missing", "file does not exist"),
])
def test_inputs_that_are_not_regular_files_are_refused_by_their_kind(capsys, tmp_path: Path, kind: str, words: str) -> None:
    import os

    path = {"directory": str(tmp_path), "missing": str(tmp_path / "none.toml")}.get(kind, kind)
    if kind == "fifo":
        path = str(tmp_path / "model.exp")
        os.mkfifo(path)
    err = assert_input_error(capsys, "generate", path, mentions=words)
    assert err.count("error:") == 1


def test_a_model_through_a_pipe_is_read(capsys, tmp_path: Path) -> None:
    """``express eigen <(cat model)``: a FIFO with a writer is an input (read once, not cached)."""
    import os
    import threading

    fifo = tmp_path / "model.toml"
    os.mkfifo(fifo)
    writer = threading.Thread(target=lambda: fifo.write_bytes(Path(CONVENTIONAL).read_bytes()))
    writer.start()
    status, out, err = run(capsys, "eigen", fifo)
    writer.join()
    assert status == 0, err
    assert "23 modes" in out


def test_a_cycle_of_601_definitions_names_a_few_and_counts_them(capsys, tmp_path: Path) -> None:
    text = Path(CONVENTIONAL).read_text()
    cycle = "\n".join(f'q{k} = "q{(k + 1) % 601} + 1"' for k in range(601))
    model = tmp_path / "cycle.toml"
    model.write_text(text.replace("[parameters]", "[parameters]\n" + cycle, 1))
    err = assert_input_error(capsys, "eigen", model, mentions="601 definitions in the cycle")
    assert len(err.splitlines()) == 1 and len(err) < 400
    assert "q0 (line" in err and "q5 (line" in err and "q7 (line" not in err


def test_a_chain_of_3000_derived_parameters_is_evaluated_without_recursion(capsys, tmp_path: Path) -> None:
    text = Path(CONVENTIONAL).read_text()
    chain = "\n".join(f'p{k} = "p{k - 1} + 1"' for k in range(1, 3001))
    model = tmp_path / "chain.toml"
    model.write_text(text.replace("[parameters]", "[parameters]\np0 = 0.0\n" + chain, 1))
    status, _, err = run(capsys, "eigen", model, "--set", "p0=1")
    assert status == 0, err


MASS = 'mc = { value = 30000.0, unit = "kg" }'


def test_a_chain_of_9000_definitions_that_feeds_a_mass_is_read(capsys, tmp_path: Path) -> None:
    """Issue 36: the unit inference went backwards from the mass by recursion (exit 70)."""
    text = Path(CONVENTIONAL).read_text()
    assert MASS in text
    chain = "\n".join(f'p{k} = "p{k + 1}*1"' for k in range(9000)) + '\np9000 = { value = 30000.0, unit = "kg" }'
    model = tmp_path / "chain.toml"
    model.write_text(text.replace(MASS, 'mc = "p0"\n' + chain, 1))
    status, out, err = run(capsys, "eigen", model, "--no-cache")
    assert status == 0, err
    assert "23 modes" in out


def test_a_cycle_of_2000_definitions_that_feeds_a_mass_is_refused_as_a_cycle(capsys, tmp_path: Path) -> None:
    text = Path(CONVENTIONAL).read_text()
    cycle = "\n".join(f'q{k} = "q{(k + 1) % 2000}*1"' for k in range(2000))
    model = tmp_path / "cycle.toml"
    model.write_text(text.replace(MASS, 'mc = "q0"\n' + cycle, 1))
    err = assert_input_error(capsys, "eigen", model, "--no-cache", mentions="2000 definitions in the cycle")
    assert len(err.splitlines()) == 1


@pytest.mark.parametrize("content", [b"\x7fELF\x02\x01\x01\x00" + bytes(range(256)) * 4, b'\x80\x81{"format": 1}\n', b"[1, 2]\n",
                                     b"[" * 100_000 + b"\n"])  # nested beyond the JSON parser: was exit 70
def test_a_file_that_is_not_a_checkpoint_is_refused_as_such(capsys, tmp_path: Path, content: bytes) -> None:
    study = tmp_path / "study.toml"
    study.write_text(f'[study]\nmodel = "{STEERED}"\nkind = "grid"\noutputs = ["critical_speed"]\n'
                     "[study.parameters]\nGamma = { values = [0.1, 0.2] }\n")
    (tmp_path / "out.csv.checkpoint.jsonl").write_bytes(content)
    assert_input_error(capsys, "study", study, "-o", tmp_path / "out.csv", "--resume",
                       mentions="not a checkpoint of an EXPRESS study")
    assert not (tmp_path / "out.csv").exists()


def test_a_checkpoint_cut_short_in_its_header_starts_again(capsys, tmp_path: Path) -> None:
    study = tmp_path / "study.toml"
    study.write_text(f'[study]\nmodel = "{STEERED}"\nkind = "grid"\noutputs = ["critical_speed"]\n'
                     "[study.parameters]\nGamma = { values = [0.1, 0.2] }\n")
    (tmp_path / "out.csv.checkpoint.jsonl").write_bytes(b'{"format": "express-study-che')
    status, _, err = run(capsys, "study", study, "-o", tmp_path / "out.csv", "--resume", "--workers", "1")
    assert status == 0, err
    assert len((tmp_path / "out.csv").read_text().splitlines()) == 3


def test_a_missing_optional_package_names_the_extra(capsys, tmp_path: Path, monkeypatch) -> None:
    import importlib.util

    real = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec", lambda name, *a: None if name == "pythonfmu" else real(name, *a))
    assert_input_error(capsys, "export", CONVENTIONAL, "--format", "fmu", "-o", tmp_path / "car.fmu",
                       mentions="pip install 'express[interop]'")
    assert not (tmp_path / "car.fmu").exists()


# ------------------------------------------------------------------ messages a person can read


def test_after_20_problems_a_count_of_the_rest(capsys, tmp_path: Path) -> None:
    text = Path(CONVENTIONAL).read_text()
    undefined = "\n".join(f'u{k} = "nothing{k} * 2"' for k in range(1000))
    model = tmp_path / "many.toml"
    model.write_text(text.replace("[parameters]", "[parameters]\n" + undefined, 1))
    err = assert_input_error(capsys, "generate", model)
    lines = err.splitlines()
    assert len(lines) == 21 and "undefined name nothing0" in lines[0]
    assert lines[-1] == "error: ... and 980 more problems (1000 in all, the first 20 shown)"


def test_quoted_input_is_cut_to_200_characters(capsys) -> None:
    values = ",".join(["0.1"] * 10001)
    err = assert_input_error(capsys, "critical-speed", CONVENTIONAL, "--conicities", values, mentions="40003 characters")
    assert len(err) < 500


def test_substructure_instances_with_the_same_prefix_are_one_problem_naming_both(capsys, tmp_path: Path) -> None:
    model = tmp_path / "same-prefix.toml"
    model.write_text(Path(CONVENTIONAL).read_text().replace('prefix = "T2_"', 'prefix = "T1_"'))
    err = assert_input_error(capsys, "generate", model)
    assert err.count("error:") == 1, err
    assert "instance rear: its ids collide with those of instance front" in err and "'T1_'" in err


# ------------------------------------------------------------------ truncation


def _cut(tmp_path: Path, source: str, lines: int) -> Path:
    path = tmp_path / f"cut{Path(source).suffix}"
    path.write_text("".join(Path(source).read_text().splitlines(keepends=True)[:lines]))
    return path


@pytest.mark.parametrize("fraction", [0.3, 0.6, 0.85, 0.97, 0.985])
def test_a_classic_file_cut_short_is_refused_where_it_stops(capsys, tmp_path: Path, fraction: float) -> None:
    """``forced-steering.exp`` (written by ``convert``: its header lists every id) cut at
    any line: a missing section or an id listed without its row."""
    source = str(Path(STEERED).with_suffix(".exp"))
    total = len(Path(source).read_text().splitlines())
    lines = int(total * fraction)
    err = assert_input_error(capsys, "generate", _cut(tmp_path, source, lines), mentions=f"the file stops early, at line {lines}")
    assert err.count("error:") == 1


@pytest.mark.parametrize(("lines", "mentions"), [
    (6, "sections (2) Ground, (3) CP, (4) TSD, (5) Pinned Joint missing"),
    (22, "sections (4) TSD, (5) Pinned Joint missing"),
    (32, "section (5) Pinned Joint missing"),
    (31, "section (5) Pinned Joint missing"),
])
def test_the_papers_lever_cut_before_its_last_rows_is_refused(capsys, tmp_path: Path, lines: int, mentions: str) -> None:
    assert_input_error(capsys, "generate", _cut(tmp_path, LEVER, lines), mentions=mentions)


@pytest.mark.parametrize("text", ["", "\n\n", '[model]\nname = "empty"\n', "[parameters]\nm = 1.0\n"])
def test_a_toml_model_without_bodies_is_refused(capsys, tmp_path: Path, text: str) -> None:
    path = tmp_path / "empty.toml"
    path.write_text(text)
    assert_input_error(capsys, "generate", path, mentions="the model has no bodies")


# ------------------------------------------------------------------ studies bounded by time


def _study_file(tmp_path: Path, body: str) -> Path:
    path = tmp_path / "study.toml"
    path.write_text(f'[study]\nmodel = "{STEERED}"\noutputs = ["critical_speed"]\n' + body)
    return path


@pytest.mark.parametrize(("body", "mentions"), [
    ('kind = "grid"\n[study.parameters]\nGamma = { from = 0.05, to = 0.4, count = 9223372036854775807 }\n',
     "count = 9223372036854775807 is more than the limit of 10000000 points"),
    ('kind = "grid"\n[study.parameters]\nGamma = { from = 0.05, to = 0.4, count = 10000 }\n'
     'kx1 = { from = "1 MN/m", to = "4 MN/m", count = 1001 }\n', "expands to 10010000 points (10000 x 1001 grid)"),
    ('kind = "sobol-indices"\nsamples = 10000000\n[study.parameters]\nGamma = { from = 0.05, to = 0.4 }\n'
     'kx1 = { from = "1 MN/m", to = "4 MN/m" }\n', "expands to 40000000 points"),
    ('kind = "lhs"\nsamples = 9223372036854775807\n[study.parameters]\nGamma = { from = 0.05, to = 0.4 }\n',
     "must be a whole number from 1 to 10000000"),
])
def test_counts_are_checked_before_any_allocation(capsys, tmp_path: Path, body: str, mentions: str) -> None:
    assert_input_error(capsys, "study", _study_file(tmp_path, body), "-o", tmp_path / "out.csv", mentions=mentions)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["study.toml"]


def test_a_study_estimated_to_take_too_long_is_refused_before_it_starts(capsys, tmp_path: Path, monkeypatch) -> None:
    """The estimate is timed on a few points; the bound is lowered here so that a small
    grid stands for a huge one."""
    from express.analysis.study import run as study_run

    monkeypatch.setattr(study_run, "CALIBRATE_ABOVE", 4)
    study = _study_file(tmp_path, 'kind = "grid"\n[study.parameters]\nGamma = { from = 0.05, to = 0.4, count = 6 }\n')
    output = tmp_path / "out.csv"
    err = assert_input_error(capsys, "study", study, "-o", output, "--workers", "1", "--max-hours", "1e-9",
                             mentions="the study would take about")
    assert "6 points at" in err and "give --max-hours" in err and "--scheduler" in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["study.toml"]  # no checkpoint, no output
    status, _, err = run(capsys, "study", study, "-o", output, "--workers", "1", "--max-hours", "1")
    assert status == 0, err
    assert len(output.read_text().splitlines()) == 7


@pytest.mark.parametrize(("method", "evaluations", "workers"), [
    ("differential-evolution", 18, "2 workers"),  # population 3 x 2 parameters x (2 + 1)
    ("cobyla", 6, "1 worker"),  # iterations 2 x population 3, one at a time
])
def test_an_optimisation_estimated_to_take_too_long_is_refused_before_it_starts(
    capsys, tmp_path: Path, monkeypatch, method: str, evaluations: int, workers: str,
) -> None:
    """An optimisation is bounded by its maximum number of evaluations times the time of a
    calibration evaluation; the bound is lowered here so that a small one stands for a huge one."""
    from express.analysis.study import run as study_run

    monkeypatch.setattr(study_run, "CALIBRATE_ABOVE", 4)
    study = _study_file(tmp_path, 'kind = "optimise"\n[study.parameters]\nGamma = { from = 0.05, to = 0.4 }\n'
                        'kx1 = { from = "1 MN/m", to = "4 MN/m" }\n[study.objective]\nmaximise = "critical_speed"\n'
                        f'[study.optimiser]\nmethod = "{method}"\npopulation = 3\niterations = 2\n')
    output = tmp_path / "out.csv"
    err = assert_input_error(capsys, "study", study, "-o", output, "--workers", "2", "--max-hours", "1e-9",
                             mentions="the study would take about")
    assert f"{evaluations} evaluations at most at" in err and f"(measured) on {workers}" in err
    assert "give --max-hours" in err and "--scheduler" in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["study.toml"]  # no checkpoint, no output
    status, _, err = run(capsys, "study", study, "-o", output, "--workers", "2", "--max-hours", "1")
    assert status == 0, err
    assert 2 <= len(output.read_text().splitlines()) - 1 <= evaluations


# ------------------------------------------------------------------ profiles know their role


@pytest.fixture()
def profile_files(tmp_path: Path) -> dict[str, Path]:
    """The standard S1002 wheel and 60E1 rail as files, and the wheel mirrored."""
    from express.rail.profiles import standard_profile_text

    files = {"wheel": tmp_path / "w.csv", "rail": tmp_path / "r.csv", "mirrored": tmp_path / "wm.csv"}
    files["wheel"].write_text(standard_profile_text("S1002"))
    files["rail"].write_text(standard_profile_text("60E1"))
    rows = [line.split(",") for line in files["wheel"].read_text().splitlines() if line[:1] in "-0123456789"]
    files["mirrored"].write_text("y_mm,z_mm\n" + "".join(f"{-float(y):.6f},{z}\n" for y, z in reversed(rows)))
    return files


@pytest.mark.parametrize(("wheel", "rail", "mentions"), [
    ("rail", "wheel", "r.csv: wheel profile: given as the wheel, but it has a convex head"),
    ("wheel", "wheel", "the same file given as the wheel and as the rail"),
    ("mirrored", "rail", "wm.csv: wheel profile: given as the wheel, but its flange (28 mm deep at y = 55.02 mm) "
                         "lies at positive y: a mirrored wheel"),
])
@pytest.mark.parametrize("command", ["contact-geometry", "conicity"])
def test_a_profile_in_the_wrong_role_is_refused_naming_file_role_and_shape(
    capsys, tmp_path: Path, profile_files, wheel: str, rail: str, mentions: str, command: str,
) -> None:
    output = tmp_path / "out.csv"
    err = assert_input_error(capsys, command, profile_files[wheel], profile_files[rail], "-o", output, mentions=mentions)
    assert "nan" not in err.lower() and not output.exists()


def test_a_wheel_given_as_the_rail_is_named_a_wheel(capsys, profile_files) -> None:
    assert_input_error(capsys, "contact-geometry", "S1002", profile_files["wheel"],
                       mentions="w.csv: rail profile: given as the rail, but it has a flange (28 mm deep")


def test_the_shapes_of_the_roles() -> None:
    """Documented tests on the shapes: the standard wheel and rail pass their own role
    and fail the other; a flangeless cone (a roller) is no wheel for the commands."""
    import numpy as np

    from express.rail.profiles import role_problems, standard_profile

    wheel, rail = standard_profile("S1002"), standard_profile("60E1")
    assert role_problems(wheel.y * 1e3, wheel.z * 1e3, "S1002", "wheel") == []
    assert role_problems(rail.y * 1e3, rail.z * 1e3, "60E1", "rail") == []
    assert role_problems(wheel.y * 1e3, wheel.z * 1e3, "S1002", "rail")
    assert role_problems(rail.y * 1e3, rail.z * 1e3, "60E1", "wheel")
    y = np.linspace(-40.0, 40.0, 81)
    assert "no flange" in role_problems(y, 0.05 * y, "cone", "wheel")[0].message


# ------------------------------------------------------------------ stability relative to the spectrum


def test_a_rounding_eigenvalue_is_not_an_instability(capsys) -> None:
    """Young's modulus 1e-300 Pa: no creep forces, the free lateral motions give a double
    eigenvalue 0 that rounding moves to +6.7e-7 1/s (spectrum scale 231 1/s): stable, as a
    threshold relative to the spectrum's scale says; a real instability stays one."""
    from express.analysis.modes.modes import STABILITY_RTOL
    from express.analysis.stability.stability import eigen_analysis
    from express.numeric.statespace import load_vehicle

    result = eigen_analysis(load_vehicle(CONVENTIONAL, {"Emod": "1e-300"}), 120 / 3.6)
    assert 0 < result.max_real < result.threshold == pytest.approx(STABILITY_RTOL * 230.82, rel=1e-3)
    assert result.stable
    status, out, _ = run(capsys, "eigen", CONVENTIONAL, "--set", "Emod=1e-300")
    assert status == 0 and "; stable" in out.splitlines()[0]
    status, out, _ = run(capsys, "eigen", CONVENTIONAL, "--speed", "520")
    assert "; UNSTABLE" in out.splitlines()[0]


def test_writing_over_a_bundled_example_is_refused_as_documented(capsys, tmp_path: Path) -> None:
    """docs/cli.md, Outputs: a bundled example is never a destination (also through a link)."""
    import os

    conventional = Path(CONVENTIONAL)
    before = conventional.read_bytes()
    link = tmp_path / "link.toml"
    os.symlink(conventional, link)
    for target in (conventional, link):
        assert_input_error(capsys, "convert", LEVER, "-o", target, mentions="refusing to overwrite the bundled example")
    assert conventional.read_bytes() == before


def test_a_non_finite_contact_result_is_no_result() -> None:
    """No NaN is written or printed: a table with a missing contact is status 1 (AnalysisError)."""
    from types import SimpleNamespace

    import numpy as np

    from express.base.diagnostics import AnalysisError
    from express.cli.contact_geometry import require_finite

    y = np.array([-0.002, 0.0, 0.002])
    good = SimpleNamespace(y=y, roll=np.zeros(3), height=np.zeros(3), delta_r=np.zeros(3),
                           radius=np.full((2, 3), 0.46), contact_angle=np.zeros((2, 3)))
    require_finite(good, "S1002 on 60E1")
    bad = SimpleNamespace(**{**vars(good), "delta_r": np.array([0.0, math.nan, math.nan])})
    with pytest.raises(AnalysisError, match=r"at 2 of 3 lateral displacements, the first at y = 0 mm"):
        require_finite(bad, "w on r")


@pytest.mark.parametrize("argv", [
    ["study", "{special}", "-o", "{tmp}/out.csv"],
    ["ride", CONVENTIONAL, "--track", "{special}"],
])
@pytest.mark.parametrize(("special", "words"), [
    ("/dev/zero", "not a regular file but a character device"),
    ("fifo", "a FIFO (named pipe) that nobody writes into"),
])
def test_study_files_and_psd_tables_are_refused_by_their_kind_too(capsys, tmp_path: Path, argv, special, words) -> None:
    import os

    if special == "fifo":
        special = str(tmp_path / "input.csv")
        os.mkfifo(special)
    arguments = [a.format(special=special, tmp=tmp_path) for a in argv]
    assert_input_error(capsys, *arguments, mentions=words)


# ------------------------------------------------------------------ no NaN or inf as a result


def _poisoned(value, bad: float, field: str = ""):
    """``(copy of value with its first float number set to bad, done)``: the first float
    array entry or float found in dataclasses, dicts, lists and tuples, depth first
    (within the dataclass ``field`` of ``value`` when given)."""
    import copy
    import dataclasses

    import numpy as np

    if field:
        twin = copy.copy(value)
        new, done = _poisoned(getattr(value, field), bad)
        object.__setattr__(twin, field, new)
        return twin, done
    if isinstance(value, np.ndarray) and value.dtype.kind in "fc" and value.size:
        array = value.copy()
        array.flat[0] = bad
        return array, True
    if isinstance(value, float):
        return bad, True
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        for item in dataclasses.fields(value):
            new, done = _poisoned(getattr(value, item.name), bad)
            if done:
                twin = copy.copy(value)
                object.__setattr__(twin, item.name, new)
                return twin, True
    if isinstance(value, dict):
        for key, item in value.items():
            new, done = _poisoned(item, bad)
            if done:
                return {**value, key: new}, True
    if isinstance(value, (list, tuple)):
        for k, item in enumerate(value):
            new, done = _poisoned(item, bad)
            if done:
                items = list(value)
                items[k] = new
                return (type(value)(items) if isinstance(value, tuple) and type(value) is tuple else
                        items if isinstance(value, list) else value._make(items)), True
    return value, False


#: command line (``{out}``: the output file), the analysis function whose result is
#: poisoned (module, name, and the field of the result when not its first number), the
#: bad value, and what the message names.
NON_FINITE_CASES = [
    (["eigen", CONVENTIONAL], "express.analysis.stability.stability", "eigen_analysis:modes", math.nan, "eigen: a result"),
    (["eigen", CONVENTIONAL, "--json"], "express.analysis.stability.stability", "eigen_analysis:modes", math.inf,
     "result.modes"),
    (["critical-speed", STEERED], "express.analysis.stability.stability", "critical_speed", math.inf, "critical-speed: a result"),
    (["critical-speed", STEERED, "--json"], "express.analysis.stability.stability", "critical_speed", math.nan, "result."),
    (["critical-speed", STEERED, "--conicities", "0.1,0.2", "-o", "{out}"], "express.analysis.stability.stability",
     "critical_speed_vs_conicity", math.inf, "critical_speed_m_s: not a finite number (inf) at row 1"),
    (["frf", CONVENTIONAL, "--points", "20", "-o", "{out}"], "express.analysis.frequency.frequency", "frequency_response",
     math.nan, "is not finite at some frequency"),  # frf's own check, before the writer's
    (["ride", CONVENTIONAL, "--track", "ERRI-low", "--points", "20", "-o", "{out}"], "express.analysis.ride.vehicle",
     "ride_response:psd", math.inf, "not a finite number (inf)"),
    (["curving", STEERED, "--radius", "600", "-o", "{out}"], "express.analysis.curving.settled", "curving_or_settled",
     math.nan, "not a finite number (nan)"),
    (["export", CONVENTIONAL, "-o", "{out}.npz"], "express.export.linear_system", "numeric_matrices", math.nan,
     "not a finite number (nan) at index"),
    (["export", CONVENTIONAL, "-o", "{out}.mat"], "express.export.linear_system", "numeric_matrices", math.inf,
     "not a finite number (inf) at index"),
    (["sensitivity", CONVENTIONAL, "--output", "eigenvalue", "--parameter", "ky1"], "express.analysis.study.sensitivity",
     "eigenvalue_derivatives", math.nan, "sensitivity: a result is not a finite number (nan)"),
    (["sensitivity", CONVENTIONAL, "--output", "eigenvalue", "--parameter", "ky1", "--json"],
     "express.analysis.study.sensitivity", "eigenvalue_derivatives", math.inf, "result.eigenvalue"),
    (["simulate", CONVENTIONAL, "--dt", "0.01", "-o", "{out}.csv"], "express.analysis.time.simulate", "simulate:q",
     math.nan, "a state or output is not finite"),  # diverged at t = 0: no valid step to keep as .diverged.csv
    (["report", CONVENTIONAL, "-o", "{out}.html"], "express.analysis.stability.stability", "eigen_analysis:modes", math.nan,
     "report: a result is not a finite number (nan)"),
]


@pytest.mark.parametrize(("argv", "module", "function", "bad", "mentions"), NON_FINITE_CASES,
                         ids=[f"{case[0][0]}-{k}" for k, case in enumerate(NON_FINITE_CASES)])
def test_a_non_finite_result_is_exit_1_naming_it_and_nothing_is_written(
    capsys, tmp_path: Path, monkeypatch, argv: list, module: str, function: str, bad: float, mentions: str,
) -> None:
    """The analysis is made to return a nan or inf (its first number); the command
    refuses to write or print it: status 1, the quantity and its place named, no file."""
    import importlib

    function, _, field = function.partition(":")
    target = importlib.import_module(module)
    real = getattr(target, function)

    def poisoned(*args, **kwargs):
        value, done = _poisoned(real(*args, **kwargs), bad, field)
        assert done, f"{function} returned no number to poison"
        return value

    monkeypatch.setattr(target, function, poisoned)
    out = tmp_path / "out"
    status, stdout, err = run(capsys, *[str(a).replace("{out}", str(out)) for a in argv])
    assert status == 1, (status, err)
    assert mentions in err and "finite" in err, err
    assert "nan" not in stdout.lower().split() and "inf" not in stdout.lower().split()
    assert sorted(p.name for p in tmp_path.iterdir()) == []  # nothing written, no temporary left


def test_a_failed_study_point_is_nan_with_its_reason(tmp_path: Path, monkeypatch) -> None:
    """A study's documented failure marker (docs/studies.md): nan, never without its reason."""
    from express.analysis.study import outputs
    from express.analysis.study.results import read_table
    from express.analysis.study.run import run_study
    from express.analysis.study.spec import read_study

    real = outputs.PointOutputs.__call__

    def no_value(self, vehicle):
        values, _ = real(self, vehicle)
        return dict.fromkeys(values, math.inf), []

    monkeypatch.setattr(outputs.PointOutputs, "__call__", no_value)
    study = _study_file(tmp_path, 'kind = "grid"\n[study.parameters]\nGamma = { from = 0.05, to = 0.4, count = 2 }\n')
    run_study(read_study(study), tmp_path / "out.csv", workers=1)
    text = (tmp_path / "out.csv").read_text()
    assert "inf" not in text.lower().replace("info", "")
    table = read_table(tmp_path / "out.csv")
    assert np_all_nan(table["critical_speed"])
    assert list(table["error"]) == ["no finite value of critical_speed"] * 2


def np_all_nan(values) -> bool:
    import numpy as np

    return bool(np.all(np.isnan(np.asarray(values, dtype=float))))


def test_a_demo_with_a_non_finite_number_writes_nothing(capsys, tmp_path: Path, monkeypatch) -> None:
    """The demo's files go through the same writers: a nan in its summary is status 1
    and the files it wrote before are not kept (one transaction)."""
    import express.paper.demo as library
    from express.io.output import write_text
    from express.io.text_formats import csv_text, json_text

    def run_demo(outdir, *, examples=None, log=print):
        outdir.mkdir(parents=True, exist_ok=True)
        write_text(outdir / "fig.csv", csv_text({"speed": [1.0, 2.0]}))
        write_text(outdir / "summary.json", json_text({"critical_speed_kmh": math.nan}))
        return outdir / "summary.json"

    monkeypatch.setattr(library, "run_demo", run_demo)
    status, _, err = run(capsys, "demo", tmp_path / "out", "--examples", Path(STEERED).parent)
    assert status == 1 and "result.critical_speed_kmh: not a finite number (nan)" in err, err
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == []


# ------------------------------------------------------------ issue 36, item 6: leftovers


@pytest.mark.parametrize("argv, status, words", [
    (["contact-geometry", "S1002", "60E1", "--inclination", "1:inf", "-o", "{tmp}/g.csv"], 0, []),
    (["critical-speed", "examples/conventional.toml", "--conicities", "0.1,,0.2"], 2, ["an empty item in the list"]),
    (["simulate", "examples/conventional.toml", "--assess", "--linear"], 2, ["--assess", "drop one of them"]),
], ids=["upright rail 1:inf", "an empty list item", "assess of a linear run"])
def test_leftovers_of_the_fourth_audit(tmp_path, argv, status, words):
    """The documented upright rail ``1:inf`` is not refused as a non-finite result (the
    finite check read the echoed input); ``0.1,,0.2`` is an error, not two values;
    ``simulate --assess --linear`` is refused instead of dropping the assessment."""
    import subprocess
    import sys

    root = Path(__file__).resolve().parents[1]
    run = subprocess.run([sys.executable, "-m", "express", *[a.replace("{tmp}", str(tmp_path)) for a in argv]],
                         capture_output=True, text=True, cwd=root, timeout=600)
    assert run.returncode == status, run.stderr
    assert "Traceback" not in run.stderr
    for word in words:
        assert word in run.stderr


def test_a_non_ascii_name_is_told_it_is_not_ascii():
    from express.base.diagnostics import ModelError
    from express.io import parse_toml_model

    text = '[model]\nname = "m"\n[parameters]\n"μ" = 0.3\n[bodies.B]\nmass = 1\ndofs = ["x"]\n'
    with pytest.raises(ModelError) as error:
        parse_toml_model(text, "m.toml")
    message = " ".join(str(p) for p in error.value.problems)
    assert "ASCII" in message and "'μ'" in message and "must start with a letter" not in message


@pytest.mark.slow
def test_a_report_of_a_profile_contact_model_prints_no_library_warning(tmp_path):
    """``express report examples/manchester-s1002.toml --track R600`` printed Matplotlib's
    "No artists with labels found to put in legend" (the run's force panel looked for the
    dead-band model's Q<n>; it now draws each wheel's Y)."""
    import subprocess
    import sys

    root = Path(__file__).resolve().parents[1]
    run = subprocess.run([sys.executable, "-m", "express", "report", "examples/manchester-s1002.toml", "--track", "R600",
                          "-o", str(tmp_path / "r.html")], capture_output=True, text=True, cwd=root, timeout=900)
    assert run.returncode == 0, run.stderr
    assert "No artists" not in run.stderr and "Warning" not in run.stderr
