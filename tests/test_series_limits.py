"""Limits of series (Maxwell) elements (issue 25 item 5).

A series element with zero damping or zero stiffness transmits no force: the vehicle
equals the model without the element (its stroke leaves the coordinates); with infinite
damping the damper locks and the element is its spring alone.  Checked on the
37-coordinate coach with series yaw and lateral dampers against models written without
the elements (or with plain springs), through ``with_values`` as studies use it, and on
the command line.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from express.assembly.first_order import series_limits
from express.cli import main
from express.io import parse_toml_model
from express.numeric.statespace import vehicle_model

ROOT = Path(__file__).resolve().parents[1]
COACH = ROOT / "tests" / "data" / "coach-series-dampers.toml"
YAW = ("yawL = {", "yawR = {")


def _coach(text_change=None):
    text = COACH.read_text()
    if text_change is not None:
        text = "\n".join(text_change(line) for line in text.splitlines())
    return vehicle_model(parse_toml_model(text, str(COACH)))


def _without_yaw_dampers(line):
    return "" if line.startswith(YAW) else line


def _plain_yaw_springs(line):
    if line.startswith(YAW):
        return line.replace(', damping = "cyaw", series = true', "")
    return line


def _eigenvalues(vehicle):
    values = np.linalg.eigvals(vehicle.state_matrix(vehicle.speed))
    return np.sort_complex(values)


@pytest.fixture(scope="module")
def coach():
    return _coach()


@pytest.mark.parametrize("change", [{"cyaw": 0.0}, {"kyaw": 0.0}, {"cyaw": "0 kN*s/m"}])
def test_a_series_element_without_damping_or_stiffness_is_no_element(coach, change):
    reference = _coach(_without_yaw_dampers)
    vehicle = coach.with_values(change)
    assert vehicle.n == reference.n == coach.n - 4
    assert set(coach.dofs) - set(vehicle.dofs) == {"T1_yawL.stroke", "T1_yawR.stroke", "T2_yawL.stroke",
                                                   "T2_yawR.stroke"}
    for name in ("mass", "stiffness", "damping_base", "damping_creep", "forcing_base", "forcing_rate_matrix"):
        np.testing.assert_allclose(getattr(vehicle, name), getattr(reference, name), rtol=1e-12, atol=1e-6,
                                   err_msg=name)
    np.testing.assert_allclose(_eigenvalues(vehicle), _eigenvalues(reference), rtol=1e-12)  # achieved 0 to 3e-15


def test_an_infinite_damper_locks_and_leaves_the_spring(coach):
    reference = _coach(_plain_yaw_springs)
    vehicle = coach.with_values({"cyaw": "inf"})
    assert vehicle.n == reference.n == coach.n - 4
    np.testing.assert_allclose(vehicle.stiffness, reference.stiffness, rtol=1e-12, atol=1e-6)
    np.testing.assert_allclose(_eigenvalues(vehicle), _eigenvalues(reference), rtol=1e-12)  # achieved 0 to 3e-15
    # and the limit is approached: a damper 1e6 times stiffer than the yaw damper is
    # already within 1e-7 (relative, of the largest eigenvalue; achieved 1.2e-8) of the locked one
    stiff = coach.with_values({"cyaw": 3e11})
    locked = _eigenvalues(reference)
    nearly = np.linalg.eigvals(stiff.state_matrix(stiff.speed))
    nearly = nearly[np.abs(nearly) < 1e5]  # without the stroke's own decay rate -k/c ... fast
    scale = np.abs(locked).max()
    for value in locked:
        assert np.min(np.abs(nearly - value)) <= 1e-7 * scale


def test_a_study_across_the_limits_works(coach):
    """A sweep of the yaw damping from 0 through finite values to infinity (as a study
    does, by with_values) gives a stable vehicle at every point."""
    for value in (0.0, 1e4, 3e5, 1e7, "inf"):
        vehicle = coach.with_values({"cyaw": value})
        assert np.all(np.real(_eigenvalues(vehicle)) < 0), value


@pytest.mark.parametrize("value", ["0", "inf"])
def test_the_command_line_accepts_the_limits(capsys, value):
    assert main(["eigen", str(COACH), "--set", f"cyaw={value}"]) == 0
    out = capsys.readouterr().out
    assert "T1_yawL" not in out


def test_infinite_damping_is_refused_for_a_plain_damper(capsys):
    assert main(["eigen", str(ROOT / "examples" / "conventional.toml"), "--set", "cy1=inf"]) == 2
    assert "outside the valid range" in capsys.readouterr().err


def test_condensing_a_stroke_without_damping_removes_the_element_stiffness():
    """Mass on k0 and a series (k, c = 0) element, with a ground input u on the
    element's far end: K~ = k0 and P~ = 0 (no force passes)."""
    k0, k = 5.0, 3.0
    mass = np.diag([2.0, 0.0])
    stiffness = np.array([[k0 + k, -k], [-k, k]])
    forcing = np.array([[k], [-k]])  # V = k/2 (x - u - s)^2: P = -dV/dq at q = 0 per unit u
    limits = series_limits(["B.x", "e.stroke"], mass, np.zeros((2, 2)), np.zeros((2, 2)), stiffness,
                           forcing, np.zeros((2, 1)), np.zeros((2, 1)))
    assert limits.removed == ("e.stroke",)
    np.testing.assert_allclose(limits.matrices[3], [[k0]])
    np.testing.assert_allclose(limits.matrices[4], [[0.0]], atol=1e-15)
