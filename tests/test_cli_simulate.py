"""``express simulate`` (``express.cli.simulate``): JSON in SI, files with units in the
header, all-or-nothing outputs, standard output, diverged runs (status 1)."""

from __future__ import annotations

import csv
import io
import json
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from cli_support import (
    CONVENTIONAL,
    LEVER,
    SHORT_TRACK,
    SINUSOID,
    STEERED,
    assert_fails,
    assert_input_error,
    run,
    run_json,
    valued_lever,
)
from express.analysis.time.divergence import find_divergence


@pytest.fixture
def short_track(tmp_path):
    path = tmp_path / "short.toml"
    path.write_text(SHORT_TRACK, encoding="utf-8")
    return path


def test_simulate_json_on_the_paper_curve(capsys):
    data = run_json(capsys, "simulate", CONVENTIONAL, "--dt", "0.01")
    assert data["speed"] == pytest.approx(120 / 3.6)  # m/s, the model's speed
    assert data["track_length"] == pytest.approx(460.0)  # the paper's curve
    maxima = data["max_abs"]
    for key in ("Y1", "Y2", "psi_TW1", "psi_TW2"):
        assert key in maxima
    assert not any(key.startswith("theta_") for key in maxima)  # no levers on this car
    # SI: newtons and radians (tens of kN, a fraction of a milliradian)
    assert 5e3 < maxima["Y1"] < 1e5
    assert 0 < maxima["psi_TW1"] < 0.01
    assert maxima["rho1"] == pytest.approx(1 / 400)


def test_simulate_steered_reports_lever_angles_and_writes_files(capsys, short_track, tmp_path):
    outputs = [tmp_path / "run.csv", tmp_path / "run.npz", tmp_path / "out" / "run.mat"]
    figure = tmp_path / "run.png"
    args = ["simulate", STEERED, "--track", short_track, "--dt", "0.01", "--plot", figure]
    for path in outputs:
        args += ["-o", path]
    data = run_json(capsys, *args)
    assert data["track_length"] == pytest.approx(80.0)
    assert {"theta_L1", "theta_L2", "theta_L3", "theta_L4", "Y1", "Y2", "psi_TW1", "psi_TW2"} <= set(data["max_abs"])
    assert data["max_abs"]["theta_L1"] > 0.01  # the lever turns in the curve [rad]
    for path in [*outputs, figure]:
        assert path.is_file() and path.stat().st_size > 0, path
    with open(outputs[0], newline="", encoding="utf-8") as stream:
        header = next(csv.reader(stream))
    assert {"time_s", "d1_m", "Y1_N", "YQ1", "theta_L1_rad", "W1.y_m", "W1.y_dot_m_s"} <= set(header)
    assert figure.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    with np.load(outputs[1]) as npz:
        assert "Y1" in npz.files


def test_simulate_outputs_are_deterministic(capsys, short_track, tmp_path):
    for name in ("a", "b"):
        argv = ["simulate", CONVENTIONAL, "--track", short_track, "--dt", "0.02"]
        for suffix in (".csv", ".npz", ".mat"):
            argv += ["-o", tmp_path / f"{name}{suffix}"]
        assert run(capsys, *argv)[0] == 0
    for suffix in (".csv", ".npz", ".mat"):
        assert (tmp_path / f"a{suffix}").read_bytes() == (tmp_path / f"b{suffix}").read_bytes()


def test_simulate_csv_on_standard_output(capsys, short_track):
    """``-o -`` writes the CSV to stdout; the readable summary moves to stderr."""
    status, out, err = run(capsys, "simulate", CONVENTIONAL, "--track", short_track, "--dt", "0.02", "-o", "-")
    assert status == 0, err
    rows = list(csv.reader(io.StringIO(out)))
    assert rows[0][:2] == ["time_s", "d1_m"] and len(rows) > 100
    assert "largest absolute values" in err


def test_simulate_set_changes_the_result(capsys, short_track):
    base = run_json(capsys, "simulate", CONVENTIONAL, "--track", short_track, "--dt", "0.01")
    changed = run_json(capsys, "simulate", CONVENTIONAL, "--track", short_track, "--dt", "0.01", "--set", "Gamma=0.05")
    assert changed["max_abs"]["psi_TW1"] != pytest.approx(base["max_abs"]["psi_TW1"], rel=1e-3)


@pytest.mark.parametrize("speed", ["80", "80 km/h", "22.2222222222 m/s"])
def test_simulate_track_speed_and_linear_options(capsys, speed):
    data = run_json(capsys, "simulate", CONVENTIONAL, "--track", SINUSOID, "--speed", speed, "--linear", "--dt", "0.01")
    assert data["speed"] == pytest.approx(80 / 3.6)
    assert data["linear"] is True
    assert data["max_abs"]["flange1"] == 0.0  # no flange contact in the linear run


def test_simulate_prints_a_readable_summary(capsys, short_track):
    status, out, err = run(capsys, "simulate", CONVENTIONAL, "--track", short_track, "--dt", "0.01")
    assert status == 0, err
    assert "km/h" in out and "kN" in out and "Y1" in out


@pytest.mark.parametrize(
    "argv, mentions",
    [
        (["simulate", CONVENTIONAL, "--speed", "fast"], "--speed"),
        (["simulate", CONVENTIONAL, "--speed", "-5"], "0 < --speed"),
        (["simulate", CONVENTIONAL, "--dt", "0"], "--dt"),
        (["simulate", CONVENTIONAL, "-o", "results.txt"], ".csv"),
        (["simulate", CONVENTIONAL, "--plot", "figure.gif"], ".png"),
        (["simulate", CONVENTIONAL, "-o", "-", "--json"], "standard output"),
        (["simulate", CONVENTIONAL, "-o", "-", "-o", "-"], "twice"),
        (["simulate", LEVER], "undefined name"),  # no values: nothing to evaluate
        (["simulate", "no-such-model.toml"], "does not exist"),
        (["simulate", CONVENTIONAL, "--track", "no-such-track.toml"], "no-such-track.toml"),
        (["simulate", CONVENTIONAL, "--set", "Gamma"], "NAME=VALUE"),
        (["simulate", CONVENTIONAL, "--set", "gamma=0.05"], "Gamma"),  # the closest name
        (["simulate", CONVENTIONAL, "--speed", "1 km/h", "--dt", "1e-5"], "steps"),
    ],
)
def test_simulate_bad_input_exits_2(capsys, argv, mentions):
    assert_input_error(capsys, *argv, mentions=mentions)


def test_simulate_bad_track_file_exits_2(capsys, tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text('[[segment]]\ntype = "curve"\nlength = -3\n', encoding="utf-8")
    assert_input_error(capsys, "simulate", CONVENTIONAL, "--track", bad, mentions="bad.toml")


def test_several_outputs_are_all_or_nothing(capsys, tmp_path):
    """``-o a.csv -o blocked/b.csv``: refused before the run, a.csv keeps its contents."""
    first = tmp_path / "a.csv"
    first.write_text("earlier result\n")
    (tmp_path / "blocked").write_text("a file")
    assert_input_error(capsys, "simulate", CONVENTIONAL, "-o", first, "-o", tmp_path / "blocked" / "b.csv",
                       mentions="blocked")
    assert first.read_text() == "earlier result\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.csv", "blocked"]


def test_simulate_refuses_to_overwrite_its_inputs(capsys, tmp_path, short_track):
    model = tmp_path / "car.toml"
    model.write_text(Path(CONVENTIONAL).read_text(encoding="utf-8"), encoding="utf-8")
    before, track_before = model.read_bytes(), short_track.read_bytes()
    csv_model = tmp_path / "car.csv"  # a model whose name looks like an output
    csv_model.write_bytes(before)
    assert_input_error(capsys, "simulate", csv_model, "--track", short_track, "-o", csv_model, mentions="refusing")
    assert csv_model.read_bytes() == before
    assert_input_error(capsys, "frf", model, "-o", model, mentions="refusing")
    assert_input_error(capsys, "critical-speed", model, "--conicities", "0.1", "-o", model, mentions="refusing")
    assert model.read_bytes() == before and short_track.read_bytes() == track_before


# --------------------------------------------------------------------------- diverged runs


def _result(q: np.ndarray, outputs: dict | None = None):
    time = np.arange(len(q)) * 0.01
    return SimpleNamespace(time=time, distance=30 * time, q=q, q_dot=np.zeros_like(q),
                           outputs=outputs or {"Q1": np.zeros(len(q))}, speed=30.0)


_VEHICLE = SimpleNamespace(wheelsets=[SimpleNamespace(name="W1", y=0, flange_clearance=0.006)])


@pytest.mark.parametrize(
    "q, outputs, index, reason",
    [
        (np.zeros((50, 2)), None, None, None),
        (np.full((50, 2), 0.05), None, None, None),  # 50 mm: within 10 clearances (60 mm)
        (np.vstack([np.zeros((20, 2)), np.full((30, 2), np.nan)]), None, 20, "not finite"),
        (np.vstack([np.zeros((7, 2)), np.full((43, 2), 0.07)]), None, 7, "wheelset W1"),
        (np.zeros((50, 2)), {"Q1": np.r_[np.zeros(33), np.full(17, np.inf)]}, 33, "not finite"),
    ],
)
def test_find_divergence(q, outputs, index, reason):
    """The first time step with a non-finite value or a wheelset beyond ten flange
    clearances (and none for a run that stays in range)."""
    found = find_divergence(_result(q, outputs), _VEHICLE)
    if index is None:
        assert found is None
    else:
        assert found.index == index and reason in found.reason


@pytest.mark.slow
def test_a_diverged_run_exits_1_keeps_the_history_and_replaces_nothing(capsys, tmp_path):
    """A negative lateral damper (``--set cy2=-300000``, issue 17): status 1, a message
    with the time, the track position and the least-damped eigenvalue; the requested
    output keeps its old contents; the history before the divergence is kept, marked."""
    target = tmp_path / "run.csv"
    target.write_text("earlier\n")
    err = assert_fails(capsys, 1, "simulate", CONVENTIONAL, "--dt", "0.01", "--set", "cy2=-300000", "-o", target,
                       mentions="diverged")
    errors = [line for line in err.splitlines() if line.startswith("error: ")]
    assert len(errors) == 1 and "warning: " in err and "negative damping" in err  # the negative damper is a modelling device
    assert "t = " in err and "d1 = " in err and "least-damped eigenvalue" in err
    assert target.read_text() == "earlier\n"
    kept = tmp_path / "run.diverged.csv"
    assert kept.is_file() and kept.name in err
    rows = list(csv.reader(kept.open(encoding="utf-8")))
    assert rows[0][0] == "time_s" and len(rows) > 2
    assert all(np.isfinite(float(x)) for x in rows[-1])


def test_json_summary_is_plain_json(capsys, short_track):
    status, out, _ = run(capsys, "simulate", CONVENTIONAL, "--track", short_track, "--dt", "0.02", "--json")
    assert status == 0
    json.loads(out)  # nan/inf would not parse with the default decoder's strictness off
    assert "NaN" not in out and "Infinity" not in out


def test_simulate_needs_rail_data(capsys, tmp_path):
    """A model with values but no rail data: status 2 and a message saying what applies."""
    assert_input_error(capsys, "simulate", valued_lever(tmp_path), mentions="no rail data")


def test_a_profile_read_by_the_track_is_an_input(capsys, tmp_path):
    """``-o`` naming the measured profile the track reads is refused; the profile is intact."""
    profile = tmp_path / "profile.csv"
    rows = "\n".join(f"{s},{0.001 * np.sin(s / 5):.6f}" for s in range(0, 101, 5))
    profile.write_text("s,yr\n" + rows + "\n", encoding="utf-8")
    track = tmp_path / "measured.toml"
    track.write_text('[[segment]]\ntype = "straight"\nlength = 100.0\n\n[irregularity]\ntype = "csv"\nfile = "profile.csv"\n',
                     encoding="utf-8")
    before = profile.read_bytes()
    assert_input_error(capsys, "simulate", CONVENTIONAL, "--track", track, "-o", profile, mentions="refusing")
    assert profile.read_bytes() == before


def test_assess_reports_wear_and_rcf_per_wheel(capsys, short_track, tmp_path):
    """With the contact tables, ``--assess`` gives each wheel's largest and mean Tgamma,
    USFD wear rate and RCF index (``assessment.wear`` in JSON, a table in the text), and
    the CSV has their columns with units (docs/wear.md)."""
    from cli_support import EXAMPLES

    model = str(EXAMPLES / "manchester-s1002.toml")
    table = tmp_path / "run.csv"
    data = run_json(capsys, "simulate", model, "--track", str(short_track), "--speed", "60", "--assess", "-o",
                    str(table))
    wear = data["assessment"]["wear"]
    assert [w["wheel"] for w in wear] == [f"{j}{s}" for j in range(1, 5) for s in "LR"]
    for w in wear:
        assert 0.0 <= w["tgamma_mean"] <= w["tgamma_max"] and 0.0 <= w["wear_mean"] <= w["wear_max"]
        assert 0.0 <= w["rcf_mean"] <= w["rcf_max"] <= 1e-5
    header = table.read_text().splitlines()[0].split(",")
    assert {"Tgamma1L_N", "wear4R_ug_m_mm2", "rcf2L"} <= set(header)
    status, out, _ = run(capsys, "simulate", model, "--track", str(short_track), "--speed", "60", "--assess")
    assert status == 0 and "wear and RCF per wheel" in out and "\n  4R " in out
