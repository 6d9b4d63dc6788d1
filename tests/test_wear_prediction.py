"""The wear prediction over mileage (issue 37, items 3 and 4; docs/wear.md, "Wear
prediction"): the route file's errors, the flange dimensions of S1002, a uniformly worn
profile against its closed form, the mass between the contacts and the profile, the step
size's convergence and a resumed prediction against an uninterrupted one."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from express.analysis.wear.cases import case_depth, initial_grid, profile_text, with_wheel_profile
from express.analysis.wear.prediction import WearSettings, predict_wear, prediction_identity, profile_path
from express.analysis.wear.route import read_route, route_problems
from express.base.diagnostics import ModelError
from express.rail.profiles import standard_profile
from express.rail.wear import wear_rate_of_contact
from express.rail.wear_profile import WHEEL_STEEL_DENSITY, smooth_depth
from express.rail.wheel_dimensions import flange_dimensions

MODEL = Path(__file__).resolve().parents[1] / "examples" / "manchester-s1002.toml"
#: A tiny route: one curve with flange-root contact, and straight track.
TINY = """[route]
name = "tiny"

[[case]]
radius = "800 m"
cant = "100 mm"
speed = "100 km/h"
share = 0.5

[[case]]
share = 0.5
"""
#: The tiny route's distance for the step checks [m]: about 2 steps of 0.1 mm.
DISTANCE = 250e3


def test_a_bad_route_gets_every_problem_with_its_line(tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text('[route]\nname = "x"\n\n[[case]]\nradius = "400 kg"\nspeed = "80 km/h"\nshare = 0.5\n\n'
                    '[[case]]\nradius = "-3 m"\nspeed = "80 km/h"\ncant_deficiency = 0.5\nshare = 0.3\nlenght = 1\n\n'
                    '[[case]]\nradius = "600 m"\nshare = 0.3\n', encoding="utf-8")
    with pytest.raises(ModelError) as caught:
        read_route(path)
    found = {(p.line, p.item) for p in caught.value.problems}
    assert (5, "case 1: radius") in found  # a mass for a length
    assert (10, "case 2: radius") in found  # negative
    assert (9, "case 2") in found  # both speed and cant deficiency
    assert (14, "case 2: lenght") in found  # unknown key (did you mean ...)
    assert (16, "case 3") in found  # neither
    assert any(p.item == "share" and "sum to 1.1" in p.message for p in caught.value.problems)


def test_the_command_refuses_a_bad_route_and_writes_nothing(tmp_path, capsys):
    from express.cli import main

    path = tmp_path / "bad.toml"
    path.write_text('[[case]]\nradius = "400 m"\nshare = 2\n', encoding="utf-8")
    status = main(["wear", str(MODEL), "--route", str(path), "--distance", "100km", "-o", str(tmp_path / "out")])
    err = capsys.readouterr().err
    assert status == 2
    assert f"{path}:1: case 1" in err and f"{path}:3: case 1: share" in err and "Traceback" not in err
    assert not (tmp_path / "out").exists()


def test_flange_dimensions_of_s1002():
    """EN 13715's S1002 has Sd 32.5 mm, Sh 28 mm, qR 10.8 mm (the design values; our
    profile from its arcs gives them to 0.1 um, 0.02 um and 6 um: asserted 1 um, 1 um,
    10 um; qR is rounded to 0.1 mm in the standard)."""
    profile = standard_profile("S1002")
    dims = flange_dimensions(profile.y, profile.z)
    assert dims.thickness == pytest.approx(32.5e-3, abs=1e-6)
    assert dims.height == pytest.approx(28.0e-3, abs=1e-6)
    assert dims.slope == pytest.approx(10.8e-3, abs=1e-5)
    worn = flange_dimensions(profile.y, profile.z + 1e-3)  # a uniform 1 mm: the same flange
    assert worn.thickness == pytest.approx(dims.thickness, abs=1e-12)


def test_smoothing_keeps_the_volume():
    depth = np.zeros(300)
    depth[[0, 5, 150, 299]] = [1.0, 2.0, 3.0, 4.0]
    smoothed = smooth_depth(depth, 1e-4, 1e-3)
    assert smoothed.sum() == pytest.approx(depth.sum(), rel=1e-14)
    assert smoothed.max() < 0.5 and np.all(smoothed >= 0)


@pytest.fixture(scope="module")
def vehicle():
    from express.numeric.statespace import load_vehicle

    found = load_vehicle(MODEL)
    return found.origin.twin() if found.origin.cached else found


@pytest.fixture(scope="module")
def route(tmp_path_factory):
    path = tmp_path_factory.mktemp("route") / "tiny.toml"
    path.write_text(TINY, encoding="utf-8")
    return read_route(path)


@pytest.mark.slow
def test_a_uniformly_worn_profile(vehicle, tmp_path):
    """A profile worn by a uniform 0.5 mm: every rolling radius of the contact tables on
    the tread (|y| <= 5 mm) falls by 0.5 mm (closed form: the profile moves up rigidly),
    the EN 15302 conicity is unchanged.  Achieved: radius 9.6e-8 m (the contact solver's
    tolerance), conicity 1.6e-5 relative; asserted 2e-7 m, 3e-5.  (Beyond the tread the
    flange jump's node moves by a grid step: 5.8e-5 m at one node.)"""
    from express.rail.profile_contact import wheelset_contacts

    grid = initial_grid(vehicle, 0.1e-3)
    paths = [tmp_path / "new.csv", tmp_path / "worn.csv"]
    paths[0].write_text(profile_text(grid, "new"), encoding="utf-8")
    paths[1].write_text(profile_text(grid.worn(np.full(grid.z.size, 0.5e-3)), "worn"), encoding="utf-8")
    new, worn = (with_wheel_profile(vehicle, path) for path in paths)
    tables = [wheelset_contacts(v.model, v.values, v.wheelsets)[0].tables for v in (new, worn)]
    change = tables[1].data[0] - tables[0].data[0]
    tread = np.abs(tables[0].y) <= 5e-3
    assert np.max(np.abs(change[:, tread] + 0.5e-3)) < 2e-7
    assert worn.wheelsets[0].conicity == pytest.approx(new.wheelsets[0].conicity, rel=3e-5)


@pytest.mark.slow
def test_the_mass_worn_off_the_profile_is_the_contacts(vehicle, route):
    """The depth of a steady state on the profile, smoothed, holds the USFD mass of its
    contacts (``rate x A``, mean over the 8 wheels): achieved 2e-16 relative, asserted 1e-12."""
    from express.analysis.curving.steady import SteadyCurve, SteadyCurvingSolver

    grid = initial_grid(vehicle, 0.1e-3)
    result = SteadyCurvingSolver(vehicle, 100 / 3.6).solve(SteadyCurve(800.0, 0.1))
    depth, _ = case_depth(vehicle, grid, [result])
    out = result.wheel_rail
    mass = float(np.mean(wear_rate_of_contact(out.frictional_power, out.patch_area) * out.patch_area * 1e6)) * 1e-9
    volume = smooth_depth(depth, grid.spacing, 1e-3).sum() * grid.spacing * 2 * math.pi * vehicle.wheelsets[0].r0
    assert mass > 0
    assert volume * WHEEL_STEEL_DENSITY == pytest.approx(mass, rel=1e-12)


#: The fixture's predictions: method, bound [m], tolerance [m], workers, steps before a stop.
RUNS = {"whole": ("heun", 0.5e-3, 0.01e-3, 2, None), "resumed": ("heun", 0.5e-3, 0.01e-3, 1, 1),
        "euler": ("euler", 0.1e-3, 0.01e-3, 1, None), "euler-half": ("euler", 0.05e-3, 0.01e-3, 1, None),
        "heun-coarse": ("heun", 0.2e-3, 1e-3, 1, None), "heun-fine": ("heun", 0.1e-3, 1e-3, 1, None)}


@pytest.fixture(scope="module")
def runs(vehicle, route, tmp_path_factory):
    """The tiny route over DISTANCE: Heun with its error control on 2 workers and, stopped
    after one step then resumed, on one; Euler with bounds 0.1 and 0.05 mm; Heun without
    the error control (tolerance 1 mm) with bounds 0.2 and 0.1 mm."""
    base = tmp_path_factory.mktemp("wear")
    problems, speeds = route_problems(route, 1.5, 9.81)
    assert not problems
    out = {}
    for name, (method, bound, tolerance, workers, stop) in RUNS.items():
        settings = WearSettings(bound=bound, method=method, tolerance=tolerance)
        identity = prediction_identity(MODEL.read_text(encoding="utf-8"), {}, route, settings)
        first = predict_wear(vehicle, route, speeds, DISTANCE, base / name, identity=identity, settings=settings,
                             workers=workers, stop_after=stop, figures=name == "whole")
        if stop is not None:
            assert not first.finished and first.run_now == 1
            first = predict_wear(vehicle, route, speeds, DISTANCE, base / name, identity=identity, settings=settings,
                                 workers=workers, figures=False)
        out[name] = first
    return out


def _final(run) -> np.ndarray:
    return np.loadtxt(profile_path(run.directory, len(run.rows) - 1), delimiter=",", skiprows=2)[:, 1] * 1e-3


@pytest.mark.slow
def test_a_resumed_prediction_gives_the_same_bytes(runs):
    """Heun's steps with their error control (the proposed length kept in the checkpoint)."""
    whole, resumed = runs["whole"], runs["resumed"]
    assert resumed.run_now == len(resumed.rows) - 2  # the first step came from the checkpoint
    assert whole.finished and whole.rows[-1]["distance"] == DISTANCE
    for name in ("wear.csv", "checkpoint.json", f"profiles/wheel-{len(whole.rows) - 1:03d}.csv"):
        assert (whole.directory / name).read_bytes() == (resumed.directory / name).read_bytes(), name
    assert (whole.directory / "wear.png").stat().st_size > 0 and (whole.directory / "profiles.png").exists()
    assert all(row["step_error"] <= 0.01e-3 or row["evaluations"] == 6 for row in whole.rows[1:])


@pytest.mark.slow
def test_step_size_convergence_and_the_volume(runs):
    """Over 250 km of the tiny route (0.13-0.18 mm worn at the flange root):

    * Euler, bound 0.1 -> 0.05 mm (2 -> 4 steps): the final profile changes by 0.048 mm
      at most (asserted 0.062 mm; 0.021 mm with FASTSIM);
    * Heun without error control, bound 0.2 -> 0.1 mm (1 -> 2 steps): by 0.041 mm
      (asserted 0.053 mm; FASTSIM 0.026 mm);
    * Heun with its error control (tolerance 0.01 mm) within 0.018 mm of Euler's 0.05 mm
      (asserted 0.023 mm; FASTSIM 0.011 mm).

    Measured separately (docs/wear.md, "Step-size convergence"): the largest depth falls
    as the bound shrinks, 0.177, 0.157, 0.143, 0.134 mm for Euler at 0.1 ... 0.0125 mm
    (order about 0.5: a new profile's contact moves away once worn a little). The
    accumulated wear's volume equals the profile's change to rounding (1e-12), and no step
    changes the profile by more than its bound."""
    final = {name: _final(run) for name, run in runs.items()}
    euler = np.max(np.abs(final["euler"] - final["euler-half"]))
    heun = np.max(np.abs(final["heun-coarse"] - final["heun-fine"]))
    assert len(runs["euler-half"].rows) > len(runs["euler"].rows)
    controlled = np.max(np.abs(final["whole"] - final["euler-half"]))
    assert euler < 0.062e-3 and heun < 0.053e-3 and controlled < 0.023e-3, (euler, heun, controlled)
    for name, run in runs.items():
        for row in run.rows:
            assert row["worn_volume"] == pytest.approx(row["profile_volume"], rel=1e-12, abs=1e-18)
            assert row["largest_change"] <= RUNS[name][1] * (1 + 1e-9)


@pytest.mark.slow
def test_a_curve_without_an_equilibrium_wears_as_the_settled_run_into_it():
    """Where the worn profile gives a curve no equilibrium, a case wears as the time run
    into it (``express.analysis.curving.settled``), each instant of its last 100 m an
    equal share of the metre: on a curve that has one (R 400 m, 95 km/h) the settled run
    wears the profile as the equilibrium does, to 1e-5 of the largest depth (achieved
    3.5e-7; the total 1.9e-7)."""
    from express.analysis.curving.settled import settled_curving
    from express.analysis.curving.steady import SteadyCurve, SteadyCurvingSolver
    from express.analysis.wear.cases import case_depth, initial_grid
    from express.numeric.statespace import load_vehicle

    car = load_vehicle("examples/manchester-s1002.toml")
    grid = initial_grid(car, 0.5e-3)
    curve = SteadyCurve(400.0, 0.150, "right")
    steady, _ = case_depth(car, grid, [SteadyCurvingSolver(car, 95 / 3.6).solve(curve)])
    settled, _ = case_depth(car, grid, [settled_curving(car, curve, 95 / 3.6, "a check")])
    assert np.abs(settled - steady).max() < 1e-5 * np.abs(steady).max()
