"""A model's drawing geometry kept in the cache (express.drawing.geometry_data,
express.numeric.products, docs/cache.md).

The data reads back to the same geometry for every bundled example; a second ``draw``
of unchanged files writes the same bytes as a cold run and ``--no-cache`` without
reading the model or importing SymPy; ``--set`` and a damaged entry are handled."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from cache_support import entries, rewrite_entry, use_fresh_cache
from express.cli import main
from express.cli.draw import model_geometry_of
from express.drawing import geometry_data as data_module
from express.drawing.geometry_data import geometry_data, geometry_from_data
from express.io import load_model
from express.numeric.program import ProgramError

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = sorted(p for p in (ROOT / "examples").iterdir()
                  if p.suffix == ".toml" and p.name != "vehicle_parameters.toml")  # .exp files have no values


@pytest.fixture
def fresh(tmp_path, monkeypatch):
    use_fresh_cache(tmp_path, monkeypatch)
    return tmp_path


@pytest.fixture
def makes(monkeypatch):
    """Counts the geometries made from a model read (calls of model_geometry_of)."""
    import express.cli.draw as draw

    calls: list[int] = []
    original = draw.model_geometry_of
    monkeypatch.setattr(draw, "model_geometry_of", lambda *a, **k: calls.append(1) or original(*a, **k))
    return calls


@pytest.mark.parametrize("path", EXAMPLES, ids=lambda p: p.name)
def test_the_data_reads_back_to_the_same_geometry(path):
    geometry = model_geometry_of(load_model(path))
    data = json.loads(json.dumps(geometry_data(geometry)))
    assert geometry_from_data(data) == geometry


@pytest.mark.parametrize("suffix", [".svg", ".png"])
def test_cold_warm_and_no_cache_draw_the_same_bytes(fresh, makes, suffix):
    model = ROOT / "examples" / "manchester.toml"
    outputs = []
    for extra in ([], [], ["--no-cache"]):
        out = fresh / f"car{len(outputs)}{suffix}"
        assert main(["draw", str(model), "-o", str(out), *extra]) == 0
        outputs.append(out.read_bytes())
    assert outputs[0] == outputs[1] == outputs[2]
    assert len(makes) == 2  # the cold run and --no-cache


def test_set_draws_from_the_model(fresh, makes):
    model = ROOT / "examples" / "forced-steering.toml"
    for _ in range(2):
        assert main(["draw", str(model), "--set", "lT=8 m", "-o", str(fresh / "a.png")]) == 0
    assert len(makes) == 2 and not _geometry_entries()


def _geometry_entries() -> list[Path]:
    return entries("drawing geometry")


BAD = {
    "not a mapping": [],
    "a body short of a field": lambda d: d["bodies"][0].pop(),
    "a centre not finite": lambda d: d["bodies"][0][2].__setitem__(0, "nan"),
    "an axis out of range": lambda d: d["elements"][0].__setitem__(3, 7),
    "an element to a missing point": lambda d: d["elements"][0].__setitem__(1, "nowhere"),
    "a point of two numbers": lambda d: d["points"][0].pop(),
}


@pytest.mark.parametrize("how", list(BAD))
def test_bad_data_does_not_check(how):
    data = geometry_data(model_geometry_of(load_model(ROOT / "examples" / "forced-steering.toml")))
    change = BAD[how]
    if callable(change):
        change(data)
    else:
        data = change
    with pytest.raises(ProgramError):
        geometry_from_data(data)


def test_a_damaged_entry_is_drawn_anew_with_one_warning(fresh, makes, capsys):
    model = ROOT / "examples" / "forced-steering.toml"
    assert main(["draw", str(model), "-o", str(fresh / "a.svg")]) == 0
    first = (fresh / "a.svg").read_bytes()
    (entry,) = _geometry_entries()
    rewrite_entry(entry, lambda payload: payload["data"]["elements"][0].__setitem__(3, 9))
    capsys.readouterr()
    assert main(["draw", str(model), "-o", str(fresh / "b.svg")]) == 0
    assert capsys.readouterr().err.count("damaged or foreign entry") == 1
    assert (fresh / "b.svg").read_bytes() == first and len(makes) == 2


def test_a_geometry_that_cannot_be_stored_is_made_every_time(fresh, monkeypatch, makes):
    monkeypatch.setattr(data_module, "geometry_data", lambda g: (_ for _ in ()).throw(ProgramError("not finite")))
    model = ROOT / "examples" / "forced-steering.toml"
    for _ in range(2):
        assert main(["draw", str(model), "-o", str(fresh / "a.png")]) == 0
    assert len(makes) == 2 and not _geometry_entries()


@pytest.mark.slow
def test_a_warm_draw_imports_no_sympy(tmp_path):
    env = {k: v for k, v in os.environ.items() if k != "EXPRESS_NO_CACHE"}
    env.update(PYTHONPATH=str(ROOT / "src"), EXPRESS_CACHE_DIR=str(tmp_path / "cache"))
    code = (f"import sys\nfrom express.cli import main\nassert main(['draw', {str(ROOT / 'examples' / 'manchester.toml')!r}, "
            f"'-o', {str(tmp_path / 'car.png')!r}]) == 0\nprint('sympy' in sys.modules)\n")
    runs = [subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, timeout=600)
            for _ in range(2)]
    assert [r.returncode for r in runs] == [0, 0], runs[-1].stderr
    assert [r.stdout.split()[-1] for r in runs] == ["True", "False"]
