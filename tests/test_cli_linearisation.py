"""``--linearisation`` on the commands and ``linearisation`` in studies (issue 31, item 6):
the command line gives the library's equivalent vehicle, says which linearisation it used,
refuses what does not fit; the eigenvalue sensitivities of an equivalent vehicle against
central differences; the study option against the library.

The coach (``examples/coach-blowoff.toml``) has four blow-off yaw dampers, 600 kN s/m up to
12 kN.  At 10 mm and 1 Hz their velocity amplitude, 62.8 mm/s, is beyond the blow-off
(20 mm/s): the describing function of the saturation,
``c_eq = c (2/pi) (asin r + r sqrt(1 - r^2))`` with ``r = F / (c w X)``, is the closed form.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from cli_support import EXAMPLES, run
from express.analysis.study.results import read_table
from express.analysis.study.run import run_study
from express.analysis.study.sensitivity import eigenvalue_derivatives
from express.analysis.study.spec import read_study
from express.base.diagnostics import ModelError
from express.cli.common import LINEARISATIONS
from express.forces.linearisation import KINDS, Linearisation, linearised
from express.io import parse_toml_model
from express.numeric.statespace import load_vehicle, vehicle_model
from tests.test_forces_friction import MODEL as SLIDER

COACH = EXAMPLES / "coach-blowoff.toml"
C_YAW, F_YAW, X, FREQUENCY = 600e3, 12e3, 0.010, 1.0  # the coach's yaw dampers; the amplitude and frequency asked


def _saturation_damping(c: float, force: float, amplitude: float, frequency: float) -> float:
    """The describing function of ``F = c v`` saturated at ``force`` for ``v = V cos``."""
    r = force / (c * 2 * math.pi * frequency * amplitude)
    if r >= 1:
        return c
    return c * 2 / math.pi * (math.asin(r) + r * math.sqrt(1 - r * r))


def test_the_command_line_offers_the_librarys_linearisations():
    assert LINEARISATIONS == KINDS


@pytest.mark.slow
def test_eigen_with_the_equivalent_linearisation_is_the_librarys_vehicle(capsys):
    """``express eigen --linearisation equivalent`` gives the eigenvalues of the library's
    ``linearised`` vehicle (to 1e-12 of the largest magnitude: the same matrices, one
    eigensolver) and says each damper's ``c_eq``, the closed form's to 6 digits."""
    status, out, err = run(capsys, "eigen", COACH, "--linearisation", "equivalent", "--element-amplitude", "10",
                           "--element-frequency", "1", "--json")
    assert status == 0, err
    summary = json.loads(out)
    expected = _saturation_damping(C_YAW, F_YAW, X, FREQUENCY)
    assert expected == pytest.approx(0.3983 * C_YAW, rel=1e-3)  # r = 0.318: the damper gives 40 %
    assert set(summary["linearisation"]) == {"T1_ydL", "T1_ydR", "T2_ydL", "T2_ydR"}
    for text in summary["linearisation"].values():
        assert text.startswith("equivalent (describing functions) at amplitude 10 mm")
        assert f"c_eq {expected:.6g} N s/m" in text and "tangent c 600000 N s/m in C" in text
    assert "nonlinear elements seen by this linear analysis as equivalent" in err and "T1_ydL (and 3 alike)" in err
    vehicle = linearised(load_vehicle(COACH), Linearisation("equivalent", amplitude=X, frequency=FREQUENCY))
    library = np.linalg.eigvals(vehicle.state_matrix(summary["speed"]))
    found = np.array(summary["eigenvalues"]).view(complex).ravel()
    scale = np.abs(library).max()
    assert found.size == library.size
    assert np.abs(np.sort_complex(found) - np.sort_complex(library)).max() < 1e-12 * scale


@pytest.mark.parametrize("argv, words", [
    (["eigen", COACH, "--element-amplitude", "2"], "--element-amplitude: the amplitude and frequency of --linearisation equivalent"),
    (["frf", COACH, "--linearisation", "tangent", "--element-frequency", "2"], "--element-frequency"),
    (["eigen", COACH, "--linearisation", "statistical"], "invalid choice: 'statistical'"),
    (["critical-speed", COACH, "--nonlinear", "--linearisation", "equivalent"], "--nonlinear marches the whole nonlinear elements"),
    (["eigen", COACH, "--linearisation", "equivalent", "--element-amplitude", "-1"], "element-amplitude"),
])
def test_linearisation_options_that_do_not_fit_are_usage_errors(capsys, tmp_path, argv, words):
    status, out, err = run(capsys, *argv)
    assert status == 2 and words in err and out == ""


@pytest.mark.slow
def test_ride_with_the_statistical_linearisation_says_its_fixed_point(capsys):
    """The wagon's friction elements at their rms levels: the run says it converged and
    each element its statistical equivalent, where the tangent run says stuck or tangent,
    for the same elements."""
    wagon = EXAMPLES / "y25-wagon.toml"
    common = ["ride", wagon, "--track", "ERRI-high", "--speed", "80", "--points", "400", "--json"]
    status, out, err = run(capsys, *common, "--linearisation", "statistical")
    assert status == 0, err
    statistical = json.loads(out)
    assert "statistical linearisation: the levels changed by" in err
    assert statistical["linearisation"] and all(t.startswith("statistical") for t in statistical["linearisation"].values())
    status, out, err = run(capsys, *common)
    tangent = json.loads(out)
    assert all(t.startswith(("stuck", "tangent")) for t in tangent["linearisation"].values())
    assert statistical["linearisation"].keys() == tangent["linearisation"].keys()


def _slider(limit: str = "200 N"):
    text = SLIDER.format(ks="40 MN/m").replace('F = "200 N"', f'F = "{limit}"')
    return vehicle_model(parse_toml_model(text, "slider.toml"))


def test_the_sensitivity_of_an_equivalent_vehicle_includes_its_describing_function():
    """d lambda / dF of the slider seen at 20 mm, 3 Hz (slipping: F/ks = 5 um; the mode
    underdamped, zeta ~ 0.17): the equivalent branch's change with the limit is part of
    the derivative.  Against central differences of the eigenvalues of the re-linearised
    vehicle (outer step 1e-3 F, not the derivative's own 1e-4): achieved 3.2e-9 relative
    (1.4e-8 at 1e-5 F, rounding); asserted 5e-8; and zero for the tangent vehicle, whose
    matrices do not hold F."""
    seen = linearised(_slider(), Linearisation("equivalent", amplitude="20 mm", frequency="3 Hz"))
    eigenvalues, rates = eigenvalue_derivatives(seen, 1.0, ["F", "k"])
    k = int(np.argmax(eigenvalues.imag))
    step = 1e-3 * 200.0
    ends = [np.linalg.eigvals(seen.with_values({"F": 200.0 + h}).state_matrix(1.0)) for h in (step, -step)]
    expected = (ends[0][np.argmax(ends[0].imag)] - ends[1][np.argmax(ends[1].imag)]) / (2 * step)
    assert eigenvalues[k].imag > 0 and abs(expected) > 0
    assert abs(rates["F"][k] - expected) <= 5e-8 * abs(expected)
    _, tangent_rates = eigenvalue_derivatives(_slider(), 1.0, ["F"])
    assert np.all(tangent_rates["F"] == 0)


STUDY = """\
[study]
model = "{model}"
kind = "grid"
outputs = ["least_damping_ratio"]
[study.parameters]
Fyd = {{ values = ["6 kN", "12 kN"] }}
[study.options]
speed = "150 km/h"
linearisation = "{kind}"
element_amplitude = "10 mm"
element_frequency = "1 Hz"
"""


@pytest.mark.slow
def test_a_studys_equivalent_linearisation_is_the_librarys(tmp_path):
    """Each point's least damping ratio against the library's linearised coach with that
    blow-off force (1e-12: the same matrices); the two blow-off forces differ (c_eq
    0.20 c and 0.40 c at 10 mm, 1 Hz)."""
    path = tmp_path / "study.toml"
    path.write_text(STUDY.format(model=COACH.as_posix(), kind="equivalent"), encoding="utf-8")
    run_study(read_study(path), tmp_path / "out.csv", workers=1)
    table = read_table(tmp_path / "out.csv")
    base = load_vehicle(COACH)
    spec = Linearisation("equivalent", amplitude=X, frequency=FREQUENCY)
    for force, found in zip((6e3, 12e3), table["least_damping_ratio"], strict=True):
        lam = np.linalg.eigvals(linearised(base.with_values({"Fyd": force}), spec).state_matrix(150 / 3.6))
        keep = np.abs(lam) > 1e-9
        assert found == pytest.approx(float(np.min(-lam.real[keep] / np.abs(lam[keep]))), rel=1e-12)
    assert table["least_damping_ratio"][0] != table["least_damping_ratio"][1]


def test_a_study_refuses_the_equivalent_linearisation_with_a_time_run_output(tmp_path):
    path = tmp_path / "study.toml"
    path.write_text(STUDY.format(model=COACH.as_posix(), kind="equivalent").replace(
        '["least_damping_ratio"]', '["least_damping_ratio", "max_Y"]'), encoding="utf-8")
    with pytest.raises(ModelError) as info:
        read_study(path)
    assert "the equivalent linearisation is of the linear outputs; max_Y march the whole" in str(info.value)
