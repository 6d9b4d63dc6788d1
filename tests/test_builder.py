"""Building a model in Python (express.io.builder): the same model as the file.

* The quarter coach of ``examples/elements/quarter-car.toml`` written by hand with the
  builder's calls: the same state-space matrices (to 1e-12 of the largest entry;
  achieved: equal) and parameter values as the file.
* Table-driven over bundled models with bodies, points, elements, pins, gravity and rail:
  each file's items fed through the builder's calls give the file's matrices.
* Mistakes: every problem at once, naming the item; an item added twice; a value that
  is not a number, quantity, string or list.
"""

from __future__ import annotations

import tomllib
from pathlib import Path

import numpy as np
import pytest

from express.base.diagnostics import ArgumentError, ModelError
from express.io import load_model
from express.io.builder import ModelBuilder
from express.numeric.statespace import vehicle_model

ROOT = Path(__file__).resolve().parents[1]


def _same(first, second) -> None:
    assert second.dofs == first.dofs and second.values == pytest.approx(first.values, rel=1e-15)
    for speed in (10.0, 30.0):
        a, b = first.state_matrix(speed), second.state_matrix(speed)
        np.testing.assert_allclose(b, a, rtol=0, atol=1e-12 * max(1.0, float(np.abs(a).max())))


def test_the_quarter_coach_built_by_hand_is_the_files():
    import pint

    unit = pint.UnitRegistry()
    car = ModelBuilder("quarter_car", "Quarter coach: air spring with reservoir, bilinear coil, blow-off damper, "
                                      "bump stop")
    for name, value in (("mc", "10 t"), ("mt", 1200.0), ("p", 450 * unit.kPa), ("A", "0.22 m^2"), ("Vb", "55 L"),
                        ("Vr", "90 L"), ("R", "1.6e6 Pa*s/m^3"), ("ky2", "150 kN/m"), ("kp", "1.1 MN/m"),
                        ("kp2", "2.4 MN/m"), ("dp", "12 mm"), ("cp", "20 kN*s/m"), ("Fp", "3 kN"),
                        ("kstop", "2 MN/m"), ("gstop", "30 mm")):
        car.parameter(name, value)
    car.body("CB", mass="mc", dofs=["z"]).body("T", mass="mt", dofs=["z"]).ground("G")
    for point, body in (("CB1", "CB"), ("T1", "T"), ("G1", "G")):
        car.point(point, body, [0, 0, 0])
    car.element("air", "CB1", "T1", "z", air_spring={
        "gauge_pressure": "p", "area": "A", "bag_volume": "Vb", "reservoir_volume": "Vr", "orifice_resistance": "R",
        "lateral": {"stiffness": "ky2"}})
    car.element("stop", "CB1", "T1", "z", characteristic={"shape": "contact", "stiffness": "kstop", "gap": "gstop"})
    car.element("coil", "T1", "G1", "z", characteristic={"shape": "bilinear", "stiffness": "kp", "knee": "dp",
                                                         "beyond": "kp2"})
    car.element("damper", "T1", "G1", "z", characteristic={"shape": "blow-off", "damping": "cp", "force": "Fp"})
    built = car.build()
    assert [e.id for e in built.elements] == [e.id for e in load_model(ROOT / "examples/elements/quarter-car.toml").elements]
    _same(vehicle_model(load_model(ROOT / "examples/elements/quarter-car.toml")), vehicle_model(built))


_ITEMS = {"bodies": "body", "grounds": "ground", "points": "point", "elements": "element", "pins": "pin"}


def _rebuilt(data: dict) -> ModelBuilder:
    """A file's parsed TOML fed through the builder's calls."""
    info = data["model"]
    builder = ModelBuilder(info["name"], info.get("title", ""))
    for name, value in data.get("parameters", {}).items():
        builder.parameter(name, value)
    for section, keys in data.items():
        if section in ("model", "parameters"):
            continue
        if section not in _ITEMS:
            _sections(builder, section, keys)
            continue
        for item_id, item in keys.items():
            item = dict(item)
            if section == "bodies":
                builder.body(item_id, mass=item.pop("mass"), dofs=item.pop("dofs"), **item)
            elif section == "grounds":
                builder.ground(item_id, **item)
            elif section == "points":
                builder.point(item_id, item["body"], item["offset"])
            elif section == "elements":
                builder.element(item_id, item.pop("from"), item.pop("to"), item.pop("direction"), **item)
            else:
                builder.pin(item_id, item["virtual"], item["non_virtual"])
    return builder


def _sections(builder: ModelBuilder, path: str, keys: dict) -> None:
    values = {k: v for k, v in keys.items() if not (isinstance(v, dict) and _is_section(path, k))}
    builder.section(path, **values)
    for k, v in keys.items():
        if isinstance(v, dict) and _is_section(path, k):
            _sections(builder, f"{path}.{k}", v)


def _is_section(path: str, key: str) -> bool:
    """Whether ``path.key`` is a [section] of these files (else an inline table)."""
    return key not in ("conicity",) and path in ("rail", "rail.wheelset", "rail.outputs", "rail.creep")


@pytest.mark.parametrize("name", ["examples/elements/swing-link.toml", "examples/conventional.toml",
                                  "tests/data/boocock_bogie.toml"])
def test_a_files_items_through_the_builder_give_the_files_model(name):
    path = ROOT / name
    builder = _rebuilt(tomllib.loads(path.read_text(encoding="utf-8")))
    _same(vehicle_model(load_model(path)), vehicle_model(builder.build()))


def test_mistakes_are_told_all_at_once_naming_the_item():
    car = ModelBuilder("bad").parameter("m", "250 kg")
    car.body("B", mass="m", dofs=["z", "q"]).ground("G").point("p", "B", [0, 0, 0]).point("g", "nowhere", [0, 0, 0])
    car.element("s", "p", "g", "z", stiffness="k")
    with pytest.raises(ModelError) as error:
        car.build("built")
    text = "\n".join(error.value.lines())
    assert "body B" in text and "CP g" in text and "nowhere" in text and len(error.value.problems) == 2
    with pytest.raises(ArgumentError, match="added twice"):
        car.body("B", mass="m", dofs=["z"])
    with pytest.raises(ArgumentError, match="parameters.x"):
        ModelBuilder("m").parameter("x", object()).to_toml()
    with pytest.raises(ArgumentError, match="not a finite number"):
        ModelBuilder("m").parameter("x", float("nan")).to_toml()
