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
header holding the format, the key and an HMAC of the key and payload under the user's
secret; the files are opened, written and removed by :mod:`express.io.cache_files`
(private folder, no link followed, no special file opened, a new file renamed into
place), so a reader sees a whole entry or none, concurrent writers leave a valid one,
and a link planted in the folder is never written through.  A truncated, corrupted,
foreign or re-signed entry is ignored with one warning and rebuilt.  Nothing read is
executed or evaluated; no ``pickle``.

Place: ``EXPRESS_CACHE_DIR``, else the user's cache directory (:mod:`platformdirs`,
``~/.cache/express`` on Linux), sub-folder ``derivations``.  ``EXPRESS_NO_CACHE=1`` or
``--no-cache`` (:func:`disabled`) switches it off.  Size bound: ``EXPRESS_CACHE_MB``
(default :data:`DEFAULT_SIZE_MB`); when a write passes it, the least recently used
entries (file modification time, renewed at every hit) are removed.  A location that
cannot be written is used for reading only, with one warning; a folder that is a link,
another user's or writable by others is not used at all (one warning).
"""

from __future__ import annotations

import contextlib
import contextvars
import hashlib
import hmac
import json
import math
import os
import re
import stat
import warnings
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from express.base.limits import limit
from express.io.cache_files import (
    Folder,
    entry_signature,
    open_folder,
    own_files,
    read_private,
    remove_own,
    write_private,
)

__all__ = [
    "DEFAULT_SIZE_MB",
    "FORMAT_VERSION",
    "CacheInfo",
    "cache_directory",
    "cache_enabled",
    "cache_info",
    "clear_cache",
    "disabled",
    "entry_bound",
    "entry_key",
    "has_entry",
    "memoized_values",
    "read_entry",
    "write_entry",
]

#: Version of the entry format; a new one makes every older entry a miss.
FORMAT_VERSION = 2
#: Default size bound of the cache [MB] (``EXPRESS_CACHE_MB`` changes it).
DEFAULT_SIZE_MB = 512
_MAGIC = b"EXPRESS-DERIVATION-CACHE"
_SUFFIX = ".json"
_KEY = re.compile(r"[0-9a-f]{64}")
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


def _folder(*, write: bool) -> Folder:
    """The cache folder checked (:func:`express.io.cache_files.open_folder`); one warning
    when it is refused (a link, another owner, other writers)."""
    folder = open_folder(cache_directory(), create=write)
    if folder.refused is not None:
        _warn_once(f"refused {folder.path}", f"derivation cache: {folder.path} {folder.refused}; "
                   "working without the cache")
    return folder


def entry_bound() -> int:
    """The largest entry read or written [bytes]: the input file size limit
    (``EXPRESS_MAX_FILE_MB``, :mod:`express.base.limits`), within the cache's bound.

    An entry is smaller than the model file it derives from (the 100-car train's: 0.53 MB),
    so a larger one is not this program's and is not parsed.
    """
    return min(size_bound(), limit("file_mb") * 1024 * 1024)


def read_entry(key: str) -> Any:
    """The payload stored under ``key``, or ``None`` (no entry, the cache off, or an entry
    that is damaged, foreign or not a regular file of this user: then one warning, and
    the caller rebuilds it)."""
    if not cache_enabled() or not _KEY.fullmatch(key):
        return None
    folder = _folder(write=False)
    if not folder.usable:
        return None
    assert folder.secret is not None
    path = folder.path / f"{key}{_SUFFIX}"
    data = read_private(path, entry_bound())
    if data is None:
        return None
    payload = _payload(data, key, folder.secret) if isinstance(data, bytes) else None
    if payload is None:
        reason = f" ({data})" if isinstance(data, str) else ""
        _warn_once(f"damaged {path}", f"derivation cache: ignored the damaged or foreign entry {path}{reason}; rebuilding it")
        return None
    with contextlib.suppress(OSError):
        os.utime(path, follow_symlinks=False)  # least recently used = oldest modification time
    return payload


def has_entry(key: str) -> bool:
    """Whether an entry is stored under ``key`` (not read: it may still turn out damaged)."""
    if not cache_enabled():
        return False
    with contextlib.suppress(OSError):
        return stat.S_ISREG(os.lstat(_entry_path(key)).st_mode)
    return False


def entry_damaged(key: str) -> None:
    """Report an entry whose payload turned out unusable (a program that does not check):
    one warning; the caller rebuilds and overwrites it."""
    path = _entry_path(key)
    _warn_once(f"damaged {path}", f"derivation cache: ignored the damaged or foreign entry {path}; rebuilding it")


def _payload(data: bytes, key: str, secret: bytes) -> Any:
    header, newline, body = data.partition(b"\n")
    parts = header.split(b" ")
    if not newline or len(parts) != 4 or parts[0] != _MAGIC:
        return None
    if parts[1] != str(FORMAT_VERSION).encode() or parts[2] != key.encode():
        return None
    if not hmac.compare_digest(entry_signature(secret, key, body).encode(), parts[3]):
        return None
    try:
        return checked_json(body)
    except ValueError:
        return None


def write_entry(key: str, payload: Any) -> None:
    """Store ``payload`` (JSON-able data) under ``key``, then keep the cache within its
    bound.  A location that cannot be written gives one warning and nothing else."""
    if not cache_enabled() or not _KEY.fullmatch(key):
        return
    folder = _folder(write=True)
    if folder.refused is not None:
        return
    body = json.dumps(payload, separators=(",", ":"), sort_keys=True).encode()
    if len(body) + 200 > entry_bound():  # it would never be read back
        return
    try:
        if folder.secret is None or not folder.writable:
            raise PermissionError("the folder cannot be written")
        signature = entry_signature(folder.secret, key, body).encode()
        header = b" ".join((_MAGIC, str(FORMAT_VERSION).encode(), key.encode(), signature))
        write_private(folder.path, f"{key}{_SUFFIX}", header + b"\n" + body)
    except OSError as error:
        reason = getattr(error, "strerror", None) or error
        _warn_once("write", f"derivation cache: cannot write in {folder.path} ({reason}); working without storing")
        return
    _evict(folder.path, size_bound())


def memoized_values(kind: str, arguments: Sequence[float], compute: Callable[[], dict[str, float]],
                    valid: Callable[[dict[str, float]], bool] | None = None) -> dict[str, float]:
    """``compute()`` of a pure numerical function of ``arguments``, kept in the cache by
    the exact arguments (``repr`` of the floats: the same bits or a miss).  The values
    read back are the floats that were computed (JSON keeps a double exactly); they are
    used only when they are finite and pass ``valid`` (the check the computation's own
    results pass), else the entry is damaged: one warning, computed anew."""
    key = entry_key(f"values {kind}", (), {"arguments": [repr(float(x)) for x in arguments]})
    payload = read_entry(key)
    values = payload.get("values") if isinstance(payload, dict) and payload.get("kind") == "values" else None
    if (isinstance(values, dict) and values and all(type(v) is float and math.isfinite(v) for v in values.values())
            and (valid is None or valid(values))):
        return dict(values)
    if payload is not None:
        entry_damaged(key)
    result = compute()
    write_entry(key, {"name": f"{kind} values", "kind": "values", "values": {k: float(v) for k, v in result.items()}})
    return result


def checked_json(body: bytes) -> Any:
    """``json.loads`` of an entry's payload; ValueError for JSON nested beyond what the
    parser takes (an entry of 100 000 nested arrays), as for any other bad JSON."""
    try:
        return json.loads(body)
    except RecursionError:
        raise ValueError("nested too deeply") from None


def _entries(directory: Path) -> list[tuple[str, os.stat_result]]:
    return list(own_files(directory))


def _evict(directory: Path, bound: int) -> None:
    """Remove the least recently used entries until the total size is within ``bound``."""
    entries = sorted(_entries(directory), key=lambda item: (item[1].st_mtime_ns, item[0]))
    total = sum(status.st_size for _, status in entries)
    for name, status in entries:
        if total <= bound:
            break
        remove_own(directory, name)
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
    refused : str or None
        Why the folder is not used (a link, another owner, other writers), or None.
    """

    directory: Path
    enabled: bool
    entries: int
    size: int
    bound: int
    models: tuple[tuple[str, str, int], ...]
    refused: str | None = None


def cache_info() -> CacheInfo:
    """Place, size and entries of the cache (only the entries of its own shape: regular
    files of this user named by a key)."""
    folder = _folder(write=False)
    found = [] if folder.refused is not None else _entries(folder.path)
    entries = sorted(found, key=lambda item: -item[1].st_mtime_ns)
    models = tuple((name[: -len(_SUFFIX)], _entry_name(folder, name), status.st_size) for name, status in entries)
    return CacheInfo(folder.path, cache_enabled(), len(entries), sum(m[2] for m in models), size_bound(), models,
                     folder.refused)


def _entry_name(folder: Folder, name: str) -> str:
    """The model name recorded in an entry (read back as data; ``?`` when unreadable),
    printable characters only."""
    data = read_private(folder.path / name, entry_bound()) if folder.usable else None
    payload = _payload(data, name[: -len(_SUFFIX)], folder.secret) if isinstance(data, bytes) and folder.secret else None
    recorded = payload.get("name") if isinstance(payload, dict) else None
    return "".join(c if c.isprintable() else "?" for c in recorded) if isinstance(recorded, str) else "?"


def clear_cache() -> int:
    """Remove every entry (and stray temporary files) — only regular files of this user
    named as the cache names them, never through a link; return the number of entries removed."""
    folder = _folder(write=False)
    if folder.refused is not None:
        return 0
    removed = 0
    for name, _ in list(own_files(folder.path, temporaries=True)):
        if remove_own(folder.path, name):
            removed += name.endswith(_SUFFIX)
    return removed
