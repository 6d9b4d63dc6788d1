"""The body classifier shared by the stability labels and the simulation outputs."""

from __future__ import annotations

import pytest

from express.io import load_model
from express.model.topology import classify_bodies


@pytest.mark.parametrize(
    ("path", "role", "bogie_of", "levers"),
    [
        (
            "examples/forced-steering.toml",
            {"CB": "body", "T1": "bogie", "T2": "bogie", "W1": "wheelset", "W4": "wheelset", "L1": "lever"},
            {"W1": "T1", "W2": "T1", "W3": "T2", "W4": "T2"},
            ("L1", "L2", "L3", "L4"),
        ),
        (
            "examples/conventional.toml",
            {"CB": "body", "T1": "bogie", "T2": "bogie", "W1": "wheelset", "W3": "wheelset"},
            {"W1": "T1", "W2": "T1", "W3": "T2", "W4": "T2"},
            (),
        ),
        # the paper's lever: no rail data, B2 hosts the pin's virtual CP and rotates
        ("examples/lever.exp", {"B1": "body", "B2": "lever"}, {}, ("B2",)),
    ],
)
def test_roles_of_the_bundled_models(path, role, bogie_of, levers):
    topology = classify_bodies(load_model(path))
    for body, expected in role.items():
        assert topology.role[body] == expected, body
    assert topology.bogie_of == bogie_of
    assert topology.levers == levers


def test_levers_belong_to_their_bogie_and_bogies_are_ordered_by_station():
    model = load_model("examples/forced-steering.toml")
    stations = {"T1": 7.0, "T2": -7.0}
    front_first = classify_bodies(model, lambda body: stations.get(body, 0.0))
    rear_first = classify_bodies(model, lambda body: -stations.get(body, 0.0))
    assert front_first.bogies == ("T1", "T2") and rear_first.bogies == ("T2", "T1")
    assert front_first.bogie_label("T1") == "front bogie" and rear_first.bogie_label("T1") == "rear bogie"
    assert {front_first.group(lever) for lever in front_first.levers} == {"T1", "T2"}
    assert front_first.group("W4") == "T2" and front_first.group("CB") == ""
