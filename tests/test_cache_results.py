"""Results identical with a cold cache, a warm cache and --no-cache (issue 24 item 5):
every bundled example, its exports byte for byte and its numbers bit for bit.

Each test has its own cache folder; the in-process reuse is cleared before every run, so
the second run reads the entry a first run in another process would have left."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from express.cli import main
from express.numeric import statespace
from express.rail import build

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
MODELS = sorted(p.name for p in EXAMPLES.iterdir() if p.suffix in (".toml", ".exp") and p.name != "vehicle_parameters.toml")
RAIL_MODELS = [name for name in MODELS if name.endswith(".toml")]


@pytest.fixture
def runs(tmp_path, monkeypatch, capsys):
    """``runs(argv)``: the standard output of ``argv`` cold, warm and with --no-cache, and
    the number of symbolic derivations each made."""
    monkeypatch.setenv("EXPRESS_CACHE_DIR", str(tmp_path / "cache"))
    monkeypatch.delenv("EXPRESS_NO_CACHE", raising=False)
    calls: list[int] = []
    original = build.generate_vehicle

    def counting(*args, **kwargs):
        calls.append(1)
        return original(*args, **kwargs)

    monkeypatch.setattr(build, "generate_vehicle", counting)

    def run(argv: list[str]) -> tuple[list[str], list[int]]:
        outputs, derivations = [], []
        for extra in ([], [], ["--no-cache"]):
            statespace._GENERATED.clear()
            before = len(calls)
            assert main([*argv, *extra]) == 0, capsys.readouterr().err
            outputs.append(capsys.readouterr().out)
            derivations.append(len(calls) - before)
        return outputs, derivations

    return run


@pytest.mark.slow
@pytest.mark.parametrize("name", MODELS)
def test_generate_exports_the_same_bytes(runs, name):
    (cold, warm, uncached), derivations = runs(["generate", str(EXAMPLES / name), "--format", "json"])
    assert derivations == [1, 0, 1]
    assert cold == warm == uncached
    assert '"M"' in cold


@pytest.mark.slow
@pytest.mark.parametrize("name", RAIL_MODELS)
@pytest.mark.parametrize(
    "command",
    [["eigen", "--speed", "100", "--json"], ["frf", "--points", "30", "--json"]],
    ids=["eigen", "frf"],
)
def test_numerical_commands_print_the_same_numbers(runs, name, command):
    (cold, warm, uncached), derivations = runs([command[0], str(EXAMPLES / name), *command[1:]])
    assert derivations == [1, 0, 1]
    assert cold == warm == uncached  # every float printed in full (repr) in the JSON


@pytest.mark.slow
def test_critical_speed_prints_the_same_numbers(runs):
    (cold, warm, uncached), derivations = runs(["critical-speed", str(EXAMPLES / "forced-steering.toml"), "--json"])
    assert derivations == [1, 0, 1]
    assert cold == warm == uncached


@pytest.mark.slow
@pytest.mark.parametrize("name", RAIL_MODELS)
def test_the_vehicles_matrices_are_the_same_bits(tmp_path, monkeypatch, name):
    monkeypatch.setenv("EXPRESS_CACHE_DIR", str(tmp_path / "cache"))
    vehicles = []
    for off in (False, False, True):
        statespace._GENERATED.clear()
        monkeypatch.setenv("EXPRESS_NO_CACHE", "1" if off else "0")
        vehicles.append(statespace.load_vehicle(EXAMPLES / name))
    cold, warm, uncached = vehicles
    for other in (warm, uncached):
        for speed in (10.0, 55.0):
            assert np.array_equal(cold.state_matrix(speed), other.state_matrix(speed))
            assert np.array_equal(cold.input_matrix(speed), other.input_matrix(speed))
        assert cold.wheelsets == other.wheelsets
        assert cold.equations.clearances == other.equations.clearances  # the bump stops of the simulation
        assert np.array_equal(cold.station_positions, other.station_positions)

