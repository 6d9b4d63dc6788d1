"""A route's case on a random track (``express.analysis.wear.random_track``; docs/wear.md,
"Random track"): the route keys and their errors, the time run's wear on straight track
(where the steady state wears nothing) converged in the step, and its mass against the
contacts'."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from express.analysis.wear.cases import case_depth, initial_grid
from express.analysis.wear.random_track import DT, random_track_run
from express.analysis.wear.route import RouteCase, read_route, route_problems
from express.base.diagnostics import ModelError
from express.rail.wear import wear_rate_of_contact
from express.rail.wear_profile import WHEEL_STEEL_DENSITY

MODEL = Path(__file__).resolve().parents[1] / "examples" / "manchester-s1002.toml"


@pytest.mark.parametrize(("case", "line", "item", "words"), [
    ('track = "erri_lo"\nspeed = "200 km/h"', 3, "case 1: track", "erri_low"),
    ('track = "erri_low"\nspeed = "200 km/h"\nrun_length = "5 m"', 5, "case 1: run_length", "10 m"),
    ('track = "erri_low"\nspeed = "200 km/h"\nseed = -1', 5, "case 1: seed", ">= 0"),
    ('speed = "200 km/h"\nseed = 3', 4, "case 1: seed", "random track"),
])
def test_a_bad_random_track_is_refused_with_its_line(tmp_path, case, line, item, words):
    path = tmp_path / "route.toml"
    path.write_text(f"[[case]]\nshare = 1\n{case}\n", encoding="utf-8")
    with pytest.raises(ModelError) as caught:
        read_route(path)
    found = [p for p in caught.value.problems if p.item == item]
    assert found and found[0].line == line and words in found[0].message, caught.value.problems


def test_a_straight_random_track_needs_its_speed(tmp_path):
    path = tmp_path / "route.toml"
    path.write_text('[[case]]\nshare = 1\ntrack = "fra6"\n', encoding="utf-8")
    route = read_route(path)
    assert route.cases[0].track == "fra6" and route.cases[0].run_length == 500.0 and route.cases[0].seed == 0
    problems, _ = route_problems(route, 1.5, 9.81)
    assert problems and "needs its speed" in problems[0].message and problems[0].line == 1


@pytest.fixture(scope="module")
def car():
    from express.numeric.statespace import load_vehicle

    found = load_vehicle(MODEL)
    return found.origin.twin() if found.origin.cached else found


STRAIGHT = RouteCase("straight", math.inf, 0.0, 200 / 3.6, None, 1.0, None, "erri_low", 500.0, 0)


@pytest.mark.slow
def test_straight_random_track_wears_the_tread_converged_in_the_step(car):
    """On straight track the steady state wears nothing; the run on ERRI-low alignment at
    200 km/h wears the tread within 15 mm of the taping line.  Its depth at the default
    step 2.5 ms against 1.25 ms: the largest depth within 0.5 % (asserted 1.5 %), the volume
    within 2.7 % (asserted 4 %).  The depth's volume holds the contacts' USFD mass
    (rate x A per metre, mean over the 8 wheels; rounding, asserted 1e-12)."""
    grid = initial_grid(car, 0.1e-3)
    assert not case_depth(car, grid, [])[0].any()
    runs = {dt: random_track_run(car, STRAIGHT, STRAIGHT.speed, dt=dt) for dt in (DT, DT / 2)}
    depth = {dt: case_depth(car, grid, [run])[0] for dt, run in runs.items()}
    fine, default = depth[DT / 2], depth[DT]
    assert default.max() > 0 and abs(grid.y[np.argmax(default)]) < 15e-3
    assert default.max() == pytest.approx(fine.max(), rel=0.015)
    assert default.sum() == pytest.approx(fine.sum(), rel=0.04)
    run = runs[DT]
    assert np.all(run.lateral_rms > 0.5e-3) and np.all(run.lateral_rms < 6e-3)
    out = run.wheel_rail
    mass = float(np.mean(wear_rate_of_contact(out.frictional_power, out.patch_area) * out.patch_area * 1e6)) * 1e-9
    volume = default.sum() * grid.spacing * 2 * math.pi * car.wheelsets[0].r0
    assert volume * WHEEL_STEEL_DENSITY == pytest.approx(mass, rel=1e-12)
