"""BLAS threads of the numerical paths: limited while they run, restored afterwards.

The library's matrices are small (tens to a few hundred states): a multithreaded BLAS
only adds thread start-up and, on a busy machine, contention.  On a 2-core machine
with OpenBLAS's default threads a curving ``simulate()`` took 4-5x longer than with
one thread, and a 120 x 120 inverse 70 ms instead of 1 ms.  So the numerical entry
points (``simulate``, eigenvalue sweeps, critical speed, ``frf``, re-evaluation of a
vehicle) run inside :func:`blas_threads`, which sets the BLAS libraries already
loaded (NumPy's, and SciPy's when it is imported) to :func:`blas_limit` threads and
restores what they had when the outermost numerical call returns; a library first
loaded inside (SciPy imported by the work) starts with the limit too.

The limit is 1 unless the environment variable ``EXPRESS_BLAS_THREADS`` says otherwise:
a positive integer is the limit, ``0`` or ``none`` leaves BLAS alone.  Limits nest: an
inner numerical call inside an outer one changes nothing, and an explicit
``blas_threads(4)`` around library calls is obeyed by them.

One large dense problem may run on more threads (:func:`large_problem_threads`): the
eigendecomposition of a long train's ``A`` (4800 states for 100 cars) runs on
``EXPRESS_BLAS_THREADS_LARGE`` threads (:func:`large_problem_limit`, default 1: no
change) while the default limit holds: ``EXPRESS_BLAS_THREADS`` unset and no explicit
``blas_threads(n)`` outside, in the main thread of a process that is not a worker (a
study's workers keep one thread each: they already share the cores).  The default is
one thread because that was faster where it was measured: on a 2-core machine shared
with other jobs two OpenBLAS threads took 2.2-2.7x longer for the 4800-state
eigenproblem (``docs/benchmarks.md``); on a quiet machine with idle cores
``EXPRESS_BLAS_THREADS_LARGE=2`` (or more) may pay without slowing the small problems.

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
import sys
import threading
from collections.abc import Callable, Iterator
from typing import Any, TypeVar

from express.base.diagnostics import UsageError

__all__ = ["ENVIRONMENT_VARIABLE", "LARGE_ENVIRONMENT_VARIABLE", "LARGE_PROBLEM", "blas_limit", "blas_threads",
           "large_problem_limit", "large_problem_threads", "limited_blas"]

#: Name of the environment variable that sets the limit (``0``/``none``: no limit).
ENVIRONMENT_VARIABLE = "EXPRESS_BLAS_THREADS"
#: Name of the environment variable that sets the threads of one large problem (default 1).
LARGE_ENVIRONMENT_VARIABLE = "EXPRESS_BLAS_THREADS_LARGE"
#: A dense problem of at least this many states (rows) is large: :func:`large_problem_threads`.
LARGE_PROBLEM = 1000

_Function = TypeVar("_Function", bound=Callable[..., Any])

_lock = threading.RLock()
_depth = 0
_default_outside = False  # the outermost blas_threads holds the default limit
_controller: Any = None
_with_scipy = False


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
    """One ``threadpoolctl`` controller over the BLAS libraries loaded: NumPy's, and
    SciPy's once ``scipy.linalg`` is imported (built again then: building one walks the
    loaded libraries, about a millisecond).  SciPy is not imported for it: a command
    that does not use SciPy does not pay its import (0.2 s)."""
    global _controller, _with_scipy
    with_scipy = "scipy.linalg" in sys.modules
    if _controller is None or with_scipy != _with_scipy:
        importlib.import_module("numpy")
        from threadpoolctl import ThreadpoolController

        _controller = ThreadpoolController().select(user_api="blas")
        _with_scipy = with_scipy
    return _controller


#: The variables OpenBLAS, MKL and OpenMP read when their library is loaded.
_LOAD_VARIABLES = ("OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "OMP_NUM_THREADS")


@contextlib.contextmanager
def _loaded_inside(limit: int) -> Iterator[None]:
    """A BLAS library first loaded inside the block (SciPy's, imported by the work) starts
    with ``limit`` threads (the variables its loader reads); afterwards it is given the
    threads NumPy's had before the block, the caller's setting."""
    before = {name: os.environ.get(name) for name in _LOAD_VARIABLES}
    known = {library.filepath for library in _blas_controller().lib_controllers}
    original = [library.num_threads for library in _blas_controller().lib_controllers]
    for name in _LOAD_VARIABLES:
        os.environ[name] = str(limit)
    try:
        yield
    finally:
        for name, value in before.items():
            if value is None:
                os.environ.pop(name, None)
            else:
                os.environ[name] = value
        for library in _blas_controller().lib_controllers:
            if library.filepath not in known and original:
                library.set_num_threads(original[0])


@contextlib.contextmanager
def blas_threads(limit: int | str | None = "default") -> Iterator[None]:
    """Run the body with BLAS limited to ``limit`` threads, restored afterwards.

    Parameters
    ----------
    limit : int, None or "default"
        Number of threads (>= 1); ``None``: leave BLAS alone; ``"default"``:
        :func:`blas_limit`.  Inside another ``blas_threads`` the outer limit stays.
    """
    global _depth, _default_outside
    default = limit == "default"
    if limit == "default":
        limit = blas_limit()
    with _lock:
        outermost = _depth == 0
        _depth += 1
        if outermost:
            _default_outside = default
    try:
        if not outermost or limit is None:
            yield
            return
        with _threads_set(int(limit)), _loaded_inside(int(limit)):
            yield
    finally:
        with _lock:
            _depth -= 1


def large_problem_limit() -> int:
    """Threads for one large dense problem: ``EXPRESS_BLAS_THREADS_LARGE`` (default 1),
    read on every call.

    Raises
    ------
    UsageError
        When the variable is not a positive integer.
    """
    text = os.environ.get(LARGE_ENVIRONMENT_VARIABLE, "").strip()
    if not text:
        return 1
    try:
        limit = int(text)
    except ValueError:
        limit = 0
    if limit < 1:
        raise UsageError(f"environment variable {LARGE_ENVIRONMENT_VARIABLE}={text!r}: expected a number of "
                         "threads (>= 1)")
    return limit


def _may_use_more(states: int) -> bool:
    """A large problem may have more threads than the default limit (module docstring)."""
    if states < LARGE_PROBLEM or os.environ.get(ENVIRONMENT_VARIABLE, "").strip() or large_problem_limit() == 1:
        return False
    if threading.current_thread() is not threading.main_thread():
        return False
    import multiprocessing

    return multiprocessing.parent_process() is None and (_depth == 0 or _default_outside)


@contextlib.contextmanager
def large_problem_threads(states: int) -> Iterator[None]:
    """Run one large dense problem (``states`` rows, e.g. an eigendecomposition) on
    :func:`large_problem_limit` BLAS threads when the default limit holds (module
    docstring); otherwise, for a smaller problem, or with the default of one thread,
    change nothing.

    Parameters
    ----------
    states : int
        Size of the problem (rows of the matrix); large from :data:`LARGE_PROBLEM`.

    Examples
    --------
    >>> import numpy as np
    >>> a = np.eye(1200)
    >>> with blas_threads(), large_problem_threads(a.shape[0]):
    ...     values = np.linalg.eigvals(a)
    """
    if not _may_use_more(states):
        yield
        return
    with _threads_set(large_problem_limit()):
        yield


@contextlib.contextmanager
def _threads_set(count: int) -> Iterator[None]:
    """Every loaded BLAS library on ``count`` threads, each set back to its own on exit."""
    libraries = _blas_controller().lib_controllers
    original = [library.num_threads for library in libraries]
    try:
        for library in libraries:
            library.set_num_threads(count)
        yield
    finally:
        for library, threads in zip(libraries, original, strict=True):
            library.set_num_threads(threads)


def limited_blas(function: _Function) -> _Function:
    """Decorator: ``function`` runs inside :func:`blas_threads` (default limit)."""

    @functools.wraps(function)
    def limited(*args: Any, **kwargs: Any) -> Any:
        with blas_threads():
            return function(*args, **kwargs)

    return limited  # type: ignore[return-value]
