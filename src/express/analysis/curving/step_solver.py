"""The linear solve of a pseudo-transient step: ``(I / h - J) d = f``.

The steady-curving solver (:mod:`express.analysis.curving.steady`) solves one such
system per step, ``J`` the state matrix ``A`` plus the contact's slopes on the wheelset
rows.  For a single car a dense LU is the fastest.  A long train's ``A`` couples each car
only with its neighbours (the 100-car train: 25 188 non-zeros of 23 million), so from
:data:`SPARSE_FROM` states up ``J`` is kept sparse and each step solved by a sparse LU
(SuperLU through :func:`scipy.sparse.linalg.splu`: a fill-reducing column order and
partial pivoting, the backward stability of the dense solve): for that train about 0.1 s
a step instead of seconds, and no dense ``J`` is ever formed.
"""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["SPARSE_FROM", "StepSolver"]

#: From this many states up the steps are solved sparse (below, dense: the same bits as before).
SPARSE_FROM = 400


class StepSolver:
    """``solver(h, J, f)``: the step ``d`` of ``(I / h - J) d = f``; ``J`` (n, n) dense, or a
    SciPy sparse matrix when :attr:`sparse`; ``f`` (n,).

    Examples
    --------
    >>> j = -np.diag([1.0, 2.0]) + np.diag([0.5], 1)
    >>> StepSolver(2)(0.1, j, np.array([1.0, 1.0])).round(6).tolist()
    [0.094697, 0.083333]
    """

    def __init__(self, n: int, sparse_from: int | None = None):
        self.sparse = n >= (SPARSE_FROM if sparse_from is None else sparse_from)
        self.n = n
        self._identity: Any = None

    def __call__(self, step: float, jacobian: Any, f: np.ndarray) -> np.ndarray:
        if self._identity is None:
            if self.sparse:
                from scipy import sparse

                self._identity = sparse.identity(self.n, format="csc")
            else:
                self._identity = np.eye(self.n)
        return self.solve(self._identity / step - jacobian, f)

    def solve(self, system: Any, f: np.ndarray) -> np.ndarray:
        """``x`` of ``system x = f`` on the same route (the linear steady state: ``A x = -e``)."""
        if not self.sparse:
            return np.linalg.solve(system, f)
        from scipy import sparse
        from scipy.sparse.linalg import splu

        try:
            return splu(sparse.csc_matrix(system)).solve(np.asarray(f, dtype=float))
        except RuntimeError as error:  # SuperLU: "Factor is exactly singular"
            raise np.linalg.LinAlgError(f"singular matrix ({error})") from None
