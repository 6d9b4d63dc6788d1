"""BLAS threads of the numerical paths: limited while they run, restored afterwards.

The library's matrices are small (tens to a few hundred states): a multithreaded BLAS
only adds thread start-up and, on a busy machine, contention.  On a 2-core machine
with OpenBLAS's default threads a curving ``simulate()`` took 4-5x longer than with
one thread, and a 120 x 120 inverse 70 ms instead of 1 ms.  So the numerical entry
points (``simulate``, eigenvalue sweeps, critical speed, ``frf``, re-evaluation of a
vehicle) run inside :func:`blas_threads`, which sets the BLAS libraries already
loaded (NumPy's and SciPy's) to :func:`blas_limit` threads and restores what they
had when the outermost numerical call returns.

The limit is 1 unless the environment variable ``EXPRESS_BLAS_THREADS`` says otherwise:
a positive integer is the limit, ``0`` or ``none`` leaves BLAS alone (for very large
models, where threads pay).  Limits nest: an inner numerical call inside an outer one
changes nothing, and an explicit ``blas_threads(4)`` around library calls is obeyed by
them.

Examples
--------
>>> import numpy as np
>>> with blas_threads():
...     values = np.linalg.eigvals(np.eye(3))
>>> @limited_blas
... def sweep(matrices):
...     return [np.linalg.eigvals(a) for a in matrices]
"""

from __future__ import annotations

import contextlib
import functools
import importlib
import os
import threading
from collections.abc import Callable, Iterator
from typing import Any, TypeVar

from express.base.diagnostics import UsageError

__all__ = ["ENVIRONMENT_VARIABLE", "blas_limit", "blas_threads", "limited_blas"]

#: Name of the environment variable that sets the limit (``0``/``none``: no limit).
ENVIRONMENT_VARIABLE = "EXPRESS_BLAS_THREADS"

_Function = TypeVar("_Function", bound=Callable[..., Any])

_lock = threading.RLock()
_depth = 0
_controller: Any = None


def blas_limit() -> int | None:
    """The number of BLAS threads numerical calls run with (``None``: not limited).

    Read from ``EXPRESS_BLAS_THREADS`` on every call (default 1).

    Raises
    ------
    UsageError
        (a ``ValueError``) When the variable is set to something else than a
        non-negative integer or ``none``: the CLI prints it as one line, status 2.
    """
    text = os.environ.get(ENVIRONMENT_VARIABLE, "").strip().lower()
    if not text:
        return 1
    if text in ("0", "none"):
        return None
    try:
        limit = int(text)
    except ValueError:
        limit = -1
    if limit < 0:
        raise UsageError(
            f"environment variable {ENVIRONMENT_VARIABLE}={text!r}: expected a number of threads (>= 1), "
            "or 0 or 'none' for no limit"
        )
    return limit


def _blas_controller() -> Any:
    """One ``threadpoolctl`` controller over NumPy's and SciPy's BLAS (built once:
    building one walks the loaded libraries, about a millisecond)."""
    global _controller
    if _controller is None:
        for module in ("numpy", "scipy.linalg"):  # each loads its own BLAS
            importlib.import_module(module)
        from threadpoolctl import ThreadpoolController

        _controller = ThreadpoolController().select(user_api="blas")
    return _controller


@contextlib.contextmanager
def blas_threads(limit: int | str | None = "default") -> Iterator[None]:
    """Run the body with BLAS limited to ``limit`` threads, restored afterwards.

    Parameters
    ----------
    limit : int, None or "default"
        Number of threads (>= 1); ``None``: leave BLAS alone; ``"default"``:
        :func:`blas_limit`.  Inside another ``blas_threads`` the outer limit stays.
    """
    global _depth
    if limit == "default":
        limit = blas_limit()
    with _lock:
        outermost = _depth == 0
        _depth += 1
    try:
        if not outermost or limit is None:
            yield
            return
        libraries = _blas_controller().lib_controllers
        original = [library.num_threads for library in libraries]
        try:
            for library in libraries:
                library.set_num_threads(int(limit))
            yield
        finally:
            for library, threads in zip(libraries, original, strict=True):
                library.set_num_threads(threads)
    finally:
        with _lock:
            _depth -= 1


def limited_blas(function: _Function) -> _Function:
    """Decorator: ``function`` runs inside :func:`blas_threads` (default limit)."""

    @functools.wraps(function)
    def limited(*args: Any, **kwargs: Any) -> Any:
        with blas_threads():
            return function(*args, **kwargs)

    return limited  # type: ignore[return-value]
