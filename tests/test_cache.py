"""The derivation cache (express.io.cache, docs/cache.md): hits and misses, every key
ingredient, damaged and foreign entries, concurrent writers, an unwritable place, the
size bound, the command line, and the in-process reuse.

Every test works in its own cache folder (``fresh``), never in the session's."""

from __future__ import annotations

import multiprocessing
import os
import warnings
from pathlib import Path

import numpy as np
import pytest

from express.base.limits import read_input_text
from express.base.reads import recorded_reads
from express.cli import main
from express.io import cache
from express.numeric import statespace
from express.numeric.statespace import load_vehicle
from express.rail import build

MODEL = """
[model]
name = "wheelset"
[parameters]
m = {value = 1400, unit = "kg"}
I = {value = 600, unit = "kg*m^2"}
k = "1 MN/m"
f = "7.8 MN"
v = "100 km/h"
G = "1067 mm"
[bodies.W]
mass = "m"
inertia = [0, 0, "I"]
dofs = ["y", "rz"]
[grounds.track]
[points.W_L]
body = "W"
offset = [0, 1, 0]
[points.G_L]
body = "track"
offset = [0, 1, 0]
[elements.spring]
from = "W_L"
to = "G_L"
stiffness = "k"
direction = "y"
[rail]
wheelsets = ["W"]
[rail.wheel_rail]
f1 = "f"
f2 = "f"
conicity = 0.1
r0 = 0.43
b = 0.56
flange_clearance = 0.006
rail_stiffness = 2e7
friction = 0.3
wheel_load = 5e4
"""


@pytest.fixture
def fresh(tmp_path, monkeypatch):
    """An empty cache folder, no in-process reuse, no warning given yet; the model file."""
    monkeypatch.setenv("EXPRESS_CACHE_DIR", str(tmp_path / "cache"))
    monkeypatch.delenv("EXPRESS_NO_CACHE", raising=False)
    monkeypatch.delenv("EXPRESS_CACHE_MB", raising=False)
    monkeypatch.setattr(statespace, "_GENERATED", {})
    monkeypatch.setattr(cache, "_WARNED", set())
    path = tmp_path / "wheelset.toml"
    path.write_text(MODEL)
    return path


@pytest.fixture
def derivations(monkeypatch):
    """Counts the symbolic derivations (calls of generate_vehicle)."""
    calls: list[int] = []
    original = build.generate_vehicle

    def counting(*args, **kwargs):
        calls.append(1)
        return original(*args, **kwargs)

    monkeypatch.setattr(build, "generate_vehicle", counting)
    return calls


def _load_anew(path, **options):
    """load_vehicle as a new process would: nothing reused in memory."""
    statespace._GENERATED.clear()
    return load_vehicle(path, **options)


def _entries() -> list[Path]:
    """The derivation entries (not the warm entries beside them, express.numeric.warm)."""
    return sorted(path for path in cache.cache_directory().glob("*.json") if b'"kind":"vehicle warm"' not in path.read_bytes())


def _same(first, second) -> None:
    for name in ("mass", "stiffness", "damping_base", "damping_creep", "forcing_base", "forcing_speed2"):
        assert np.array_equal(getattr(first, name), getattr(second, name)), name
    assert first.wheelsets == second.wheelsets
    assert first.speed == second.speed


def test_miss_then_hit_gives_the_same_vehicle_without_deriving(fresh, derivations):
    cold = _load_anew(fresh)
    assert len(derivations) == 1 and len(_entries()) == 1
    warm = _load_anew(fresh)
    assert len(derivations) == 1  # read from the entry
    _same(cold, warm)
    assert warm.equations.dofs == cold.equations.dofs and warm.equations.inputs == cold.equations.inputs
    assert warm.equations.values == cold.equations.values
    # the symbolic matrices come back on demand, equal to the derived ones
    assert warm.equations.matrices == cold.equations.matrices


def test_in_process_reuse_reads_nothing(fresh, derivations, monkeypatch):
    first = load_vehicle(fresh)
    monkeypatch.setattr(cache, "read_entry", lambda key: pytest.fail("read the disk again"))
    second = load_vehicle(fresh, {"m": "1500 kg"})
    assert len(derivations) == 1
    assert second.mass[0, 0] == 1500.0 and first.mass[0, 0] == 1400.0


def test_overrides_are_applied_after_the_cache(fresh, derivations):
    _load_anew(fresh)
    warm = _load_anew(fresh, overrides={"k": "2 MN/m"})
    from express.model.parameters import with_values

    fresh_derived = statespace.vehicle_model(
        with_values(__import__("express.io", fromlist=["load_model"]).load_model(fresh), {"k": "2 MN/m"})
    )
    assert len(derivations) == 2  # the vehicle_model above; the warm load derived nothing
    _same(warm, fresh_derived)


def test_no_cache_derives_and_stores_nothing(fresh, derivations, monkeypatch):
    monkeypatch.setenv("EXPRESS_NO_CACHE", "1")
    _load_anew(fresh)
    _load_anew(fresh)
    assert len(derivations) == 2 and not _entries()
    monkeypatch.delenv("EXPRESS_NO_CACHE")
    with cache.disabled():
        _load_anew(fresh)
    assert len(derivations) == 3 and not _entries()


@pytest.mark.parametrize("ingredient", ["model bytes", "with_rail", "package", "format"])
def test_each_key_ingredient_forces_a_rebuild(fresh, derivations, monkeypatch, ingredient):
    _load_anew(fresh)
    options = {}
    if ingredient == "model bytes":
        fresh.write_text(MODEL + "\n# a comment changes the bytes\n")
    elif ingredient == "with_rail":
        options = {"with_rail": False}
    elif ingredient == "package":
        monkeypatch.setattr(cache, "_FINGERPRINT", ["another version"])
    else:
        monkeypatch.setattr(cache, "FORMAT_VERSION", cache.FORMAT_VERSION + 1)
    _load_anew(fresh, **options)
    assert len(derivations) == 2
    assert len(_entries()) == 2


def test_every_file_read_enters_the_key(tmp_path):
    """Profiles, delta-r tables and model files are read through read_input_text, which
    records them; a changed byte in any changes the key."""
    other = tmp_path / "profile.txt"
    other.write_text("0 0\n1 1\n")
    with recorded_reads() as reads:
        read_input_text(other)
    first = cache.entry_key("vehicle", reads, {})
    other.write_text("0 0\n1 2\n")
    with recorded_reads() as reads_again:
        read_input_text(other)
    assert [path for path, _ in reads] == [str(other)]
    assert cache.entry_key("vehicle", reads_again, {}) != first
    assert cache.entry_key("readable", reads, {}) != first
    assert cache.entry_key("vehicle", reads, {"keep_virtual": True}) != first


def _damage(path: Path, how: str) -> None:
    data = path.read_bytes()
    if how == "truncated":
        path.write_bytes(data[: len(data) // 2])
    elif how == "flipped byte":
        middle = len(data) // 2
        path.write_bytes(data[:middle] + bytes([data[middle] ^ 0x01]) + data[middle + 1 :])
    elif how == "foreign":
        path.write_bytes(b"PK\x03\x04 not an entry at all\n" + data)
    elif how == "entry of another key":
        header, _, body = data.partition(b"\n")
        parts = header.split(b" ")
        parts[2] = b"0" * 64
        path.write_bytes(b" ".join(parts) + b"\n" + body)
    elif how == "re-signed without the secret":  # the payload changed, its SHA-256 recomputed
        import hashlib

        header, _, body = data.partition(b"\n")
        body = body.replace(b"\"wheelset", b"\"wheelsex")
        parts = header.split(b" ")
        parts[3] = hashlib.sha256(body).hexdigest().encode()
        path.write_bytes(b" ".join(parts) + b"\n" + body)
    else:  # a whole entry, signed with the user's secret, whose program does not check
        from cache_support import rewrite_entry

        rewrite_entry(path, lambda payload: payload["constant"]["operations"].append(["exec", 0]))


@pytest.mark.parametrize("how", ["truncated", "flipped byte", "foreign", "entry of another key",
                                 "re-signed without the secret", "bad program"])
def test_a_damaged_entry_is_ignored_with_one_warning_and_rebuilt(fresh, derivations, how):
    cold = _load_anew(fresh)
    (entry,) = _entries()
    _damage(entry, how)
    with pytest.warns(UserWarning, match="damaged or foreign entry") as caught:
        rebuilt = _load_anew(fresh)
    assert len([w for w in caught if "derivation cache" in str(w.message)]) == 1
    assert len(derivations) == 2
    _same(cold, rebuilt)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        _load_anew(fresh)  # the rebuilt entry is whole again: no warning, no derivation
    assert len(derivations) == 2


def _write_many(folder: str, key: str, worker: int) -> None:
    os.environ["EXPRESS_CACHE_DIR"] = folder
    payload = {"name": f"writer {worker}", "data": list(range(200_000))}
    for _ in range(5):
        cache.write_entry(key, payload)


def test_concurrent_writers_leave_a_valid_entry(fresh):
    key = "f" * 64
    folder = os.environ["EXPRESS_CACHE_DIR"]
    context = multiprocessing.get_context("fork")
    workers = [context.Process(target=_write_many, args=(folder, key, i)) for i in range(4)]
    for worker in workers:
        worker.start()
    seen = 0
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # a reader never sees a part of an entry
        while any(worker.is_alive() for worker in workers):
            payload = cache.read_entry(key)
            if payload is not None:
                assert payload["data"][-1] == 199_999
                seen += 1
    for worker in workers:
        worker.join()
        assert worker.exitcode == 0
    final = cache.read_entry(key)
    assert final["name"].startswith("writer ") and len(final["data"]) == 200_000
    assert not list(cache.cache_directory().glob("*.tmp"))


def test_an_unwritable_place_works_without_storing(fresh, derivations, monkeypatch, tmp_path):
    blocker = tmp_path / "a file"
    blocker.write_text("not a folder")
    monkeypatch.setenv("EXPRESS_CACHE_DIR", str(blocker / "cache"))  # cannot be made, even by root
    with pytest.warns(UserWarning, match="cannot write") as caught:
        first = _load_anew(fresh)
        second = _load_anew(fresh)
    assert len([w for w in caught if "derivation cache" in str(w.message)]) == 1
    assert len(derivations) == 2
    _same(first, second)


def test_a_read_only_entry_is_still_read(fresh, derivations, monkeypatch):
    _load_anew(fresh)
    monkeypatch.setattr(os, "utime", _refuse)  # the hit cannot renew the entry's time
    _load_anew(fresh)
    assert len(derivations) == 1


def _refuse(*args, **kwargs):
    raise PermissionError("read-only")


def test_the_size_bound_removes_the_least_recently_used(fresh, monkeypatch):
    payload = {"name": "x", "data": "y" * 40_000}
    monkeypatch.setenv("EXPRESS_CACHE_MB", str(130_000 / 1024 / 1024))  # room for three entries
    keys = [f"{i}" * 64 for i in range(4)]
    for age, key in enumerate(keys[:3]):
        cache.write_entry(key, payload)
        os.utime(cache.cache_directory() / f"{key}.json", ns=(10**18 + age, 10**18 + age))
    assert cache.read_entry(keys[0]) is not None  # used now: the most recent
    cache.write_entry(keys[3], payload)
    left = {path.stem for path in _entries()}
    assert left == {keys[0], keys[2], keys[3]}  # keys[1], the least recently used, went
    assert cache.cache_info().size <= cache.size_bound()


def test_cache_info_and_clear_on_the_command_line(fresh, capsys):
    _load_anew(fresh)
    assert main(["cache", "info"]) == 0
    out = capsys.readouterr().out
    # the derivation and the warm entry (express.numeric.warm), both of the model "wheelset"
    assert str(cache.cache_directory()) in out and "2 entries" in out and "wheelset" in out
    assert main(["cache", "clear"]) == 0
    assert "removed 2 entries" in capsys.readouterr().out
    assert not _entries()


def test_the_no_cache_option_of_a_command(fresh, derivations, capsys):
    assert main(["eigen", str(fresh), "--speed", "100", "--no-cache"]) == 0
    without = capsys.readouterr().out
    assert not _entries() and os.environ.get("EXPRESS_NO_CACHE") is None
    statespace._GENERATED.clear()
    assert main(["eigen", str(fresh), "--speed", "100"]) == 0
    assert capsys.readouterr().out == without
    assert len(_entries()) == 1


def test_kalkers_coefficients_are_kept_by_their_exact_arguments(fresh, monkeypatch):
    """A warm load of a model with [rail.creep] from = "kalker" neither solves Kalker's
    contact again nor imports SciPy's root finder; the values are the same floats."""
    from express.rail import contact

    model = Path(__file__).resolve().parents[1] / "examples" / "conventional.toml"
    cold = _load_anew(model)
    solved: list[int] = []
    original = contact.creep_coefficients
    monkeypatch.setattr(contact, "creep_coefficients", lambda *a: solved.append(1) or original(*a))
    warm = _load_anew(model)
    assert not solved
    assert warm.values == cold.values and warm.wheelsets == cold.wheelsets
    statespace._GENERATED.clear()
    load_vehicle(model, {"mc": "30 t"})  # another wheel load: solved anew
    assert solved
