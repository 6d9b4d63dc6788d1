"""Steady curving that says what it found (issue 32, item 5;
express.analysis.curving.settled): where the equilibrium is unstable or absent, the
vehicle run into the curve, and where it settles or the limit cycle it keeps."""

from __future__ import annotations

import pytest

from cli_support import run_json
from express.analysis.curving import settled as module
from express.analysis.curving.settled import curving_or_settled, settled_curving
from express.analysis.curving.steady import NoSteadyStateError, SteadyCurve, SteadyCurvingSolver
from express.numeric.statespace import load_vehicle

S1002 = "examples/manchester-s1002.toml"


@pytest.fixture(scope="module")
def car():
    return load_vehicle(S1002)


@pytest.mark.slow
def test_a_stable_curve_settles_where_the_equilibrium_is(car):
    """R 400 m at 95 km/h (a stable equilibrium, growth -0.46 1/s): the run into it
    settles (every half range within 0.1 % of its size) at the equilibrium: the leading
    wheelset's angle of attack and each ΣY within 1e-5 of the steady state's (achieved
    1.4e-7 and 0.7-1.8e-6, what is left of the approach over 20 s of running)."""
    curve = SteadyCurve(400.0, 0.150, "right")
    steady = SteadyCurvingSolver(car, 95 / 3.6).solve(curve)
    run = settled_curving(car, curve, 95 / 3.6, "a check")
    assert run.settled, run.describe()
    columns = steady.columns()
    for name in ("aoa1", "SY1", "SY2", "SY3", "SY4"):
        assert run.mean[name] == pytest.approx(columns[name], rel=1e-5), name


@pytest.mark.slow
def test_an_unstable_equilibrium_gives_the_limit_cycle_it_falls_into(car, capsys):
    """R 3000 m at 268 km/h (the equilibrium unstable, growth +0.49 1/s): the run keeps a
    limit cycle, said by ``express curving``: ΣY of the trailing wheelset swinging by
    +-22 N after 20 s (the instability grows slowly this close to where the equilibrium
    is lost, at 270 km/h; regression guard of our own run: more than 10 N; with FASTSIM
    at 260 km/h, growth +0.76 1/s, +-4.3 kN)."""
    data = run_json(capsys, "curving", S1002, "--radius", "3000", "--cant", "100mm", "--speed", "268")
    assert data["stability"][0]["stable"] is False
    (run,) = data["settled"]
    assert not run["settled"] and "unstable" in run["reason"] and run["dt"] == 0.005
    assert max(run["amplitude"][f"SY{j}"] for j in range(1, 5)) > 10.0


def test_an_absent_equilibrium_is_run_into_and_said(car, monkeypatch):
    """A curve whose solver finds no equilibrium (made so here): the vehicle is run into it
    and the result says why; the other curves keep their steady states."""
    solve = SteadyCurvingSolver.solve

    def failing(self, curve, start=None):
        if curve.radius == 1000.0:
            raise NoSteadyStateError("made to fail")
        return solve(self, curve, start)

    monkeypatch.setattr(module.SteadyCurvingSolver, "solve", failing)
    monkeypatch.setattr(module, "settled_length", lambda speed: 150.0)  # a short run is enough here
    curves = [SteadyCurve(800.0, 0.1), SteadyCurve(1000.0, 0.1)]
    found = curving_or_settled(car, curves, [80 / 3.6, 80 / 3.6])
    assert found[0][0] is not None and found[0][1] is None
    steady, run = found[1]
    assert steady is None and run is not None and "no equilibrium found (made to fail)" in run.reason
    assert set(run.mean) >= {"aoa1", "SY1", "YQ1L"} and run.window[1] - run.window[0] == 100.0
