"""The wheel/rail output record of curving results (express.analysis.curving.outputs)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from express.analysis.curving.outputs import FLANGE_CONTACT_ANGLE, WheelRailOutputs, column_unit


def _record(**changes):
    base = {
        "vertical_load": np.array([[[60e3, 40e3], [52e3, 48e3]]]),
        "lateral_force": np.array([[[-30e3, 5e3], [-4e3, 3e3]]]),
        "longitudinal_force": np.array([[[2e3, -2e3], [0.0, 0.0]]]),
        "contact_position": np.array([[[0.008, 0.008], [0.002, 0.002]]]),
        "contact_angle": np.array([[[math.radians(60), math.radians(3)], [math.radians(5), math.radians(4)]]]),
        "angle_of_attack": np.array([[0.004, -0.001]]),
        "static_load": np.array([50e3, 50e3]),
    }
    base.update(changes)
    return WheelRailOutputs(**base)


def test_quantities_follow_their_definitions():
    out = _record()
    # the outer left wheel of wheelset 1 is pushed to the right by its rail: guiding force +30 kN
    assert out.y_over_q[0, 0, 0] == pytest.approx(0.5)
    assert out.y_over_q[0, 0, 1] == pytest.approx(5e3 / 40e3)
    assert out.track_shift_force[0].tolist() == [-25e3, -1e3]
    assert out.flange_contact[0].tolist() == [[True, False], [False, False]]
    assert out.vehicle_unloading[0] == pytest.approx(0.2)  # 40 kN on a 50 kN wheel


def test_columns_have_units_and_a_fixed_order():
    out = _record()
    columns = out.columns()
    assert list(columns)[:3] == ["Q1L", "Q1R", "Y1L"]
    assert {"YQ2R", "Fx1L", "u2L", "gamma1R", "flanging1L", "SY1", "aoa2", "dQQ0"} <= set(columns)
    assert not [name for name in columns if name.startswith("flange")]
    units = out.units()
    assert (units["Q1L"], units["YQ1L"], units["gamma2R"], units["aoa1"], units["u1L"], units["SY2"]) == (
        "N", "", "rad", "rad", "m", "N")
    assert columns["flanging1L"].tolist() == [1.0]
    with pytest.raises(KeyError):
        column_unit("nonsense")


def test_flange_threshold_is_documented_value():
    assert math.degrees(FLANGE_CONTACT_ANGLE) == pytest.approx(30.0)


@pytest.mark.parametrize(("field", "value", "match"), [
    ("lateral_force", np.zeros((1, 2, 3)), "shape"),
    ("angle_of_attack", np.zeros((1, 3)), "angle_of_attack"),
    ("static_load", np.array([50e3, 0.0]), "static_load"),
])
def test_bad_shapes_are_refused(field, value, match):
    with pytest.raises(ValueError, match=match):
        _record(**{field: value})


def test_energy_columns_come_with_the_frictional_power():
    """Tgamma, the USFD wear rate at Tgamma / A and Burstow's index per wheel, after the
    other columns, with units; none without the frictional power (the dead-band model)."""
    assert not [name for name in _record().columns() if name.startswith(("Tgamma", "wear", "rcf"))]
    power = np.array([[[100.0, 40.0], [5.0, 0.0]]])
    area = np.array([[[20e-6, 40e-6], [50e-6, 0.0]]])  # 20, 40, 50 mm^2 and a lifted wheel's none
    out = _record(frictional_power=power, patch_area=area)
    columns, units = out.columns(), out.units()
    assert list(columns)[-12:-9] == ["Tgamma1L", "Tgamma1R", "wear1L"]
    assert columns["wear1L"].tolist() == pytest.approx([26.5], rel=1e-15)  # 100 N / 20 mm^2 = 5 N/mm^2, mild: 5.3 x 5
    assert columns["wear1R"].tolist() == pytest.approx([5.3 * 1.0])  # 40 N / 40 mm^2
    assert columns["wear2R"].tolist() == [0.0]
    assert columns["rcf1L"].tolist() == pytest.approx([1e-5 * (175 - 100) / 110], rel=1e-12)
    assert columns["rcf2L"].tolist() == [0.0]
    assert (units["Tgamma1L"], units["wear2R"], units["rcf1R"]) == ("N", "ug/m/mm^2", "")


def test_frictional_power_and_area_come_together():
    with pytest.raises(ValueError, match="together"):
        _record(frictional_power=np.zeros((1, 2, 2)))
    with pytest.raises(ValueError, match="shape"):
        _record(frictional_power=np.zeros((1, 2, 3)), patch_area=np.zeros((1, 2, 3)))
