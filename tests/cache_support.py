"""Helpers shared by the tests of the derivation cache (``tests/test_cache*.py`` and the
tests of what commands keep in it): a fresh cache folder, the entries of one kind, and an
entry rewritten with bad data but a valid checksum."""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path
from typing import Any

from express.io import cache, cache_files
from express.numeric import statespace, warm


def use_fresh_cache(tmp_path: Path, monkeypatch) -> None:
    """An empty cache folder under ``tmp_path``, nothing reused in memory, no warning given yet."""
    monkeypatch.setenv("EXPRESS_CACHE_DIR", str(tmp_path / "cache"))
    monkeypatch.delenv("EXPRESS_NO_CACHE", raising=False)
    monkeypatch.setattr(statespace, "_GENERATED", {})
    monkeypatch.setattr(warm, "_READ", {})
    monkeypatch.setattr(cache, "_WARNED", set())


def entries(kind: str) -> list[Path]:
    """The cache's entry files of ``kind``."""
    return [p for p in cache.cache_directory().glob("*.json") if f'"kind":"{kind}"'.encode() in p.read_bytes()]


def rewrite_entry(path: Path, change: Callable[[Any], Any]) -> None:
    """Change the payload of an entry and sign it again with the user's own secret: a whole
    entry whose data is bad, as only a process of the same user could write it."""
    header, _, body = path.read_bytes().partition(b"\n")
    payload = json.loads(body)
    change(payload)
    body = json.dumps(payload).encode()
    parts = header.split(b" ")
    secret = (path.parent / ".secret").read_bytes()
    parts[3] = cache_files.entry_signature(secret, path.stem, body).encode()
    path.write_bytes(b" ".join(parts) + b"\n" + body)
