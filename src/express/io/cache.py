"""The derivation cache: derived models stored on disk, safely, and reused.

Deriving a model (the symbolic generation and the compiled numerical functions) takes
a second or more; a model's equations do not change when only parameter values do,
and values are applied after derivation.  So every derivation is stored here once,
keyed by everything that can change it (``docs/cache.md``):

- the bytes of every file read while loading the model (the model file, the profiles
  and tables it names: :mod:`express.base.reads`);
- the options that change the equations (``keep_virtual``, the rail terms, the kind
  of entry);
- the package version, a fingerprint of the package's files (size and modification
  time: an edited source tree is a new version) and :data:`FORMAT_VERSION`.

Safety: an entry is JSON data (names, integers, floats; expressions as
:class:`~express.numeric.program.ExpressionProgram` data, checked when read) with a
header holding the format, the key and a SHA-256 of the payload; it is written through
the one output layer (:func:`express.io.output.write_bytes_now`: a temporary file,
fsync, atomic rename), so a reader sees a whole entry or none and concurrent writers
leave a valid one.  A truncated, corrupted or foreign entry is ignored with one warning
and rebuilt.  Nothing read is executed or evaluated; no ``pickle``.

Place: ``EXPRESS_CACHE_DIR``, else the user's cache directory (:mod:`platformdirs`,
``~/.cache/express`` on Linux), sub-folder ``derivations``.  ``EXPRESS_NO_CACHE=1`` or
``--no-cache`` (:func:`disabled`) switches it off.  Size bound: ``EXPRESS_CACHE_MB``
(default :data:`DEFAULT_SIZE_MB`); when a write passes it, the least recently used
entries (file modification time, renewed at every hit) are removed.  A location that
cannot be written is used for reading only, with one warning.
"""

from __future__ import annotations

import contextlib
import contextvars
import hashlib
import json
import os
import warnings
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

__all__ = [
    "DEFAULT_SIZE_MB",
    "FORMAT_VERSION",
    "CacheInfo",
    "cache_directory",
    "cache_enabled",
    "cache_info",
    "clear_cache",
    "disabled",
    "entry_key",
    "has_entry",
    "memoized_values",
    "read_entry",
    "write_entry",
]

#: Version of the entry format; a new one makes every older entry a miss.
FORMAT_VERSION = 1
#: Default size bound of the cache [MB] (``EXPRESS_CACHE_MB`` changes it).
DEFAULT_SIZE_MB = 512
_MAGIC = b"EXPRESS-DERIVATION-CACHE"
_SUFFIX = ".json"
_ENABLED: contextvars.ContextVar[bool] = contextvars.ContextVar("express_cache_enabled", default=True)
_WARNED: set[str] = set()


def cache_directory() -> Path:
    """The folder of the entries: ``$EXPRESS_CACHE_DIR/derivations`` or the user cache's."""
    from express.base.kernel_cache import express_cache_root

    return express_cache_root() / "derivations"


def cache_enabled() -> bool:
    """False under ``EXPRESS_NO_CACHE=1`` (any value but empty or ``0``) or :func:`disabled`."""
    return _ENABLED.get() and os.environ.get("EXPRESS_NO_CACHE", "") in ("", "0")


@contextlib.contextmanager
def disabled() -> Iterator[None]:
    """Work without the cache in the block (``--no-cache``): derive everything, store nothing."""
    token = _ENABLED.set(False)
    try:
        yield
    finally:
        _ENABLED.reset(token)


def size_bound() -> int:
    """The size bound [bytes] (``EXPRESS_CACHE_MB``, a positive number, or :data:`DEFAULT_SIZE_MB`)."""
    text = os.environ.get("EXPRESS_CACHE_MB", "")
    try:
        megabytes = float(text) if text else DEFAULT_SIZE_MB
    except ValueError:
        megabytes = -1.0
    if not megabytes > 0:
        _warn_once("size", f"EXPRESS_CACHE_MB={text!r} is not a positive number; using {DEFAULT_SIZE_MB} MB")
        megabytes = DEFAULT_SIZE_MB
    return int(megabytes * 1024 * 1024)


# --------------------------------------------------------------------------------------
# keys
# --------------------------------------------------------------------------------------


def _package_fingerprint() -> str:
    """Package version and the name, size and modification time of its files (compiled
    files and Numba's kernels left out)."""
    import express

    root = Path(express.__file__).resolve().parent
    found = []
    for directory, folders, files in os.walk(root):
        folders[:] = [folder for folder in folders if folder != "__pycache__"]
        for name in files:
            if not name.endswith((".pyc", ".nbi", ".nbc")):
                path = os.path.join(directory, name)
                with contextlib.suppress(OSError):
                    status = os.stat(path)
                    found.append(f"{os.path.relpath(path, root)}:{status.st_size}:{status.st_mtime_ns}")
    return hashlib.sha256("\n".join([express.__version__, *sorted(found)]).encode()).hexdigest()


_FINGERPRINT: list[str] = []


def entry_key(kind: str, reads: Sequence[tuple[str, str]], options: dict[str, Any]) -> str:
    """The key of an entry: SHA-256 of the format, the package, ``kind``, the digests of
    the files read (in order, with their names) and ``options`` (JSON-able)."""
    if not _FINGERPRINT:
        _FINGERPRINT.append(_package_fingerprint())
    material = json.dumps(
        {"format": FORMAT_VERSION, "package": _FINGERPRINT[0], "kind": kind, "reads": [list(r) for r in reads],
         "options": options},
        sort_keys=True,
    )
    return hashlib.sha256(material.encode()).hexdigest()


# --------------------------------------------------------------------------------------
# entries
# --------------------------------------------------------------------------------------


def _entry_path(key: str) -> Path:
    return cache_directory() / f"{key}{_SUFFIX}"


def _warn_once(topic: str, message: str) -> None:
    if topic not in _WARNED:
        _WARNED.add(topic)
        warnings.warn(message, stacklevel=3)


def read_entry(key: str) -> Any:
    """The payload stored under ``key``, or ``None`` (no entry, the cache off, or an entry
    that is damaged or foreign: then one warning, and the caller rebuilds it)."""
    if not cache_enabled():
        return None
    path = _entry_path(key)
    try:
        with open(path, "rb") as stream:
            data = stream.read(size_bound() + 1)
    except OSError:
        return None
    payload = _payload(data, key)
    if payload is None:
        _warn_once(f"damaged {path}", f"derivation cache: ignored the damaged or foreign entry {path}; rebuilding it")
        return None
    with contextlib.suppress(OSError):
        os.utime(path)  # least recently used = oldest modification time
    return payload


def has_entry(key: str) -> bool:
    """Whether an entry is stored under ``key`` (not read: it may still turn out damaged)."""
    return cache_enabled() and _entry_path(key).is_file()


def entry_damaged(key: str) -> None:
    """Report an entry whose payload turned out unusable (a program that does not check):
    one warning; the caller rebuilds and overwrites it."""
    path = _entry_path(key)
    _warn_once(f"damaged {path}", f"derivation cache: ignored the damaged or foreign entry {path}; rebuilding it")


def _payload(data: bytes, key: str) -> Any:
    header, newline, body = data.partition(b"\n")
    parts = header.split(b" ")
    if not newline or len(parts) != 4 or parts[0] != _MAGIC:
        return None
    if parts[1] != str(FORMAT_VERSION).encode() or parts[2] != key.encode():
        return None
    if hashlib.sha256(body).hexdigest().encode() != parts[3]:
        return None
    try:
        return json.loads(body)
    except ValueError:
        return None


def write_entry(key: str, payload: Any) -> None:
    """Store ``payload`` (JSON-able data) under ``key``, then keep the cache within its
    bound.  A location that cannot be written gives one warning and nothing else."""
    if not cache_enabled():
        return
    from express.base.diagnostics import OutputError
    from express.io.output import write_bytes_now

    body = json.dumps(payload, separators=(",", ":"), sort_keys=True).encode()
    header = b" ".join((_MAGIC, str(FORMAT_VERSION).encode(), key.encode(), hashlib.sha256(body).hexdigest().encode()))
    try:
        write_bytes_now(_entry_path(key), header + b"\n" + body)
    except (OutputError, OSError) as error:
        _warn_once("write", f"derivation cache: cannot write in {cache_directory()} ({error}); working without storing")
        return
    _evict(size_bound())


def memoized_values(kind: str, arguments: Sequence[float], compute: Callable[[], dict[str, float]]) -> dict[str, float]:
    """``compute()`` of a pure numerical function of ``arguments``, kept in the cache by
    the exact arguments (``repr`` of the floats: the same bits or a miss).  The values
    read back are the floats that were computed (JSON keeps a double exactly)."""
    key = entry_key(f"values {kind}", (), {"arguments": [repr(float(x)) for x in arguments]})
    payload = read_entry(key)
    values = payload.get("values") if isinstance(payload, dict) and payload.get("kind") == "values" else None
    if isinstance(values, dict) and values and all(isinstance(v, float) for v in values.values()):
        return dict(values)
    if payload is not None:
        entry_damaged(key)
    result = compute()
    write_entry(key, {"name": f"{kind} values", "kind": "values", "values": {k: float(v) for k, v in result.items()}})
    return result


def _entries() -> list[tuple[Path, os.stat_result]]:
    found = []
    with contextlib.suppress(OSError):
        for path in cache_directory().iterdir():
            if path.suffix == _SUFFIX:
                with contextlib.suppress(OSError):
                    found.append((path, path.stat()))
    return found


def _evict(bound: int) -> None:
    """Remove the least recently used entries until the total size is within ``bound``."""
    entries = sorted(_entries(), key=lambda item: (item[1].st_mtime_ns, item[0].name))
    total = sum(status.st_size for _, status in entries)
    for path, status in entries:
        if total <= bound:
            break
        with contextlib.suppress(OSError):
            path.unlink()
        total -= status.st_size


@dataclass(frozen=True)
class CacheInfo:
    """What :func:`cache_info` reports.

    Attributes
    ----------
    directory : Path
    enabled : bool
    entries : int
    size : int
        Total size of the entries [bytes].
    bound : int
        The size bound [bytes].
    models : tuple of (str, str, int)
        ``(key, model name, size in bytes)`` of every entry, most recently used first.
    """

    directory: Path
    enabled: bool
    entries: int
    size: int
    bound: int
    models: tuple[tuple[str, str, int], ...]


def cache_info() -> CacheInfo:
    """Place, size and entries of the cache."""
    entries = sorted(_entries(), key=lambda item: -item[1].st_mtime_ns)
    models = tuple((path.stem, _entry_name(path), status.st_size) for path, status in entries)
    return CacheInfo(cache_directory(), cache_enabled(), len(entries), sum(m[2] for m in models), size_bound(), models)


def _entry_name(path: Path) -> str:
    """The model name recorded in an entry (read back as data; ``?`` when unreadable)."""
    try:
        with open(path, "rb") as stream:
            payload = _payload(stream.read(size_bound() + 1), path.stem)
    except OSError:
        return "?"
    name = payload.get("name") if isinstance(payload, dict) else None
    return name if isinstance(name, str) else "?"


def clear_cache() -> int:
    """Remove every entry (and stray temporary files); return the number of entries removed."""
    removed = 0
    with contextlib.suppress(OSError):
        for path in cache_directory().iterdir():
            if path.suffix == _SUFFIX or path.name.endswith(".tmp"):
                with contextlib.suppress(OSError):
                    path.unlink()
                    removed += path.suffix == _SUFFIX
    return removed
