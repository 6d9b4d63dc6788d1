"""The warm load (express.numeric.warm, docs/cache.md): a cached vehicle without reading
the model into its records and without SymPy.

A warm command imports no SymPy (checked in a fresh interpreter's ``sys.modules``: a
robust stand-in for a timing, which ``benchmarks/bench_cache.py`` measures); the warm
vehicle is the cold one bit for bit, with the same facts; ``--set`` still works (through
the symbolic model); a changed file the model reads, a damaged warm entry and the
reading's warnings are handled as for the derivation entry."""

from __future__ import annotations

import os
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

from cache_support import rewrite_entry, use_fresh_cache
from express.base.diagnostics import ModelWarning
from express.base.limits import read_input_text
from express.io import cache
from express.numeric import statespace, warm
from express.numeric.statespace import load_vehicle, vehicle_model
from express.rail import build

ROOT = Path(__file__).resolve().parents[1]
CAR = ROOT / "examples" / "forced-steering.toml"
#: Modules a warm numerical command does without.
SYMBOLIC = ("sympy", "express.io.classic", "express.io.toml_model", "express.model.records", "express.assembly.generator",
            "numba", "matplotlib", "pint", "xarray")

MODEL = (ROOT / "tests" / "test_cache.py").read_text().split('MODEL = """', 1)[1].split('"""', 1)[0]


@pytest.fixture
def fresh(tmp_path, monkeypatch):
    """An empty cache folder, nothing reused in memory, no warning given yet; the model file."""
    monkeypatch.setenv("EXPRESS_CACHE_DIR", str(tmp_path / "cache"))
    monkeypatch.delenv("EXPRESS_NO_CACHE", raising=False)
    monkeypatch.setattr(statespace, "_GENERATED", {})
    monkeypatch.setattr(warm, "_READ", {})
    monkeypatch.setattr(cache, "_WARNED", set())
    path = tmp_path / "wheelset.toml"
    path.write_text(MODEL)
    return path


@pytest.fixture
def derivations(monkeypatch):
    """Counts the symbolic derivations (calls of generate_vehicle)."""
    calls: list[int] = []
    original = build.generate_vehicle
    monkeypatch.setattr(build, "generate_vehicle", lambda *a, **k: calls.append(1) or original(*a, **k))
    return calls


def _anew(path, overrides=None):
    """load_vehicle as a new process would: nothing kept in memory."""
    statespace._GENERATED.clear()
    warm._READ.clear()
    return load_vehicle(path, overrides)


def _same(first, second) -> None:
    for name in ("mass", "stiffness", "damping_base", "damping_creep", "forcing_base", "forcing_speed2",
                 "forcing_rate_matrix", "station_positions"):
        assert np.array_equal(getattr(first, name), getattr(second, name)), name
    assert first.wheelsets == second.wheelsets and list(first.values.items()) == list(second.values.items())
    assert first.speed == second.speed or (first.speed != first.speed and second.speed != second.speed)
    assert (first.name, first.dofs, first.inputs, first.inactive) == (second.name, second.dofs, second.inputs, second.inactive)


def _entry(kind: str) -> Path:
    (path,) = [p for p in cache.cache_directory().glob("*.json") if f'"kind":"{kind}"'.encode() in p.read_bytes()]
    return path


# --------------------------------------------------------------------------------------
# no SymPy
# --------------------------------------------------------------------------------------


def _loaded_after(code: str, folder: Path) -> list[str]:
    """Run ``code`` in a fresh interpreter with the cache in ``folder``: which of
    :data:`SYMBOLIC` it loaded."""
    env = {k: v for k, v in os.environ.items() if k != "EXPRESS_NO_CACHE"}
    env["PYTHONPATH"] = str(ROOT / "src")
    env["EXPRESS_CACHE_DIR"] = str(folder)
    code += f"\nimport sys\nprint('loaded:' + ','.join(m for m in {SYMBOLIC!r} if m in sys.modules))\n"
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, timeout=600)
    assert done.returncode == 0, done.stderr
    return [m for m in done.stdout.strip().splitlines()[-1].removeprefix("loaded:").split(",") if m]


def _command(argv: list[str]) -> str:
    return ("import contextlib, io\nfrom express.cli import main\n"
            f"with contextlib.redirect_stdout(io.StringIO()):\n    assert main({argv!r}) == 0\n")


@pytest.mark.slow
@pytest.mark.parametrize("argv", [["eigen", "--speed", "100"], ["critical-speed"], ["frf", "--points", "50"]],
                         ids=["eigen", "critical-speed", "frf"])
def test_a_warm_command_imports_no_sympy(tmp_path, argv):
    command = _command([argv[0], str(CAR), *argv[1:]])
    assert "sympy" in _loaded_after(command, tmp_path)  # cold: derives
    assert _loaded_after(command, tmp_path) == []  # warm


@pytest.mark.slow
@pytest.mark.parametrize("argv", [["eigen", "--speed", "100"], ["critical-speed"]], ids=["eigen", "critical-speed"])
def test_a_warm_command_on_a_coach_with_series_dampers_imports_no_scipy_sparse(tmp_path, argv):
    """The mode shares of a damping with series elements are summed without SciPy (its
    import is 0.15 s of a 0.25 s warm command)."""
    coach = ROOT / "tests" / "data" / "coach-series-dampers.toml"
    command = _command([argv[0], str(coach), *argv[1:]]) + "import sys\nprint('sparse:', 'scipy.sparse' in sys.modules)\n"
    env = {k: v for k, v in os.environ.items() if k != "EXPRESS_NO_CACHE"}
    env.update(PYTHONPATH=str(ROOT / "src"), EXPRESS_CACHE_DIR=str(tmp_path))
    runs = [subprocess.run([sys.executable, "-c", command], capture_output=True, text=True, env=env, timeout=600)
            for _ in range(2)]
    assert runs[1].returncode == 0, runs[1].stderr
    assert runs[1].stdout.split()[-1] == "False"


@pytest.mark.slow
def test_a_warm_load_vehicle_imports_no_sympy(tmp_path):
    code = f"from express import load_vehicle\nvehicle = load_vehicle({str(CAR)!r})\nvehicle.eigenvalues(30.0)\n"
    _loaded_after(code, tmp_path)
    assert _loaded_after(code, tmp_path) == []
    # asking for the symbolic side builds it, on demand
    assert "sympy" in _loaded_after(code + "vehicle.equations.matrices.M\n", tmp_path)


# --------------------------------------------------------------------------------------
# the same vehicle
# --------------------------------------------------------------------------------------


@pytest.mark.parametrize("name", ["forced-steering.toml", "manchester.toml", "conventional-yaw-bush.toml"])
def test_the_warm_vehicle_is_the_cold_one(fresh, derivations, name):
    path = ROOT / "examples" / name
    cold = _anew(path)
    hot = _anew(path)
    assert len(derivations) == 1 and hot.origin.cached and not cold.origin.cached
    _same(cold, hot)
    assert hot.facts == cold.facts
    for speed in (10.0, 55.0):
        assert np.array_equal(hot.state_matrix(speed), cold.state_matrix(speed))
    assert [s.name for s in hot.layout.stations] == [s.name for s in cold.layout.stations]
    assert hot.layout.inputs == cold.layout.inputs
    # the symbolic side, built on demand from the same files and the derivation entry
    assert hot.equations.matrices == cold.equations.matrices and hot.model.name == cold.model.name
    assert len(derivations) == 1


def test_set_on_a_warm_vehicle_goes_through_the_model(fresh, derivations):
    from express.io import load_model
    from express.model.parameters import with_values

    _anew(fresh)
    changed = _anew(fresh, {"k": "2 MN/m", "v": "120 km/h"})
    expected = vehicle_model(with_values(load_model(fresh), {"k": "2 MN/m", "v": "120 km/h"}))
    _same(changed, expected)
    assert len(derivations) == 2  # the cold load and vehicle_model above: the --set derived nothing


def test_a_model_without_rail_data(fresh, derivations):
    fresh.write_text(MODEL.split("[rail]")[0])
    cold = _anew(fresh)
    hot = _anew(fresh)
    assert hot.origin.cached and hot.layout is None and hot.wheelsets == () and len(derivations) == 1
    _same(cold, hot)
    assert hot.facts == cold.facts


# --------------------------------------------------------------------------------------
# when the warm entry is not used
# --------------------------------------------------------------------------------------


def test_a_changed_file_the_model_reads_misses_the_warm_entry(fresh, derivations, monkeypatch, tmp_path):
    """A model that reads another file (a profile, a table): the warm entry lists it with its
    digest; a changed byte there makes a full load, which derives and stores anew."""
    import express.io

    other = tmp_path / "table.txt"
    other.write_text("0 0\n")
    original = express.io.load_model
    monkeypatch.setattr(express.io, "load_model", lambda path: (read_input_text(other), original(path))[1])
    _anew(fresh)
    assert warm.find_warm(fresh, True) is not None
    other.write_text("0 1\n")
    warm._READ.clear()
    assert warm.find_warm(fresh, True) is None
    rebuilt = _anew(fresh)
    assert len(derivations) == 2 and not rebuilt.origin.cached
    assert _anew(fresh).origin.cached and len(derivations) == 2  # stored anew


def test_the_cache_off_reads_no_warm_entry(fresh, derivations, monkeypatch):
    _anew(fresh)
    monkeypatch.setenv("EXPRESS_NO_CACHE", "1")
    assert not _anew(fresh).origin.cached and len(derivations) == 2


DAMAGES = {
    "truncated": lambda path: path.write_bytes(path.read_bytes()[:100]),
    "bad values": lambda path: rewrite_entry(path, lambda p: p["values"][0].__setitem__(1, "1 MN/m")),
    "bad facts": lambda path: rewrite_entry(path, lambda p: p["facts"].update(gyration=[1])),
    "bad wheelset": lambda path: rewrite_entry(path, lambda p: p["wheelsets"][0].__setitem__(1, 10**6)),
    "bad warnings": lambda path: rewrite_entry(path, lambda p: p.update(warnings=[["SystemExit", "x"]])),
    "bad reads": lambda path: rewrite_entry(path, lambda p: p.update(reads="everything")),
    # issue 36: a stiffness of 1e300 (kx1 there) from a warm entry passed the range check that refuses it from a file
    "a value outside its valid range": lambda path: rewrite_entry(path, lambda p: _set_value(p, "k", 1e300)),
    "a negative mass": lambda path: rewrite_entry(path, lambda p: _set_value(p, "m", -1.0)),
    "bad bounds": lambda path: rewrite_entry(path, lambda p: p["bounds"][0].__setitem__(2, "1e15")),
    "no bounds": lambda path: rewrite_entry(path, lambda p: p.pop("bounds")),
}


def _set_value(payload: dict, name: str, value: float) -> None:
    (pair,) = [pair for pair in payload["values"] if pair[0] == name]
    pair[1] = value


@pytest.mark.parametrize("how", list(DAMAGES))
def test_a_damaged_warm_entry_is_ignored_with_one_warning_and_rebuilt(fresh, derivations, how):
    cold = _anew(fresh)
    DAMAGES[how](_entry("vehicle warm"))
    with pytest.warns(UserWarning, match="damaged or foreign entry") as caught:
        again = _anew(fresh)
    assert len([w for w in caught if "derivation cache" in str(w.message)]) == 1
    assert len(derivations) == 1  # the derivation entry is whole: nothing derived
    _same(cold, again)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert _anew(fresh).origin.cached  # rebuilt: a warm load, no warning


def test_the_readings_warnings_are_given_again(fresh, derivations, monkeypatch):
    fresh.write_text(MODEL.replace('k = "1 MN/m"', 'k = "-1 MN/m"'))
    with pytest.warns(UserWarning) as cold:
        _anew(fresh)
    with pytest.warns(UserWarning) as hot:
        vehicle = _anew(fresh)
    assert vehicle.origin.cached
    assert [str(w.message) for w in hot] == [str(w.message) for w in cold] != []
    assert {w.category for w in hot} == {w.category for w in cold} == {ModelWarning}
    # the file named as this load names it
    monkeypatch.chdir(fresh.parent)
    statespace._GENERATED.clear()
    with pytest.warns(ModelWarning, match=r"^wheelset\.toml: parameter k: a negative stiffness"):
        assert load_vehicle("wheelset.toml").origin.cached


def test_a_pipe_is_not_read_for_the_warm_entry(fresh, tmp_path):
    """``express eigen <(cat model.toml)``: the model reader reads the pipe, once; the warm
    load neither reads it (that would empty it) nor keys an entry by it."""
    fifo = tmp_path / "model.toml"
    os.mkfifo(fifo)
    assert warm.find_warm(fifo, True) is None  # returns at once: nothing read
    assert not list(cache.cache_directory().glob("*.json"))


def test_a_warm_vehicle_does_not_read_a_model_edited_after_loading(tmp_path, monkeypatch):
    """Issue 36 item 6: a warm vehicle's ``with_values`` (which goes through the symbolic
    model) read the file as edited after the load and gave another vehicle's numbers; now
    it says the file changed."""
    from express.base.diagnostics import ArgumentError
    from express.numeric.statespace import load_vehicle

    use_fresh_cache(tmp_path, monkeypatch)
    path = tmp_path / "car.toml"
    path.write_bytes((ROOT / "examples" / "conventional.toml").read_bytes())
    load_vehicle(path)  # cold: fills the cache
    statespace._GENERATED.clear()
    warm._READ.clear()
    vehicle = load_vehicle(path)
    assert vehicle.origin.cached
    path.write_text(path.read_text().replace('mc = { value = 30000.0', 'mc = { value = 35000.0', 1))
    with pytest.raises(ArgumentError, match="changed since this vehicle was loaded"):
        vehicle.with_values({"Gamma": 0.1})
