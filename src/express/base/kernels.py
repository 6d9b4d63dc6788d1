"""The decorator of the compiled force kernels: :func:`kernel`, Numba's ``njit`` cached and
without its reference counting.

Numba counts the references of every array a compiled function touches: taking an array
out of a NamedTuple (``contacts.tables``), slicing a row or handing an array to another
compiled function increments and decrements a counter through calls into its runtime
(NRT), and its pass that prunes the pairs leaves most of them where a function branches
or can raise.  In the wheel/rail kernels those calls cost more than the arithmetic: the
wheels' rise on their rails (``express.rail.wheel_rise.contact_rise``) took 0.41 us a
call with them and 0.09 us without (2026-12-03, one core), and the Y25 wagon's 30
friction elements took 14 us an evaluation with them and their tables' row views, 1.2-1.4
us without (``docs/benchmarks.md``).

A kernel allocates nothing (no ``np.empty``, no ``.copy()``, no array results): its
caller hands it every array it writes, so it needs no reference counts and is compiled
with Numba's runtime off (the ``_nrt`` option of its dispatcher; a kernel that allocates
fails to compile, loudly).  The arithmetic is the same, so the results are bit for bit
those of a plain ``njit`` (``tests/test_kernels.py``).  Functions that allocate (the
march, which makes its work arrays, and the history and table builders) stay plain
``njit(cache=True)``.

Numba's cache keys a kernel on its own source file only: after editing a kernel that
others inline, clear ``__pycache__/*.nb?`` before timing (a stale caller keeps the old
code).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from numba import njit

__all__ = ["KERNEL_OPTIONS", "kernel"]

#: The options of every kernel: cached, and without Numba's reference counting.
KERNEL_OPTIONS: dict[str, Any] = {"cache": True, "_nrt": False}


def kernel(function: Callable) -> Any:
    """``numba.njit`` with :data:`KERNEL_OPTIONS` (module docstring).

    Parameters
    ----------
    function : callable
        The kernel's Python source (``@kernel`` above it).

    Returns
    -------
    numba.core.registry.CPUDispatcher
        The compiled kernel.
    """
    return njit(**KERNEL_OPTIONS)(function)
