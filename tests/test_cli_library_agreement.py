"""One behaviour, two faces (issue 35 item 1): each command's case run through the command
line (``--json``) and through the library function the docs name for it, with the same
inputs in SI, gives the same numbers.

The command line reads a bare speed as km/h and takes a track's own speed when no
``--speed`` is given; the library is given SI and the speed explicitly where the command
chose it (the track's speed for ``simulate`` and ``curving``: the library's default,
``express.simulate``'s ``running_speed``).  Agreement asserted to 1e-12 relative (the same
code runs; achieved: equal, except the printed JSON's round trip of floats, exact).

Covered: eigen, critical-speed, frf, curving, simulate, ride, sensitivity (its four outputs),
conicity, contact-geometry, study, generate, convert, export, report (byte for byte; it
showed the expanded equations from the library and the factored ones from the command
until ``report_html`` generated the readable ones itself), wear (one step of a tiny route,
its CSV and worn profile byte for byte).  Not here: ``draw`` (a
figure; ``tests/test_cli_draw_export_report.py``), ``demo`` (the paper's numbers,
``tests/test_cli_demo.py``), ``cache`` (no library face). ``twist`` on the standard
twist (the Manchester car, its rail heights imposed at the contact springs).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import express
from cli_support import CONVENTIONAL, assert_input_error, run_json

KMH = 1 / 3.6


@pytest.fixture(scope="module")
def car():
    return express.load_vehicle(CONVENTIONAL)


def test_eigen(capsys, car):
    data = run_json(capsys, "eigen", CONVENTIONAL, "--speed", "100")
    mine = express.eigen(car, 100 * KMH)
    assert data["speed"] == pytest.approx(100 * KMH, rel=1e-15)
    cli = np.array([complex(*pair) for pair in data["eigenvalues"]])
    np.testing.assert_allclose(cli, np.asarray(mine.eigenvalues), rtol=1e-12)
    assert [m["description"] for m in data["modes"]] == [m.describe() for m in mine.modes]


def test_critical_speed(capsys, car):
    data = run_json(capsys, "critical-speed", CONVENTIONAL)
    mine = express.critical_speed(car)
    assert data["critical_speed"] == pytest.approx(mine.speed, rel=1e-12)
    assert data["frequency_hz"] == pytest.approx(mine.mode.frequency_hz, rel=1e-12)
    assert data["unstable_at_min"] is mine.unstable_at_min


def test_frequency_response(capsys, car):
    data = run_json(capsys, "frf", CONVENTIONAL, "--points", "7")
    frequencies = np.asarray(data["frequencies"])
    mine = express.frequency_response(car, frequencies, speed=data["speed"])
    assert data["speed"] == pytest.approx(car.speed, rel=1e-15)  # the model's speed, as the library's default
    for point, output in data["outputs"].items():
        np.testing.assert_allclose(output["amplitude"], np.abs(np.asarray(mine.acceleration_of(point))), rtol=1e-12)


def test_steady_curving(capsys, car):
    data = run_json(capsys, "curving", CONVENTIONAL, "--track", "R600")
    from express.analysis.curving.steady import curves_of_track

    track = express.load_track("R600")  # a bundled name, as --track takes it
    results = express.steady_curving(car, curves_of_track(track), speeds=track.speed)
    cli, library = data["results"][0], results[0].columns()
    assert cli["speed"] == pytest.approx(track.speed, rel=1e-15)  # the track's own speed
    for name in ("a_q", "Q1L", "Q1R", "YQ1L", "aoa1", "SY1"):
        assert cli[name] == pytest.approx(library[name], rel=1e-12, abs=1e-15), name


def test_simulate(capsys, car):
    data = run_json(capsys, "simulate", CONVENTIONAL, "--track", "R1000", "--dt", "0.01")
    run = express.simulate(car, express.load_track("R1000"), dt=0.01, progress=False)  # the track's speed, as the CLI's
    assert data["speed"] == pytest.approx(run.speed, rel=1e-15)
    for name, value in run.max_abs().items():
        assert data["max_abs"][name] == pytest.approx(value, rel=1e-12, abs=1e-300), name


PROFILED = str(Path(CONVENTIONAL).with_name("manchester-s1002.toml"))


def test_simulate_with_a_creep_law(capsys):
    """``--creep-law`` is the library's ``creep_law=``; the summary names the contact and law."""
    data = run_json(capsys, "simulate", PROFILED, "--track", "R600", "--dt", "0.01", "--creep-law", "fastsim")
    vehicle = express.load_vehicle(PROFILED)
    run = express.simulate(vehicle, express.load_track("R600"), dt=0.01, creep_law="fastsim", progress=False)
    assert data["contact"] == run.options["contact"] == "tables (fastsim)"
    for name, value in run.max_abs().items():
        assert data["max_abs"][name] == pytest.approx(value, rel=1e-12, abs=1e-300), name
    default = express.simulate(vehicle, express.load_track("R600"), dt=0.01, progress=False)
    assert default.options["contact"] == "tables (table)"
    assert default.max_abs()["Y1L"] != pytest.approx(run.max_abs()["Y1L"], rel=1e-3)  # the law does change the run


def test_curving_with_a_creep_law(capsys):
    from express.analysis.curving.steady import SteadyCurve

    data = run_json(capsys, "curving", PROFILED, "--radius", "1000", "--speed", "120", "--creep-law", "polach")
    mine = express.steady_curving(express.load_vehicle(PROFILED), SteadyCurve(1000.0, 0.0), speeds=120 * KMH,
                                  creep_law="polach")[0]
    cli, library = data["results"][0], mine.columns()
    assert mine.contact.endswith("(polach)")
    for name in ("Q1L", "YQ1L", "aoa1", "SY1"):
        assert cli[name] == pytest.approx(library[name], rel=1e-12, abs=1e-15), name


@pytest.mark.parametrize(("argv", "mentions"), [
    (("simulate", PROFILED, "--linear", "--creep-law", "fastsim"), "--linear"),
    (("simulate", CONVENTIONAL, "--creep-law", "fastsim"), "profiles"),
    (("curving", PROFILED, "--radius", "600", "--contact", "deadband", "--creep-law", "polach"), "dead-band"),
    (("curving", PROFILED, "--radius", "600", "--creep-law", "kalker"), "invalid choice"),
])
def test_a_creep_law_where_none_applies_is_refused(capsys, argv, mentions):
    assert_input_error(capsys, *argv, mentions=mentions)


def test_ride(capsys, car):
    """``express ride`` against ``ride_response`` with the class's spectra and the
    comfort and wheel-force summaries of the same response."""
    from express.analysis.ride.summaries import point_comfort, wheel_forces
    from express.analysis.ride.vehicle import track_class_spectra

    data = run_json(capsys, "ride", CONVENTIONAL, "--track", "ERRI-low", "--points", "300", "--speed", "120")
    response = express.ride_response(car, track_class_spectra("ERRI-low"), 120 * KMH, np.geomspace(0.1, 50.0, 300))
    for point, comfort in point_comfort(response).items():
        cli, mine = data["output_points"][point], comfort.as_dict()
        for axis, value in mine["rms"].items():
            assert cli["rms"][axis] == pytest.approx(value, rel=1e-12), (point, axis)
        assert cli["n_mv"] == pytest.approx(mine["n_mv"], rel=1e-12)
    for name, forces in wheel_forces(response, car).items():
        assert data["wheelsets"][name]["y_rms"] == pytest.approx(forces.as_dict()["y_rms"], rel=1e-12)


@pytest.mark.parametrize("output", ["critical-speed", "eigenvalue", "steady-curving"])
def test_sensitivity(capsys, car, output):
    from express.analysis.stability.critical_options import CriticalOptions
    from express.analysis.study.sensitivity import critical_speed_sensitivity, eigenvalue_derivatives

    names = ["kx1", "ky1", "cyaw"]
    arguments = ["sensitivity", CONVENTIONAL, "--output", output, *[a for n in names for a in ("--parameter", n)]]
    if output == "steady-curving":
        from express.analysis.curving.steady import SteadyCurve

        data = run_json(capsys, *arguments, "--radius", "600", "--cant", "100", "--speed", "90")
        mine = express.steady_curving_sensitivity(car, SteadyCurve(600.0, 0.1), speed=90 * KMH, parameters=names)
        assert data["values"] == pytest.approx(mine.values, rel=1e-12)
        for name in names:
            assert data["sensitivities"][name] == pytest.approx(mine.as_dict()["sensitivities"][name], rel=1e-12)
        return
    if output == "eigenvalue":
        data = run_json(capsys, *arguments, "--speed", "100")
        eigenvalues, derivatives = eigenvalue_derivatives(car, 100 * KMH, names)
        k = int(np.flatnonzero(eigenvalues.imag >= 0)[0])
        assert data["eigenvalue"] == pytest.approx([eigenvalues[k].real, eigenvalues[k].imag], rel=1e-12)
        for name in names:
            assert data["sensitivities"][name] == pytest.approx([derivatives[name][k].real, derivatives[name][k].imag],
                                                                rel=1e-12)
    else:
        data = run_json(capsys, *arguments)
        mine = critical_speed_sensitivity(car, names, CriticalOptions(tolerance=0.0)).as_dict()
        assert data["critical_speed"] == pytest.approx(mine["critical_speed"], rel=1e-12)
        for name in names:
            assert data["sensitivities"][name] == pytest.approx(mine["sensitivities"][name], rel=1e-12)


def test_sensitivity_of_the_time_run(capsys, car, tmp_path):
    """``--output time-run`` along a short curve entry at 60 km/h: every estimate, error and
    flag, and where the maxima are, the library's."""
    from cli_support import SHORT_TRACK

    track = tmp_path / "short.toml"
    track.write_text(SHORT_TRACK, encoding="utf-8")
    names = ["kx1", "ky1", "cyaw"]
    data = run_json(capsys, "sensitivity", CONVENTIONAL, "--output", "time-run", "--track", str(track), "--speed", "60",
                    *[a for n in names for a in ("--parameter", n)])
    mine = express.time_run_sensitivity(car, express.load_track(track), speed=60 * KMH, parameters=names).as_dict()
    assert data["values"] == pytest.approx(mine["values"], rel=1e-12) and data["maxima"] == mine["maxima"]
    for name in names:
        for output, estimate in mine["estimates"][name].items():
            got = data["estimates"][name][output]
            assert (got["h"], got["half_step"]) == pytest.approx((estimate["h"], estimate["half_step"]), rel=1e-12)
            assert (got["differentiable"], got["reason"], got["switched"]) == (
                estimate["differentiable"], estimate["reason"], estimate["switched"])


def test_conicity(capsys):
    from express.rail.conicity import conicity_from_profiles
    from express.rail.contact_geometry import ContactSetup

    data = run_json(capsys, "conicity", "S1002", "60E1")
    amplitude = np.asarray(data["amplitude_m"])
    mine, _ = conicity_from_profiles(express.standard_profile("S1002"), express.standard_profile("60E1"), amplitude,
                                     ContactSetup(gauge=1.435, flange_back=1.360, inclination=0.025, wheel_radius=0.46))
    np.testing.assert_allclose(data["tan_gamma_e"], mine, rtol=1e-12)


def test_study(capsys, tmp_path):
    """``express study`` writes what ``express.run_study`` writes for the same file."""
    from express.analysis.study.results import read_table
    from express.analysis.study.spec import read_study

    study = tmp_path / "s.toml"
    study.write_text(f'[study]\nmodel = "{CONVENTIONAL}"\nkind = "grid"\noutputs = ["least_damping_ratio", '
                     '"critical_speed"]\n[study.parameters]\nkx1 = { values = [1e6, 3e6] }\n')
    run_json(capsys, "study", study, "-o", tmp_path / "cli.csv", "--workers", "1")
    express.run_study(read_study(study), tmp_path / "lib.csv", workers=1)
    cli, mine = read_table(tmp_path / "cli.csv"), read_table(tmp_path / "lib.csv")
    for name in ("least_damping_ratio", "critical_speed"):
        np.testing.assert_allclose(cli[name], mine[name], rtol=1e-12)


def test_contact_geometry(capsys):
    from express.rail.contact_geometry import ContactSetup, contact_geometry

    data = run_json(capsys, "contact-geometry", "S1002", "60E1")
    table = contact_geometry(express.standard_profile("S1002"), express.standard_profile("60E1"),
                             np.arange(-1000, 1001) * 1e-5, ContactSetup())
    assert data["delta_r_max_m"] == pytest.approx(float(abs(table.delta_r).max()), rel=1e-12)
    assert data["contact_angle_max_rad"] == pytest.approx(float(table.contact_angle.max()), rel=1e-12)
    assert [j["y_before_m"] for j in data["jumps"]] == pytest.approx([j.y_before for j in table.jumps], rel=1e-12)


@pytest.mark.parametrize("fmt", ["json", "text"])
def test_generate(capsys, fmt):
    """``express generate`` is the exporter of ``express.generate_vehicle``'s equations
    (the rail terms included, as the command includes them)."""
    from cli_support import run as run_command
    from express.export import FORMATS

    status, out, err = run_command(capsys, "generate", CONVENTIONAL, "--format", fmt)
    assert status == 0, err
    equations = express.generate_vehicle(express.load_model(CONVENTIONAL)).equations
    assert out == FORMATS[fmt](equations)


def test_convert(capsys):
    from pathlib import Path

    from cli_support import run as run_command

    status, out, err = run_command(capsys, "convert", CONVENTIONAL)
    assert status == 0, err
    assert out == express.model_to_toml(express.load_model(CONVENTIONAL), Path.cwd())


def test_export(capsys, tmp_path, car):
    from cli_support import run as run_command
    from express.export.linear_system import numeric_matrices

    target = tmp_path / "car.npz"
    status, _, err = run_command(capsys, "export", CONVENTIONAL, "--speed", "100", "-o", target)
    assert status == 0, err
    written, mine = np.load(target), numeric_matrices(car, 100 * KMH)
    for key in ("M", "C", "K", "A", "B", "Bd"):
        np.testing.assert_allclose(written[key], mine[key], rtol=1e-12, atol=0)


@pytest.mark.slow
def test_report(capsys, tmp_path):
    """``express report`` writes ``report_html`` of the same vehicle, byte for byte."""
    from cli_support import STEERED
    from cli_support import run as run_command
    from express.report.build import report_html

    target = tmp_path / "r.html"
    status, _, err = run_command(capsys, "report", STEERED, "-o", target)
    assert status == 0, err
    assert target.read_text(encoding="utf-8") == report_html(express.load_vehicle(STEERED))


def test_twist(capsys):
    from express.analysis.twist import assess_twist

    data = run_json(capsys, "twist", "examples/manchester.toml", "--assess", "--no-climb")
    found = assess_twist(express.load_vehicle("examples/manchester.toml"), climb=False)
    np.testing.assert_allclose(data["delta_q"], found.delta_q, rtol=1e-12)
    assert data["criteria"][0]["value"] == pytest.approx(found.assessment.criteria[0].value, rel=1e-12)


@pytest.mark.slow
def test_wear(capsys, tmp_path):
    """``express wear`` and ``predict_wear`` with the same settings, one step of a tiny
    route: the same ``wear.csv`` and worn profile, byte for byte."""
    from cli_support import run as run_command
    from express.analysis.wear.prediction import WearSettings, predict_wear, prediction_identity, profile_path
    from express.analysis.wear.route import read_route, route_problems
    from test_wear_prediction import MODEL, TINY

    route_path = tmp_path / "tiny.toml"
    route_path.write_text(TINY, encoding="utf-8")
    status, _, err = run_command(capsys, "wear", str(MODEL), "--route", str(route_path), "--distance", "250 km",
                                 "-o", str(tmp_path / "cli"), "--stop-after", "1", "--workers", "1", "--no-figures")
    assert status == 0, err
    route = read_route(route_path)
    problems, speeds = route_problems(route, 1.5, 9.81)
    assert not problems
    settings = WearSettings()
    identity = prediction_identity(MODEL.read_text(encoding="utf-8"), {}, route, settings)
    mine = predict_wear(express.load_vehicle(MODEL), route, speeds, 250e3, tmp_path / "library", identity=identity,
                        settings=settings, workers=1, stop_after=1, figures=False)
    assert (tmp_path / "cli" / "wear.csv").read_bytes() == (tmp_path / "library" / "wear.csv").read_bytes()
    last = len(mine.rows) - 1
    assert last >= 1
    assert profile_path(tmp_path / "cli", last).read_bytes() == profile_path(tmp_path / "library", last).read_bytes()
