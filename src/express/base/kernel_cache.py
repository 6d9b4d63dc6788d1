"""Where Numba keeps the compiled kernels: a writable folder, so they compile only once.

Numba stores a kernel compiled with ``cache=True`` next to its source (``__pycache__``)
and, when that folder cannot be written (an install in a read-only site-packages), in
its own user cache; when neither can be written it refuses the kernel.  EXPRESS points
Numba at ``<cache>/numba`` (``EXPRESS_CACHE_DIR``, else the user's cache directory,
:mod:`express.io.cache`) whenever the package's own folder is read-only and
``NUMBA_CACHE_DIR`` is not set already.  It must run before Numba is imported:
``express/__init__.py`` calls :func:`configure_kernel_cache`.
"""

from __future__ import annotations

import os
from collections.abc import MutableMapping
from pathlib import Path

__all__ = ["configure_kernel_cache", "express_cache_root"]


def express_cache_root(environ: MutableMapping[str, str] | None = None) -> Path:
    """``EXPRESS_CACHE_DIR``, else the user's cache directory for EXPRESS (platformdirs)."""
    environ = os.environ if environ is None else environ
    root = environ.get("EXPRESS_CACHE_DIR")
    if root:
        return Path(root)
    import platformdirs

    return Path(platformdirs.user_cache_dir("express", appauthor=False))


def configure_kernel_cache(package: Path | None = None, environ: MutableMapping[str, str] | None = None) -> str | None:
    """Set ``NUMBA_CACHE_DIR`` to ``<cache>/numba`` when the package folder is read-only.

    Parameters
    ----------
    package : Path, optional
        The package folder (default: this package's).
    environ : mutable mapping, optional
        The environment to read and change (default ``os.environ``).

    Returns
    -------
    str or None
        The folder set, or None when nothing was changed (``NUMBA_CACHE_DIR`` given, or
        the package folder writable: Numba's ``__pycache__`` serves).
    """
    environ = os.environ if environ is None else environ
    package = Path(__file__).resolve().parents[1] if package is None else package
    if environ.get("NUMBA_CACHE_DIR") or _writable(package):
        return None
    folder = str(express_cache_root(environ) / "numba")
    environ["NUMBA_CACHE_DIR"] = folder
    return folder


def _writable(folder: Path) -> bool:
    cache = folder / "__pycache__"
    return os.access(cache if cache.is_dir() else folder, os.W_OK)
