"""Exports and the derivation cache (docs/cache.md): ``express generate`` writes its text
from the derivation on every path — cold, warm (the generation entry read back) and
``--no-cache`` — the same bytes in every format, and stores no export text: a text in the
cache could be doctored into code that runs when the export is imported (issue 36)."""

from __future__ import annotations

from pathlib import Path

import pytest

from cache_support import entries, use_fresh_cache
from express.cli import main

ROOT = Path(__file__).resolve().parents[1]
CAR = ROOT / "examples" / "forced-steering.toml"
FORMATS = ("json", "matlab", "python", "latex", "text")


@pytest.fixture
def renders(tmp_path, monkeypatch):
    """A fresh cache; counts the derivations read or made by ``generate``."""
    from express.numeric import generation

    use_fresh_cache(tmp_path, monkeypatch)
    calls: list[int] = []
    original = generation.load_generation
    monkeypatch.setattr(generation, "load_generation", lambda *a, **k: calls.append(1) or original(*a, **k))
    return calls


def _generate(*options: str, output: Path) -> bytes:
    assert main(["generate", str(CAR), *options, "-o", str(output)]) == 0
    return output.read_bytes()


@pytest.mark.parametrize("fmt", FORMATS)
def test_cold_warm_and_no_cache_write_the_same_bytes_from_the_derivation(renders, tmp_path, fmt):
    suffix = ".m" if fmt == "matlab" else ".txt"
    cold = _generate("--format", fmt, output=tmp_path / f"car{suffix}")
    warm = _generate("--format", fmt, output=tmp_path / f"car{suffix}")
    uncached = _generate("--format", fmt, "--no-cache", output=tmp_path / f"car{suffix}")
    assert cold == warm == uncached != b""
    assert renders == [1, 1, 1]  # every run writes from the derivation
    assert entries("generation") and not entries("export text")
