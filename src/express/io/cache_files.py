"""The derivation cache's files on disk, safe against links, special files and other users.

The cache folder is a place other people or programs may reach (a shared machine, a
folder planted in advance at a predictable name), so nothing here trusts what it finds
(``docs/cache.md``, "Threat model"):

- the folder is made private (``0700``); a folder that is a symbolic link, is owned by
  another user or can be written by other users is refused (one warning; the command
  works without the cache);
- an entry is opened without following a link and without blocking (``O_NOFOLLOW``,
  ``O_NONBLOCK``) and used only when it is a regular file of this user within the size
  bound: a link, a FIFO or a device in its place is never read, written through or
  removed;
- an entry is written as a new private file (``0600``, ``O_EXCL``) renamed over its
  name, which replaces a link planted there instead of writing through it;
- an entry carries an HMAC-SHA-256 of its key and payload under a secret of this user
  (``<folder>/.secret``, 32 random bytes, ``0600``): an entry copied from elsewhere,
  renamed to another key or edited is not this cache's;
- only names of the cache's own shape (64 hexadecimal digits, ``.json``; its temporary
  files) are listed, evicted or cleared, through the folder's own descriptor.

What it cannot defend against is a process running as the same user: it can read the
secret.  That is the user's own account, outside any program's reach.
"""

from __future__ import annotations

import contextlib
import hashlib
import hmac
import os
import re
import secrets
import stat
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

from express.base.interrupts import release, temporary_file

__all__ = ["ENTRY_NAME", "Folder", "entry_signature", "open_folder", "own_files", "read_private", "remove_own",
           "write_private"]

#: The name of an entry: its key (SHA-256, hexadecimal) and ``.json``.
ENTRY_NAME = re.compile(r"[0-9a-f]{64}\.json")
#: The name of an entry's temporary file while it is written.
_TEMPORARY_NAME = re.compile(r"\.[0-9a-f]{64}\.json\.[0-9a-f]{16}\.tmp")
_SECRET = ".secret"
_SECRET_BYTES = 32


@dataclass(frozen=True)
class Folder:
    """The cache folder, checked.

    Attributes
    ----------
    path : Path
    secret : bytes or None
        This user's signing secret; None when there is none and none can be made (a
        read-only place that never held a cache: nothing in it can be trusted).
    writable : bool
        Whether entries can be written.
    refused : str or None
        Why the folder may not be used at all (a link, another owner, other writers,
        no permission to read it); None for a usable folder.
    """

    path: Path
    secret: bytes | None
    writable: bool
    refused: str | None = None

    @property
    def usable(self) -> bool:
        """Whether entries can be read (the folder is safe and has a secret)."""
        return self.refused is None and self.secret is not None


def open_folder(path: Path, *, create: bool) -> Folder:
    """Check (and with ``create`` make, private) the cache folder ``path``.

    A missing folder that is not to be made is a usable, empty and unwritable one.
    """
    if create:
        _make_private(path)
    try:
        status = os.lstat(path)
    except OSError:  # missing, or a path through a file: nothing to read, nowhere to write
        return Folder(path, None, False)
    refused = _unsafe(status, "is a symbolic link") or _unsafe_parent(path.parent)
    if not refused and not os.access(path, os.R_OK | os.X_OK):
        refused = "cannot be read by this user (permission denied)"
    if refused:
        return Folder(path, None, False, refused)
    writable = os.access(path, os.W_OK | os.X_OK)
    return Folder(path, _secret(path, make=writable), writable)


def _make_private(path: Path) -> None:
    missing = []
    directory = path
    while not os.path.lexists(directory) and directory != directory.parent:
        missing.append(directory)
        directory = directory.parent
    for folder in reversed(missing):
        try:
            os.mkdir(folder, 0o700)
            os.chmod(folder, 0o700)  # the umask may have taken bits the mode gave
        except FileExistsError:
            continue
        except OSError:
            return


def _unsafe(status: os.stat_result, link: str) -> str | None:
    if stat.S_ISLNK(status.st_mode):
        return link
    if not stat.S_ISDIR(status.st_mode):
        return "is not a folder"
    if status.st_uid != os.geteuid():
        return "is owned by another user"
    if status.st_mode & 0o022:
        return "can be written by other users (make it private: chmod 700)"
    return None


def _unsafe_parent(parent: Path) -> str | None:
    """A parent that others may write may have the folder swapped under it, unless it is
    sticky (``/tmp``): then only the folder's owner may rename it."""
    try:
        status = os.stat(parent)
    except OSError:
        return None
    if status.st_mode & 0o022 and not status.st_mode & stat.S_ISVTX:
        return f"is in {parent}, which other users can write"
    return None


def _secret(folder: Path, *, make: bool) -> bytes | None:
    path = folder / _SECRET
    found = read_private(path, _SECRET_BYTES)
    if isinstance(found, bytes) and len(found) == _SECRET_BYTES:
        return found
    if not make:
        return None
    with contextlib.suppress(OSError):
        if found is not None:  # damaged or foreign: a new secret makes every entry a miss
            os.unlink(path)
        write_private(folder, _SECRET, secrets.token_bytes(_SECRET_BYTES), replace=False)
    found = read_private(path, _SECRET_BYTES)
    return found if isinstance(found, bytes) and len(found) == _SECRET_BYTES else None


def entry_signature(secret: bytes, key: str, body: bytes) -> str:
    """HMAC-SHA-256 of the entry's key and payload under the user's secret (hexadecimal)."""
    return hmac.new(secret, key.encode() + b"\n" + body, hashlib.sha256).hexdigest()


def read_private(path: Path, limit: int) -> bytes | str | None:
    """The bytes of ``path`` if it is a regular file of this user of at most ``limit``
    bytes; else the reason it is refused (a str), or None when there is no such file.

    Never follows a link, never waits on a FIFO or a device.
    """
    flags = os.O_RDONLY | getattr(os, "O_NOFOLLOW", 0) | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_CLOEXEC", 0)
    try:
        handle = os.open(path, flags)
    except FileNotFoundError:
        return None
    except OSError as error:
        if stat.S_ISLNK(_lmode(path)):
            return "a symbolic link"
        return f"cannot be read ({error.strerror or error})"
    try:
        status = os.fstat(handle)
        if not stat.S_ISREG(status.st_mode):
            return "not a regular file"
        if status.st_uid != os.geteuid():
            return "owned by another user"
        if status.st_size > limit:
            return f"larger than the bound ({status.st_size} bytes)"
        chunks, left = [], limit + 1
        while left > 0:
            chunk = os.read(handle, min(left, 1 << 20))
            if not chunk:
                break
            chunks.append(chunk)
            left -= len(chunk)
        data = b"".join(chunks)
        return data if len(data) <= limit else f"larger than the bound ({len(data)} bytes)"
    except OSError as error:
        return f"cannot be read ({error.strerror or error})"
    finally:
        os.close(handle)


def _lmode(path: Path) -> int:
    try:
        return os.lstat(path).st_mode
    except OSError:
        return 0


def write_private(folder: Path, name: str, data: bytes, *, replace: bool = True) -> None:
    """Write ``folder/name`` whole or not at all as a new private file (``0600``).

    The data goes to a new temporary file (``O_EXCL``: never an existing file or link),
    is synced, and is renamed over ``name``: a link planted at ``name`` is replaced, not
    written through.  With ``replace`` False an existing ``name`` is kept (``FileExistsError``).

    Raises
    ------
    OSError
        When the folder cannot be written.
    """
    handle, temporary = temporary_file(folder, prefix=f".{name}.", suffix=".tmp")
    try:
        with os.fdopen(handle, "wb") as stream:
            stream.write(data)
            stream.flush()
            os.fsync(stream.fileno())
        if replace:
            os.replace(temporary, folder / name)
        else:
            os.link(temporary, folder / name)  # fails on an existing name, as O_EXCL
            os.unlink(temporary)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(temporary)
        raise
    finally:
        release(temporary)


def own_files(folder: Path, *, temporaries: bool = False) -> Iterator[tuple[str, os.stat_result]]:
    """``(name, status)`` of the regular files of this user in ``folder`` named as entries
    (and, with ``temporaries``, as their temporary files); links and anything else are
    passed over.  The folder is read through its own descriptor, never through a link."""
    handle = _folder_handle(folder)
    if handle is None:
        return
    try:
        with os.scandir(handle) as listing:
            found = [entry.name for entry in listing]
        for name in sorted(found):
            if not (ENTRY_NAME.fullmatch(name) or (temporaries and _TEMPORARY_NAME.fullmatch(name))):
                continue
            with contextlib.suppress(OSError):
                status = os.stat(name, dir_fd=handle, follow_symlinks=False)
                if stat.S_ISREG(status.st_mode) and status.st_uid == os.geteuid():
                    yield name, status
    except OSError:
        return
    finally:
        os.close(handle)


def remove_own(folder: Path, name: str) -> bool:
    """Remove ``folder/name`` if it is still a regular file of this user named as an entry
    or a temporary file (checked through the folder's descriptor); whether it was."""
    if not (ENTRY_NAME.fullmatch(name) or _TEMPORARY_NAME.fullmatch(name)):
        return False
    handle = _folder_handle(folder)
    if handle is None:
        return False
    try:
        status = os.stat(name, dir_fd=handle, follow_symlinks=False)
        if not (stat.S_ISREG(status.st_mode) and status.st_uid == os.geteuid()):
            return False
        os.unlink(name, dir_fd=handle)
        return True
    except OSError:
        return False
    finally:
        os.close(handle)


def _folder_handle(folder: Path) -> int | None:
    flags = os.O_RDONLY | getattr(os, "O_DIRECTORY", 0) | getattr(os, "O_NOFOLLOW", 0) | getattr(os, "O_CLOEXEC", 0)
    try:
        return os.open(folder, flags)
    except OSError:
        return None
