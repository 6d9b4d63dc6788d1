"""Where Numba keeps the compiled kernels: a writable folder, so they compile only once.

Numba stores a kernel compiled with ``cache=True`` next to its source (``__pycache__``)
and, when that folder cannot be written (an install in a read-only site-packages), in
its own user cache; when neither can be written it refuses the kernel.  EXPRESS points
Numba at ``<cache>/numba`` (``EXPRESS_CACHE_DIR``, else the user's cache directory,
:mod:`express.io.cache`) whenever the package's own folder is read-only and
``NUMBA_CACHE_DIR`` is not set already.  It must run before Numba is imported:
``express/__init__.py`` calls :func:`configure_kernel_cache`.

The first run after installing compiles the kernels it uses (tens of seconds);
:func:`compilation_note` names what a run compiled, and the command line prints it, so the
wait is explained once and not mistaken for the normal cost of a command.
"""

from __future__ import annotations

import os
import sys
from collections.abc import MutableMapping
from pathlib import Path

__all__ = ["compilation_note", "compiled_kernels", "configure_kernel_cache", "express_cache_root"]

#: Set to 0 to leave out the note on compiled kernels (the test session does: its first
#: command on a fresh machine would print it).
NOTE_VARIABLE = "EXPRESS_COMPILE_NOTE"


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


def compiled_kernels() -> tuple[str, ...]:
    """The package's Numba kernels compiled in this process rather than loaded from
    Numba's cache (sorted ``module.function`` names; empty when Numba is not loaded)."""
    if "numba" not in sys.modules:
        return ()
    from numba.core.dispatcher import Dispatcher

    found = set()
    for name, module in list(sys.modules.items()):
        if name.startswith("express.") and module is not None:
            for value in list(vars(module).values()):
                if isinstance(value, Dispatcher) and value.stats.cache_misses:
                    found.add(f"{value.py_func.__module__}.{value.py_func.__name__}")
    return tuple(sorted(found))


def compilation_note(seconds: float, environ: MutableMapping[str, str] | None = None) -> str | None:
    """A line for the user when this run compiled kernels (None otherwise, or when
    ``EXPRESS_COMPILE_NOTE=0``): how many, the run's time and where they are kept."""
    environ = os.environ if environ is None else environ
    if environ.get(NOTE_VARIABLE, "1") == "0":
        return None
    kernels = compiled_kernels()
    if not kernels:
        return None
    folder = environ.get("NUMBA_CACHE_DIR")
    where = f"in {folder}" if folder else "next to the package's sources"
    return (f"note: compiled {len(kernels)} Numba kernel{'s' if len(kernels) > 1 else ''} in this run "
            f"({seconds:.0f} s for the whole command), once per installation: they are kept {where} and later runs "
            "load them")
