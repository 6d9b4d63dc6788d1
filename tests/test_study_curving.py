"""Curving in studies (issue 35, item 3): the EN 14363 quantities of a track run and the
steady-curving quantities as study outputs, each the number the library (and so the
command line) gives at that point; a bundled track by its name in a study file."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from express.analysis.curving.assessment import assess_run
from express.analysis.curving.steady import SteadyCurve, steady_curving
from express.analysis.study.results import read_table
from express.analysis.study.run import run_study
from express.analysis.study.spec import read_study
from express.analysis.time.simulate import simulate
from express.numeric.statespace import load_vehicle
from express.rail.track import load_track

ROOT = Path(__file__).resolve().parents[1]
MODEL = ROOT / "examples" / "forced-steering.toml"
OUTPUTS = ["max_YQ2m", "max_SY2m", "max_dQQ0", "max_aoa", "max_Tgamma", "steady_aoa", "steady_YQ", "steady_SY",
           "step_dt", "step_error"]


@pytest.mark.slow
def test_curving_outputs_of_a_study_are_the_librarys(tmp_path):
    """Two points (kx1 1 and 4 MN/m) along the bundled R400 at 95 km/h and in a steady
    R 500 m curve with 100 mm cant: every output equal to the library's own run of the
    point at the step the study's step check chose (to 1e-12 relative: the same
    computation), and that step converged: every criterion within 1 % of its limit of
    the run at twice the step."""
    study = tmp_path / "study.toml"
    study.write_text(f'[study]\nmodel = "{MODEL}"\nkind = "grid"\noutputs = {OUTPUTS!r}\n'.replace("'", '"')
                     + '[study.parameters]\nkx1 = { values = ["1 MN/m", "4 MN/m"] }\n'
                     + '[study.options]\ntrack = "R400"\nspeed = "95 km/h"\ncurve_radius = "500 m"\n'
                     + 'curve_cant = "100 mm"\n')
    output = tmp_path / "curving.csv"
    run_study(read_study(study), output, workers=1)
    table = read_table(output)
    track = load_track("R400")
    base = load_vehicle(str(MODEL))
    for row, kx1 in enumerate((1e6, 4e6)):
        vehicle = base.with_values({"kx1": kx1})
        assert table["step_error"][row] <= 0.01 and table["step_dt"][row] in (0.005, 0.0025, 0.00125, 0.000625)
        run = simulate(vehicle, track, speed=95 / 3.6, dt=table["step_dt"][row], progress=False)
        outputs, assessment = assess_run(vehicle, track, run)
        criteria = {c.name: c.value for c in assessment.criteria}
        steady = steady_curving(vehicle, SteadyCurve(500.0, 0.1), speeds=95 / 3.6)[0].wheel_rail
        expected = {
            "max_YQ2m": max(v for k, v in criteria.items() if k.startswith("YQ") and not k.endswith("_nadal")),
            "max_SY2m": max(v for k, v in criteria.items() if k.startswith("SY") and not k.endswith("_rms")),
            "max_dQQ0": criteria["dQQ0"], "max_aoa": float(np.max(np.abs(outputs.angle_of_attack))),
            "steady_aoa": float(steady.angle_of_attack[0, 0]), "steady_YQ": float(np.max(steady.y_over_q)),
            "steady_SY": float(np.max(np.abs(steady.track_shift_force))),
        }
        for name, value in expected.items():
            assert table[name][row] == pytest.approx(value, rel=1e-12), name
        assert np.isnan(table["max_Tgamma"][row])  # the dead-band contact has no frictional power
    assert table["max_SY2m"][0] != table["max_SY2m"][1]  # the parameter moves it


def test_a_study_without_the_step_check_runs_at_its_step(tmp_path):
    """``step_check = false``: the track run at ``dt`` alone (step_dt = dt, step_error 0),
    its outputs the library's run at that step (1e-12); a non-boolean is refused."""
    from express.base.diagnostics import InputError

    study = tmp_path / "study.toml"
    study.write_text(f'[study]\nmodel = "{MODEL}"\nkind = "grid"\noutputs = ["max_SY2m", "step_dt", "step_error"]\n'
                     '[study.parameters]\nkx1 = { values = ["1 MN/m"] }\n'
                     '[study.options]\ntrack = "R400"\nspeed = "95 km/h"\ndt = "4 ms"\nstep_check = false\n')
    output = tmp_path / "out.csv"
    run_study(read_study(study), output, workers=1)
    table = read_table(output)
    assert table["step_dt"][0] == 0.004 and table["step_error"][0] == 0.0
    vehicle = load_vehicle(str(MODEL)).with_values({"kx1": 1e6})
    track = load_track("R400")
    run = simulate(vehicle, track, speed=95 / 3.6, dt=0.004, progress=False)
    criteria = {c.name: c.value for c in assess_run(vehicle, track, run)[1].criteria}
    expected = max(v for k, v in criteria.items() if k.startswith("SY") and not k.endswith("_rms"))
    assert table["max_SY2m"][0] == pytest.approx(expected, rel=1e-12)
    study.write_text(study.read_text().replace("step_check = false", 'step_check = "no"'))
    with pytest.raises(InputError, match="step_check.*must be true or false"):
        read_study(study)


def test_a_bundled_track_by_its_name_and_a_wrong_one(tmp_path):
    from express.base.diagnostics import InputError

    good = tmp_path / "good.toml"
    good.write_text(f'[study]\nmodel = "{MODEL}"\nkind = "grid"\noutputs = ["max_Y"]\n'
                    '[study.parameters]\nkx1 = { values = [1e6, 2e6] }\n[study.options]\ntrack = "R400"\n')
    assert read_study(good).settings.track == "R400"
    bad = tmp_path / "bad.toml"
    bad.write_text(good.read_text().replace('track = "R400"', 'track = "R401"'))
    with pytest.raises(InputError, match="no such track file or bundled track: 'R401'.*R400"):
        read_study(bad)
