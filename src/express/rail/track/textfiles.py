"""Text files the track reader reads (CSV profiles, measured track files): their limits,
the checked read and the short quotation of a bad line (the file need not be the user's own)."""

from __future__ import annotations

from pathlib import Path

from express.base.diagnostics import ModelError, Problem
from express.base.limits import input_kind_problem

__all__ = ["EXCERPT_CHARS", "MAX_PROFILE_BYTES", "MAX_ROW_PROBLEMS", "excerpt", "read_text_file"]

#: Largest CSV profile [bytes]: 100 MB, some four million rows (1000 km every 0.25 m).
MAX_PROFILE_BYTES = 100_000_000
#: Bad rows of a CSV profile listed one by one; the rest are counted.
MAX_ROW_PROBLEMS = 20
#: Longest excerpt of a CSV line quoted in a message [characters].
EXCERPT_CHARS = 60


def read_text_file(path: Path, limit: int, item: str, encoding: str) -> str:
    """The text of a regular file of at most ``limit`` bytes, or a ModelError saying why not."""
    source = str(path)

    def refuse(message: str) -> ModelError:
        return ModelError([Problem(source, None, item, message)])

    try:
        kind = input_kind_problem(path, fifo=False)  # a FIFO would block on open
        if kind is not None:
            raise refuse(kind)
        info = path.stat()
        if info.st_size > limit:
            raise refuse(f"the file has {info.st_size} bytes, more than the limit {limit}")
        data = path.read_bytes()
    except OSError as exc:
        raise refuse(f"cannot read the file: {exc.strerror or exc}") from None
    if b"\0" in data:
        raise refuse("not a text file (it holds NUL bytes)")
    try:
        return data.decode(encoding)
    except UnicodeDecodeError as exc:
        raise refuse(f"not a UTF-8 text file (byte {exc.start + 1} cannot be decoded)") from None


def excerpt(line: str) -> str:
    """A short, printable quotation of ``line`` (at most :data:`EXCERPT_CHARS` characters)."""
    shown = "".join(ch if ch.isprintable() else "?" for ch in line[: EXCERPT_CHARS + 1])
    if len(shown) > EXCERPT_CHARS:
        shown = shown[: EXCERPT_CHARS - 3] + "..."
    return repr(shown)
