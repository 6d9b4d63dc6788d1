"""Every result is data (issue 35, item 2): each result record the library returns has
``to_xarray()`` (labelled dimensions, CF-style ``units`` and ``long_name`` on every
variable), ``to_pandas()``, a short ``repr`` and a notebook ``_repr_html_``; the linear
and the nonlinear critical speed are records with ``found`` and ``reason`` also when
nothing is found; the old output names (``Q1`` for a lateral force, ``max_QP``) are
refused with the new name.

The numbers in the datasets are the records' own (compared exactly: the same arrays).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import express
from cli_support import CONVENTIONAL, EXAMPLES, STEERED

#: Longest text repr accepted [characters]: a few lines (EquationsOfMotion's was 100 kB).
REPR_LIMIT = 600


@pytest.fixture(scope="module")
def car():
    return express.load_vehicle(CONVENTIONAL)


@pytest.fixture(scope="module")
def coach():
    return express.load_vehicle(str(EXAMPLES / "manchester.toml"))


def _eigen(car, coach):
    return express.eigen(car, 30.0)


def _critical(car, coach):
    return express.critical_speed(car)


def _stable(car, coach):
    return express.critical_speed(car, v_max=40.0)


def _frf(car, coach):
    return express.frequency_response(car, [0.5, 1.0, 2.0])


def _ground(car, coach):
    return express.ground_response(coach, [0.5, 1.0, 2.0])


def _track(car, coach):
    from express.analysis.frequency.track_response import track_frequency_response

    return track_frequency_response(coach, [0.5, 1.0, 2.0], components=["vertical"])


def _ride(car, coach):
    from express.analysis.ride.vehicle import track_class_spectra

    return express.ride_response(coach, track_class_spectra("FRA4"), frequencies=np.linspace(0.5, 20.0, 12))


def _curving(car, coach):
    from express.analysis.curving.steady import SteadyCurve

    return express.steady_curving(car, [SteadyCurve(600.0, 0.15)], speeds=30.0)[0]


def _simulate(car, coach):
    return express.simulate(car, express.load_track("R1000"), dt=0.01, progress=False, end=20.0)


def _sensitivity(car, coach):
    from express.analysis.study.sensitivity import critical_speed_sensitivity

    return critical_speed_sensitivity(car, ["Gamma", "kx1"])


def _study_table(car, coach):
    from express.analysis.study.results import ResultTable

    table = ResultTable.empty(["kx1"], {"kx1": "N/m", "critical_speed": "m/s"}, ["critical_speed"], 2)
    table.add({"point": 0, "values": [1e6], "outputs": [100.0]})
    table.add({"point": 1, "values": [2e6], "outputs": [None], "error": "stable up to v_max"})
    return table


def _study_summary(car, coach):
    from pathlib import Path

    from express.analysis.study.run import StudySummary

    return StudySummary(Path("results.csv"), 2, 2, 1, 0.5, 1, {}, _study_table(car, coach))


def _settled(car, coach):
    from express.analysis.curving.settled import SettledCurving
    from express.analysis.curving.steady import SteadyCurve

    return SettledCurving(SteadyCurve(400.0, 0.1), 25.0, "no equilibrium found", {"Y1L": 2.5e4, "aoa1": 4e-3, "YQ1L": 0.3},
                          {"Y1L": 1.2e3, "aoa1": 1e-4, "YQ1L": 0.01}, (600.0, 700.0), 0.005)


def _wear(car, coach):
    from pathlib import Path

    from express.analysis.wear.prediction import UNITS, WearPrediction

    first = {name: 0.0 for name in UNITS} | {"critical_speed": None}
    second = {name: 1.0 for name in UNITS} | {"step": 1, "distance": 5e4, "critical_speed": 60.0}
    return WearPrediction([first, second], Path("wear"), False, 1)


#: kind -> (builder, dimensions of to_xarray(), a variable and its unit, rows of to_pandas():
#: a number, a dimension's size, or None for the product of the dimensions)
RECORDS = {
    "eigen": (_eigen, {"mode"}, ("frequency", "Hz"), None),
    "critical speed": (_critical, set(), ("speed", "m/s"), 1),
    "critical speed, stable": (_stable, set(), ("speed", "m/s"), 1),
    "frequency response": (_frf, {"frequency", "dof", "point", "wheelset"}, ("output", "m"), 3),
    "ground response": (_ground, {"frequency", "dof", "input"}, ("H", None), None),
    "track response": (_track, {"frequency", "output", "input"}, ("amplitude", None), None),
    "ride": (_ride, {"frequency", "output", "component"}, ("input_psd", "m^2/Hz"), 12),
    "steady curving": (_curving, {"wheelset", "side", "dof"}, ("Y", "N"), 1),
    "time history": (_simulate, {"time", "dof"}, ("q", None), "time"),
    "sensitivity": (_sensitivity, {"parameter"}, ("elasticity", "1"), None),
    "study table": (_study_table, {"point"}, ("critical_speed", "m/s"), None),
    "study": (_study_summary, {"point"}, ("kx1", "N/m"), None),
    "settled curving": (_settled, {"statistic"}, ("Y1L", "N"), 2),
    "wear prediction": (_wear, {"step"}, ("distance", "m"), "step"),
}


@pytest.fixture(scope="module")
def records(car, coach):
    return {kind: builder(car, coach) for kind, (builder, *_rest) in RECORDS.items()}


@pytest.mark.parametrize("kind", list(RECORDS))
def test_every_record_is_data(records, kind):
    _builder, dims, (name, unit), rows = RECORDS[kind]
    record = records[kind]
    dataset = record.to_xarray()
    assert set(dataset.dims) == dims
    for variable in dataset.data_vars.values():  # CF-style attributes on every variable
        assert "units" in variable.attrs and variable.attrs.get("long_name"), (kind, variable.name)
    if unit is not None:
        assert dataset[name].attrs["units"] == unit
    frame = record.to_pandas()
    expected = (dataset.sizes[rows] if isinstance(rows, str) else rows if rows is not None
                else int(np.prod([dataset.sizes[d] for d in dims])))
    assert frame.shape[0] == expected, kind
    assert any("[" in str(column) for column in frame.columns) or "amplitude" in frame.columns, kind  # units
    text = repr(record)
    assert text.startswith(f"<{type(record).__name__}") and len(text) <= REPR_LIMIT and text.count("\n") <= 6
    assert "<" in record._repr_html_()


def test_the_datasets_hold_the_records_numbers(records):
    eigen = records["eigen"].to_xarray()
    np.testing.assert_array_equal(eigen["real"].values, [m.real for m in records["eigen"].modes])
    run = records["time history"]
    history = run.to_xarray()
    np.testing.assert_array_equal(history["q"].values, run.q)
    np.testing.assert_array_equal(history["distance"].values, run.distance)
    assert history["Y1"].attrs["units"] == "N" and history["psi_TW1"].attrs["units"] == "rad"
    assert list(history["dof_units"].values[:2]) == ["m", "m"]
    frame = run.to_pandas()
    np.testing.assert_array_equal(frame["Y1 [N]"].to_numpy(), run.outputs["Y1"])
    assert frame.index.name == "time [s]"
    curve = records["steady curving"]
    data = curve.to_xarray()
    np.testing.assert_array_equal(data["Q"].values, curve.wheel_rail.vertical_load[0])
    assert curve.to_pandas()["YQ1L [-]" if "YQ1L [-]" in curve.to_pandas() else "YQ1L"].iloc[0] == \
        curve.columns()["YQ1L"]
    frf = records["frequency response"]
    np.testing.assert_array_equal(frf.to_xarray()["output"].sel(point="floor_front").values,
                                  frf.outputs["floor_front"])


def test_critical_speed_is_a_record_with_its_reason(records, car):
    found, stable = records["critical speed"], records["critical speed, stable"]
    assert found.found and found.reason == "crossing" and not found.stable
    assert found.v_min == 1.0 and found.v_max == 150.0
    assert not stable.found and stable.stable and stable.reason == "stable up to v_max"
    assert math.isnan(stable.speed) and math.isnan(stable.speed_kmh) and stable.v_max == 40.0
    assert stable.mode.real < 0  # the least stable mode at the search limit, still decaying
    assert stable.as_dict() == {"critical_speed": None, "critical_speed_kmh": None, "mode": None,
                                "frequency_hz": None, "unstable_at_min": False}
    assert stable.to_xarray().attrs["reason"] == "stable up to v_max"
    low = express.critical_speed(express.load_vehicle(STEERED), v_min=120.0, v_max=150.0)
    assert low.found and low.unstable_at_min and low.reason == "unstable at v_min"


def test_nonlinear_critical_speed_has_found_and_reason():
    from express.analysis.stability.nonlinear_stability import BifurcationPoint, NonlinearCriticalSpeed

    none = NonlinearCriticalSpeed(None, (math.nan, math.nan), (BifurcationPoint(50.0, 1e-5, 2e-5, False),), None,
                                  "W1", "dead-band", {"dt": 0.005, "tolerance": 0.1, "v_start": 50.0})
    assert not none.found and none.reason == "no limit cycle at v_start"
    data = none.to_xarray()
    assert data.sizes["run"] == 1 and math.isnan(float(data["critical_speed"])) and data.attrs["found"] == 0
    assert data["amplitude"].attrs["units"] == "m" and len(repr(none)) <= REPR_LIMIT


def test_equations_repr_is_short():
    result = express.generate(express.load_model(STEERED))
    for record in (result, result.equations):
        text = repr(record)
        assert len(text) <= REPR_LIMIT and text.count("\n") <= 7, text
    assert "DOFs" in repr(result.equations)


def test_old_dead_band_names_are_refused_with_the_new_one(records):
    from express.analysis.time.output_names import RenamedOutputError, renamed_output

    run = records["time history"]
    assert {"Y1", "YQ1", "Ytot1"} <= set(run.outputs) and not {"Q1", "QP1", "Qtot1"} & set(run.outputs)
    with pytest.raises(RenamedOutputError, match="'Q1' is now called 'Y1'"):
        run.outputs["Q1"]
    with pytest.raises(KeyError):  # a KeyError too, as a dict's
        run.outputs["QP2"]
    with pytest.raises(RenamedOutputError, match="'Qtot1' is now called 'Ytot1'"):
        run.max_abs()["Qtot1"]
    assert renamed_output("Qtot3") == "Ytot3" and renamed_output("Q1L") is None
    with pytest.raises(KeyError) as error:
        run.outputs["nothing"]
    assert not isinstance(error.value, RenamedOutputError)


def test_old_study_output_names_are_refused_with_the_new_one(tmp_path):
    from express.analysis.study.spec import parse_study
    from express.base.diagnostics import InputError

    text = (f'[study]\nmodel = "{CONVENTIONAL}"\nkind = "grid"\noutputs = ["max_QP", "max_Q"]\n'
            '[study.parameters]\nGamma = { values = [0.1] }\n')
    path = tmp_path / "old.toml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(InputError) as error:
        parse_study(text, path)
    message = str(error.value)
    assert "'max_QP' is now called 'max_YQ'" in message and "'max_Q' is now called 'max_Y'" in message


def test_the_settled_run_wear_and_plant_hold_their_numbers(records, car):
    """The datasets of the settled run, the wear prediction and the control plant hold
    the records' own numbers (exactly), a missing critical speed as nan."""
    from express.export.plant import linear_system

    settled = records["settled curving"].to_xarray()
    assert settled["aoa1"].sel(statistic="amplitude").item() == 1e-4 and settled["aoa1"].attrs["units"] == "rad"
    assert settled["YQ1L"].attrs["units"] == "1" and settled.attrs["reason"] == "no equilibrium found"
    assert records["settled curving"].to_pandas()["Y1L [N]"].tolist() == [2.5e4, 1.2e3]
    wear = records["wear prediction"].to_xarray()
    assert math.isnan(wear["critical_speed"].values[0]) and wear["critical_speed"].values[1] == 60.0
    assert wear["critical_speed"].attrs["units"] == "m/s" and records["wear prediction"].to_pandas().index.name == "step"
    plant = linear_system(car, 30.0)
    data = plant.to_xarray()
    np.testing.assert_array_equal(data["A"].values, plant.A)
    np.testing.assert_array_equal(data["B"].sel(input=plant.inputs[0]).values, plant.B[:, 0])
    assert set(data.dims) == {"state", "from_state", "input", "output"} and data["speed"].attrs["units"] == "m/s"
    table = plant.to_pandas()
    assert len(table) == sum(np.count_nonzero(m) for m in (plant.A, plant.B, plant.C, plant.D))
    row = table[(table["matrix"] == "A")].iloc[0]
    i, j = plant.states.index(row["row"]), plant.states.index(row["column"])
    assert plant.A[i, j] == row["value [SI]"]
    for record in (plant, records["settled curving"], records["wear prediction"]):
        assert len(repr(record)) <= REPR_LIMIT and repr(record).startswith(f"<{type(record).__name__}")
