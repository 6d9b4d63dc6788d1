"""EN 14363's bogie-frame instability criterion (``express.analysis.curving.bogie_frames``):
the frames found by the model's topology, the limit's closed form, the frame's
acceleration over a wheelset and its filtered sliding rms against a sinusoid's."""

from __future__ import annotations

import math
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from express.analysis.curving.assessment import assess_run
from express.analysis.curving.bogie_frames import (
    bogie_frame_criteria,
    bogie_frame_limit,
    bogie_frames,
    frame_accelerations,
)
from express.analysis.time.simulate import simulate
from express.numeric.statespace import load_vehicle
from express.rail.track import load_track

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def manchester():
    return load_vehicle(ROOT / "examples" / "manchester.toml")


def test_the_bogie_frames_are_found_by_the_primary_suspension(manchester):
    """Manchester: T1 over W1, W2 and T2 over W3, W4; m+ = 2615 + 2 x 1813 kg; the
    wheelsets 1.28 m either side of the frame's centre (the benchmark's numbers)."""
    frames = bogie_frames(manchester)
    assert [(f.body, f.wheelsets) for f in frames] == [("T1", ("W1", "W2")), ("T2", ("W3", "W4"))]
    for frame in frames:
        assert frame.mass == pytest.approx(2615 + 2 * 1813, rel=1e-12)
        assert frame.offsets == pytest.approx((1.28, -1.28), abs=1e-12)


@pytest.mark.parametrize("mass, limit", [(5000.0, 5.5), (8000.0, 5.2), (6241.0, 5.3759)])
def test_the_limit_is_the_closed_form(mass, limit):
    assert bogie_frame_limit(mass) == pytest.approx(limit, abs=1e-12 if mass != 6241.0 else 1e-4)


def _run(vehicle, distance, time, velocities):
    q_dot = np.zeros((time.size, len(vehicle.dofs)))
    for dof, values in velocities.items():
        q_dot[:, vehicle.dofs.index(dof)] = values
    return SimpleNamespace(time=time, distance=distance, q_dot=q_dot, speed=distance[1] / time[1])


def test_the_acceleration_over_a_wheelset_and_its_rms_against_a_sinusoid(manchester):
    """A frame swaying ``y' = (a/w) sin(w t)`` with yaw ``psi' = (b/w) sin(w t)``, 4 Hz,
    at 40 m/s over 400 m: over W1 (x 1.28 m) the acceleration is ``(a + 1.28 b) cos(w t)``
    (central differences at 2 ms: achieved 1.1e-4 relative, asserted 5e-4), and the
    criterion's rms is its ``/sqrt(2)`` (filtered f0 +- 2 Hz, 100 m windows: the inner
    windows to 1e-4, the last one 0.95 % high, the zero-phase filter's end transient,
    which the largest window reports; asserted 1.5e-2)."""
    a, b, f = 3.0, 2.0, 4.0
    w = 2 * math.pi * f
    time = np.arange(0.0, 10.0, 0.002)
    run = _run(manchester, 40.0 * time, time, {"T1.y": a / w * np.sin(w * time), "T1.rz": b / w * np.sin(w * time)})
    frame = bogie_frames(manchester)[0]
    acceleration = frame_accelerations(manchester, run, frame)
    expected = (a + 1.28 * b) * np.cos(w * time)
    assert np.max(np.abs(acceleration[1:-1, 0] - expected[1:-1])) <= 5e-4 * (a + 1.28 * b)
    criteria = {name: (value, limit) for name, _quantity, value, limit in bogie_frame_criteria(manchester, run)}
    assert criteria["ay_T1_W1_rms"][0] == pytest.approx((a + 1.28 * b) / math.sqrt(2), rel=1.5e-2)
    assert criteria["ay_T1_W2_rms"][0] == pytest.approx((a - 1.28 * b) / math.sqrt(2), rel=1.5e-2)
    assert criteria["ay_T2_W3_rms"][0] < 1e-9 and criteria["ay_T1_W1_rms"][1] == pytest.approx(bogie_frame_limit(6241.0))


def test_an_assessed_run_carries_the_criterion(manchester):
    """``simulate --assess``'s criteria (``assess_run``) include each frame over each
    wheelset, in m/s^2, on a 150 m run."""
    track = load_track(str(ROOT / "examples" / "tracks" / "straight_erri_low.toml"))
    result = simulate(manchester, track, speed=40.0, end=150.0, progress=False)
    names = {c.name: c for c in assess_run(manchester, track, result)[1].criteria}
    assert {"ay_T1_W1_rms", "ay_T1_W2_rms", "ay_T2_W3_rms", "ay_T2_W4_rms"} <= set(names)
    assert names["ay_T1_W1_rms"].unit == "m/s^2" and names["ay_T1_W1_rms"].passed
