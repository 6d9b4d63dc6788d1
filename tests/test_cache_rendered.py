"""Exports kept as text in the cache (express.numeric.rendered, docs/cache.md).

A second ``express generate`` of unchanged files copies the first one's text: the same
bytes as a cold run and as ``--no-cache`` in every format, without reading the model or
importing SymPy; every option that shapes the text is its own entry; a changed file the
model reads, a damaged entry, ``--set`` and the cache switched off are handled as for the
other entries; the reading's warnings are given again."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from cache_support import entries, rewrite_entry, use_fresh_cache
from express.base.limits import read_input_text
from express.cli import main
from express.rail import build

ROOT = Path(__file__).resolve().parents[1]
CAR = ROOT / "examples" / "forced-steering.toml"
MODEL = (ROOT / "tests" / "test_cache.py").read_text().split('MODEL = """', 1)[1].split('"""', 1)[0]
FORMATS = ("json", "matlab", "python", "latex", "text")


@pytest.fixture
def fresh(tmp_path, monkeypatch):
    """An empty cache folder, nothing reused in memory, no warning given yet; the model file."""
    use_fresh_cache(tmp_path, monkeypatch)
    path = tmp_path / "wheelset.toml"
    path.write_text(MODEL)
    return path


@pytest.fixture
def renders(monkeypatch):
    """Counts the model readings of ``generate`` (calls of load_generation)."""
    from express.numeric import generation

    calls: list[int] = []
    original = generation.load_generation
    monkeypatch.setattr(generation, "load_generation", lambda *a, **k: calls.append(1) or original(*a, **k))
    return calls


def _generate(path: Path, *options: str, output: Path | None = None) -> str:
    out = output or path.with_suffix(".out")
    assert main(["generate", str(path), *options, "-o", str(out)]) == 0
    return out.read_text()


def _entries() -> list[Path]:
    return entries("export text")


@pytest.mark.parametrize("fmt", FORMATS)
def test_cold_warm_and_no_cache_write_the_same_bytes(fresh, renders, tmp_path, fmt):
    suffix = ".m" if fmt == "matlab" else ".txt"
    cold = _generate(CAR, "--format", fmt, output=tmp_path / f"cold{suffix}")
    hot = _generate(CAR, "--format", fmt, output=tmp_path / f"cold{suffix}".replace("cold", "cold"))
    assert renders == [1]  # the second run read no model
    uncached = _generate(CAR, "--format", fmt, "--no-cache", output=tmp_path / f"cold{suffix}")
    assert cold == hot == uncached != ""
    assert len(_entries()) == 1


@pytest.mark.slow
def test_a_second_generate_imports_no_sympy(tmp_path):
    env = {k: v for k, v in os.environ.items() if k != "EXPRESS_NO_CACHE"}
    env.update(PYTHONPATH=str(ROOT / "src"), EXPRESS_CACHE_DIR=str(tmp_path / "cache"))
    code = (f"import sys\nfrom express.cli import main\nassert main(['generate', {str(CAR)!r}, '--format', 'json', "
            f"'-o', {str(tmp_path / 'car.json')!r}]) == 0\nprint('sympy' in sys.modules)\n")
    runs = [subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, timeout=600)
            for _ in range(2)]
    assert [r.returncode for r in runs] == [0, 0], runs[-1].stderr
    assert [r.stdout.split()[-1] for r in runs] == ["True", "False"]


def test_each_option_is_its_own_entry(fresh, renders, tmp_path):
    """The MATLAB function is named after its file; --keep-virtual and --no-rail change the
    equations: each is stored apart and read back as itself."""
    first = _generate(CAR, "--format", "matlab", output=tmp_path / "first.m")
    second = _generate(CAR, "--format", "matlab", output=tmp_path / "second.m")
    assert first.startswith("function") and "first(" in first.splitlines()[0] and "second(" in second.splitlines()[0]
    virtual = _generate(CAR, "--format", "json", "--keep-virtual", output=tmp_path / "v.json")
    core = _generate(CAR, "--format", "json", "--no-rail", output=tmp_path / "c.json")
    plain = _generate(CAR, "--format", "json", output=tmp_path / "p.json")
    assert len({virtual, core, plain}) == 3 and len(_entries()) == 5 and len(renders) == 5
    assert _generate(CAR, "--format", "json", "--keep-virtual", output=tmp_path / "v2.json") == virtual
    assert _generate(CAR, "--format", "matlab", output=tmp_path / "second.m") == second
    assert len(renders) == 5


def test_a_changed_file_the_model_reads_renders_anew(fresh, renders, monkeypatch, tmp_path):
    import express.io

    other = tmp_path / "table.txt"
    other.write_text("0 0\n")
    original = express.io.load_model
    monkeypatch.setattr(express.io, "load_model", lambda path: (read_input_text(other), original(path))[1])
    _generate(fresh, "--format", "json")
    _generate(fresh, "--format", "json")
    assert len(renders) == 1
    other.write_text("0 1\n")
    _generate(fresh, "--format", "json")
    _generate(fresh, "--format", "json")
    assert len(renders) == 2  # rendered anew once, then read back


def test_set_and_the_cache_off_use_no_text_entry(fresh, renders, monkeypatch):
    changed = _generate(fresh, "--format", "json", "--set", "k=2 MN/m")
    assert not _entries() and "2000000" in changed.replace(".0", "")
    monkeypatch.setenv("EXPRESS_NO_CACHE", "1")
    _generate(fresh, "--format", "json")
    _generate(fresh, "--format", "json")
    assert not _entries() and len(renders) == 3


DAMAGES = {
    "truncated": lambda path: path.write_bytes(path.read_bytes()[:100]),
    "text not a text": lambda path: rewrite_entry(path, lambda p: p["data"].update(text=["M"])),
    "bad count": lambda path: rewrite_entry(path, lambda p: p["data"].update(dofs="24")),
    "bad reads": lambda path: rewrite_entry(path, lambda p: p.update(reads=[["a", "b", "c"]])),
    "bad warnings": lambda path: rewrite_entry(path, lambda p: p.update(warnings=[["SystemExit", "x"]])),
    "bad notices": lambda path: rewrite_entry(path, lambda p: p["data"].update(notices=[1])),
    "no data": lambda path: rewrite_entry(path, lambda p: p.pop("data")),
    "bad source": lambda path: rewrite_entry(path, lambda p: p.update(source=None)),
}


@pytest.mark.parametrize("how", list(DAMAGES))
def test_a_damaged_entry_is_ignored_with_one_warning_and_rebuilt(fresh, renders, capsys, how):
    cold = _generate(fresh, "--format", "json")
    (entry,) = _entries()
    DAMAGES[how](entry)
    capsys.readouterr()
    again = _generate(fresh, "--format", "json")
    assert capsys.readouterr().err.count("derivation cache: ignored the damaged or foreign entry") == 1
    assert again == cold and len(renders) == 2
    assert _generate(fresh, "--format", "json") == cold  # rebuilt: read back, no warning
    assert "damaged or foreign" not in capsys.readouterr().err and len(renders) == 2


def test_the_readings_warnings_are_given_again(fresh, renders, capsys, monkeypatch):
    fresh.write_text(MODEL.replace('k = "1 MN/m"', 'k = "-1 MN/m"'))
    _generate(fresh, "--format", "text")
    cold = capsys.readouterr().err
    _generate(fresh, "--format", "text")
    hot = capsys.readouterr().err
    assert len(renders) == 1
    assert hot == cold and "parameter k: a negative stiffness" in cold
    monkeypatch.chdir(fresh.parent)  # the file named as this run names it
    assert main(["generate", "wheelset.toml", "-o", "again.txt"]) == 0
    assert capsys.readouterr().err.startswith("warning: wheelset.toml: parameter k: a negative stiffness")
    assert len(renders) == 1


def test_the_generators_notices_are_printed_again(fresh, renders, capsys, monkeypatch):
    """What the generator noticed (printed as ``warning: ...``) comes back with the text."""
    from express.base.diagnostics import Problem

    original = build.generate_vehicle

    def noticing(*args, **kwargs):
        result = original(*args, **kwargs)
        return type(result)(result.equations, (Problem("x", None, "dof", "a DOF without mass"),),
                            result.transformation, result.full_dofs)

    monkeypatch.setattr(build, "generate_vehicle", noticing)
    _generate(fresh, "--no-cache")
    expected = capsys.readouterr().err
    assert "a DOF without mass" in expected
    for _ in range(2):
        _generate(fresh)
        assert capsys.readouterr().err.splitlines()[0] == expected.splitlines()[0]
    assert len(renders) == 2  # --no-cache and the first cached run; the second read it back
