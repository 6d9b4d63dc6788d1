"""The input files a piece of work read, with a digest of their bytes.

:func:`recorded_reads` collects every file read through
:func:`express.base.limits.read_input_text` (model files, profiles, delta-r tables)
while its block runs; the derivation cache (:mod:`express.io.cache`) keys an entry
by them, so that a change to any file a model reads forces a rebuild.

Examples
--------
>>> with recorded_reads() as reads:
...     note_read("model.toml", b"[model]")
>>> reads[0][0].endswith("model.toml"), len(reads[0][1])
(True, 64)
"""

from __future__ import annotations

import contextlib
import contextvars
import hashlib
import os
from collections.abc import Iterator

__all__ = ["note_read", "recorded_reads", "recording"]

_READS: contextvars.ContextVar[list[tuple[str, str]] | None] = contextvars.ContextVar("express_reads", default=None)


@contextlib.contextmanager
def recorded_reads() -> Iterator[list[tuple[str, str]]]:
    """Collect ``(absolute path, sha256 hex digest)`` of every input read in the block,
    in the order read (nested blocks each see the reads made inside them)."""
    outer = _READS.get()
    reads: list[tuple[str, str]] = []
    token = _READS.set(reads)
    try:
        yield reads
    finally:
        _READS.reset(token)
        if outer is not None:
            outer.extend(reads)


def recording() -> bool:
    """Whether a :func:`recorded_reads` block is active (a model is being read for the cache)."""
    return _READS.get() is not None


def note_read(path: str | os.PathLike, data: bytes) -> None:
    """Record that ``data`` was read from ``path`` (nothing when no block records)."""
    reads = _READS.get()
    if reads is not None:
        reads.append((os.path.abspath(os.fspath(path)), hashlib.sha256(data).hexdigest()))
