"""One behaviour, two faces (issue 35 item 1): each command's case run through the command
line (``--json``) and through the library function the docs name for it, with the same
inputs in SI, gives the same numbers.

The command line reads a bare speed as km/h and takes a track's own speed when no
``--speed`` is given; the library is given SI and the speed explicitly where the command
chose it (the track's speed for ``simulate`` and ``curving``: the library's default,
``express.simulate``'s ``running_speed``).  Agreement asserted to 1e-12 relative (the same
code runs; achieved: equal, except the printed JSON's round trip of floats, exact).
"""

from __future__ import annotations

import numpy as np
import pytest

import express
from cli_support import CONVENTIONAL, run_json

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
