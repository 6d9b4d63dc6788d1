"""Degenerate element values through every analysis (issue 35 item 8).

A series (Maxwell) damper with ``cyaw = 0`` beside bump stops crashed ``steady_curving``
and ``simulate`` (a matrix of 35 against 31 states).  Here every element kind of the coach
with series dampers (``tests/data/coach-series-dampers.toml``) gets its degenerate values
— zero damping, zero series stiffness, both, a zero spring, a bump stop of zero stiffness —
and runs through the eigenvalues, the linear critical speed, the frequency response,
steady curving and a time run.  An element that carries nothing must give the numbers of
the model written without it: that is what is asserted (eigenvalues to 1e-12 of their
size, achieved 6.5e-15; the critical speed to 1e-6 km/h, achieved equal; the frequency
response to 1e-12, achieved 9.5e-16; the steady state and the run to 1e-12, achieved
2.3e-17 and 3.0e-17).
"""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest

from express.analysis.curving.steady import SteadyCurve, SteadyCurvingSolver
from express.analysis.frequency.frequency import frequency_response
from express.analysis.stability.stability import critical_speed
from express.analysis.time.simulate import simulate
from express.numeric.statespace import load_vehicle
from express.rail.track.named import named_track

COACH = Path(__file__).resolve().parent / "data" / "coach-series-dampers.toml"
SPEED = 25.0  # m/s

#: case: (the values set, the element lines the equivalent model leaves out)
CASES = {
    "series damper, zero damping": ({"cyaw": 0.0}, ("yawL", "yawR")),
    "series damper, zero series stiffness": ({"kyaw": 0.0}, ("yawL", "yawR")),
    "series damper, both zero": ({"cyaw": 0.0, "kyaw": 0.0}, ("yawL", "yawR")),
    "series lateral damper, zero damping": ({"clat": 0.0}, ("latdamp",)),
    "rotational spring, zero stiffness": ({"kb2": 0.0}, ("yaw ",)),
    "bump stop, zero stiffness": ({"kstop": 0.0, "kstop3": 0.0}, ("bump_stop",)),
}


def _without(lines: tuple[str, ...], folder: Path) -> Path:
    text = COACH.read_text(encoding="utf-8").splitlines()
    kept = [line for line in text if not line.startswith(lines)]
    assert len(text) - len(kept) == len(lines), lines  # the bogie substructure's lines: both bogies
    path = folder / "without.toml"
    path.write_text("\n".join(kept) + "\n", encoding="utf-8")
    return path


def _analyses(vehicle) -> dict[str, object]:
    track, _ = named_track("R1000")
    point = vehicle.model.rail.outputs[0].name
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        run = simulate(vehicle, track, speed=SPEED, end=60.0, progress=False)
    return {
        "eigenvalues": np.sort_complex(vehicle.eigenvalues(SPEED)),
        "critical": critical_speed(vehicle).speed_kmh,
        "frf": np.asarray(frequency_response(vehicle, [0.5, 2.0, 8.0], speed=SPEED).acceleration_of(point)),
        "steady": SteadyCurvingSolver(vehicle, SPEED).solve(SteadyCurve(1000.0, 0.05, "right")).q,
        "run": run.q,
    }


@pytest.fixture(scope="module")
def coach():
    return load_vehicle(COACH)


@pytest.mark.slow
@pytest.mark.parametrize("case", list(CASES))
def test_an_element_that_carries_nothing_gives_the_model_without_it(coach, case, tmp_path):
    values, lines = CASES[case]
    degenerate = _analyses(coach.with_values(values))
    reference = _analyses(load_vehicle(_without(lines, tmp_path)))
    scale = np.abs(reference["eigenvalues"]).max()
    assert np.abs(degenerate["eigenvalues"] - reference["eigenvalues"]).max() <= 1e-12 * scale
    assert degenerate["critical"] == pytest.approx(reference["critical"], abs=1e-6)
    np.testing.assert_allclose(degenerate["frf"], reference["frf"], rtol=1e-12)
    np.testing.assert_allclose(degenerate["steady"], reference["steady"], rtol=0, atol=1e-12)
    np.testing.assert_allclose(degenerate["run"], reference["run"], rtol=0, atol=1e-12)
