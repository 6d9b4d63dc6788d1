"""Fast critical speed: the crossing located exactly, the reported value unchanged.

:func:`express.analysis.stability.stability.critical_speed` scans the largest real part
``sigma(v)`` of the eigenvalues of ``A(v)`` on a geometric grid of speeds and bisects
the first stable-to-unstable grid cell to a tolerance; it reports the midpoint of the
final bracket and solves about 50 eigenvalue problems of ``A`` (2n x 2n) per call.
This module gives **the same reported value** with fewer of them, and the **exact
crossing** (a Hopf point) besides, which the sensitivities need:

1. the crossing ``(v*, omega*)`` where the eigenvalue ``threshold + j omega*`` lies on
   ``Re lambda = threshold`` is solved by Newton's method on the Hopf system
   ``(A(v) - (threshold + j omega) I) x = 0``, ``c^H x = 1`` (unknowns ``x``, ``omega``
   and ``s = 1/v``; ``A`` is affine in ``s``), a few LU factorizations of a
   (2N + 2)-square real matrix (N states) instead of eigenvalue problems;
2. the bisection of the stability code is then *replayed*: each midpoint is stable
   exactly when it lies below ``v*`` (one crossing inside a grid cell, the same
   assumption the bisection makes), so the midpoint it would have reported follows
   without solving an eigenvalue problem (a midpoint within ``1e-9 v*`` of ``v*`` is
   decided by an eigenvalue problem, as the stability code does);
3. which grid cell holds the first crossing is decided by the grid check:

   ``check = "grid"`` (default)
       every grid speed below the crossing is checked, as the stability code does: the
       value is that of :func:`~express.analysis.stability.stability.critical_speed` (and of
       ``express critical-speed``) with the same options, bit for bit in practice.
   ``check = "local"``
       with a starting guess (the crossing of a similar vehicle: the previous point of a
       study, :class:`CriticalSpeedSearch`), Newton's method starts from it and only the
       grid speed below the crossing, the speed just below it (``v* (1 - 1e-6)``) and the
       grid speed below that came closest to instability lately are checked, with the
       direction of the crossing: 3 eigenvalue problems instead of about 40. A
       heuristic: an instability window that opens at lower speeds away from the
       watched speed is not seen until the next full check (every :data:`REFRESH`
       points, and whenever Newton's method or a check fails).

A vehicle already unstable at ``v_min`` or stable over the whole range is reported as
the stability code reports it (``unstable_at_min``; ``speed`` None).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import scipy.linalg

from express.analysis.stability.critical_options import CriticalOptions
from express.base.diagnostics import ArgumentError
from express.numeric.statespace import VehicleModel

__all__ = ["CriticalOptions", "CriticalResult", "CriticalSpeedSearch", "HopfPoint", "StateBlocks", "fast_critical_speed", "hopf_point"]

#: The search's defaults (:class:`~express.analysis.stability.critical_options.CriticalOptions`).
DEFAULT_OPTIONS = CriticalOptions()

#: Relative step of ``s = 1/v`` below which Newton's method keeps its Jacobian (chord
#: steps: one LU factorization serves the last iterations).
_CHORD = 1e-5

#: Relative distance of a bisection midpoint from the crossing below which the midpoint
#: is decided by solving the eigenvalue problem rather than by comparison.
_REPLAY_GUARD = 1e-9


@dataclass(frozen=True)
class HopfPoint:
    """An eigenvalue of ``A(v)`` on the line ``Re lambda = threshold``.

    Attributes
    ----------
    speed : float
        ``v*`` [m/s].
    omega : float
        Imaginary part of the eigenvalue [rad/s] (>= 0).
    threshold : float
        Its real part [1/s].
    vector : numpy.ndarray, complex, shape (2n,)
        Right eigenvector of ``A(v*)`` (state ``[q; q']``).
    """

    speed: float
    omega: float
    threshold: float
    vector: np.ndarray = field(repr=False)

    @property
    def eigenvalue(self) -> complex:
        return complex(self.threshold, self.omega)

    @property
    def frequency(self) -> float:
        """``omega / 2 pi`` [Hz]."""
        return self.omega / (2.0 * np.pi)


@dataclass(frozen=True)
class CriticalResult:
    """Result of :func:`fast_critical_speed`.

    Attributes
    ----------
    speed : float
        The value :func:`~express.analysis.stability.stability.critical_speed` reports [m/s]
        (bracket midpoint; the exact crossing when ``tolerance`` is 0); ``v_min`` when
        :attr:`unstable_at_min`; nan when stable over the whole range (not :attr:`found`;
        before issue 35 None).
    unstable_at_min : bool
    crossing : HopfPoint or None
        The exact crossing (None when unstable at ``v_min``, stable over the range, or
        when Newton's method failed and plain bisection gave the value).
    evaluations : int
        Eigenvalue problems solved.
    method : str
        ``"local"``, ``"grid"`` or ``"bisection"`` (how the value was found).
    mode_frequency : float
        Frequency of the least stable mode at :attr:`speed` [Hz], without a crossing.
    found : bool
        False when the vehicle is stable over the whole range (as
        :attr:`express.analysis.stability.stability.CriticalSpeed.found`).
    """

    speed: float
    unstable_at_min: bool
    crossing: HopfPoint | None
    evaluations: int
    method: str
    mode_frequency: float = float("nan")
    found: bool = True

    @property
    def reason(self) -> str:
        """Why the search ended, as :attr:`express.analysis.stability.stability.CriticalSpeed.reason`:
        ``"crossing"``, ``"unstable at v_min"`` or ``"stable up to v_max"``."""
        if not self.found:
            return "stable up to v_max"
        return "unstable at v_min" if self.unstable_at_min else "crossing"

    @property
    def frequency(self) -> float:
        """Frequency of the mode that goes unstable [Hz]: that of the crossing, or without
        one that of the least stable mode at :attr:`speed` (nan when stable throughout)."""
        return self.crossing.frequency if self.crossing is not None else self.mode_frequency


class StateBlocks:
    """``A(v) = A0 + A1 / v`` of a vehicle (its state form: ``A1`` is the creep damping),
    assembled as the stability code assembles it."""

    def __init__(self, vehicle: VehicleModel):
        if vehicle.layout is None or not vehicle.wheelsets:
            raise ArgumentError("the model has no rail data (wheelsets): its eigenvalues do not depend on the speed")
        form = getattr(vehicle, "form", None)
        if form is not None:
            self.a0, self.a1 = form.a0, form.a1
        else:  # the second-order form [[0, I], [-M^-1 K, -M^-1 (C0 + C1 / v)]]
            n = vehicle.n
            m_inv = vehicle.mass_inverse
            self.a0 = np.zeros((2 * n, 2 * n))
            self.a1 = np.zeros((2 * n, 2 * n))
            self.a0[:n, n:] = np.eye(n)
            self.a0[n:, :n] = -(m_inv @ vehicle.stiffness)
            self.a0[n:, n:] = -(m_inv @ vehicle.damping_base)
            self.a1[n:, n:] = -(m_inv @ vehicle.damping_creep)
        self.size = self.a0.shape[0]
        self.evaluations = 0

    def matrix(self, speed: float) -> np.ndarray:
        """``A(v)``, shape (N, N)."""
        return self.a0 + self.a1 / speed

    def sigma(self, speed: float) -> float:
        """Largest real part of the eigenvalues of ``A(v)`` [1/s]."""
        self.evaluations += 1
        return float(np.linalg.eigvals(self.matrix(speed)).real.max())


def hopf_point(
    blocks: StateBlocks, speed: float, omega: float, vector: np.ndarray, threshold: float, *, iterations: int = 30
) -> HopfPoint | None:
    """Newton's method on the Hopf system from a guess; None if it does not converge.

    Unknowns ``x = xr + j xi`` (N complex), ``omega`` and ``s = 1/v``; equations
    ``(A(s) - threshold I) xr + omega xi = 0``, ``(A(s) - threshold I) xi - omega xr = 0``,
    ``Re(c^H x) = 1``, ``Im(c^H x) = 0`` with ``c`` the guess (scaled so that
    ``c^H x_guess = 1``); ``A(s) = A0 + s A1``, ``dA/ds = A1``.
    """
    size = blocks.size
    x = np.asarray(vector, dtype=complex)
    scale = np.vdot(x, x).real
    if not (scale > 0 and math.isfinite(scale) and speed > 0):
        return None
    c = x / scale
    cr, ci = c.real, c.imag
    xr, xi = x.real.copy(), x.imag.copy()
    s = 1.0 / speed
    w = float(omega)
    identity = np.eye(size)
    jacobian = np.zeros((2 * size + 2, 2 * size + 2))
    top, bottom = slice(0, size), slice(size, 2 * size)
    jacobian[2 * size, top], jacobian[2 * size, bottom] = cr, ci
    jacobian[2 * size + 1, top], jacobian[2 * size + 1, bottom] = -ci, cr
    factors = None
    for _ in range(iterations):
        b = blocks.a0 + blocks.a1 * s - threshold * identity
        residual = np.concatenate([b @ xr + w * xi, b @ xi - w * xr, [cr @ xr + ci @ xi - 1.0, cr @ xi - ci @ xr]])
        if factors is None:  # Newton's Jacobian; kept once the steps are small (chord steps)
            jacobian[top, top], jacobian[top, bottom] = b, w * identity
            jacobian[bottom, top], jacobian[bottom, bottom] = -w * identity, b
            jacobian[top, 2 * size], jacobian[bottom, 2 * size] = xi, -xr
            jacobian[top, 2 * size + 1], jacobian[bottom, 2 * size + 1] = blocks.a1 @ xr, blocks.a1 @ xi
            try:
                factors = scipy.linalg.lu_factor(jacobian, check_finite=False)
            except (np.linalg.LinAlgError, ValueError):
                return None
        step = scipy.linalg.lu_solve(factors, -residual, check_finite=False)
        if not np.all(np.isfinite(step)):
            return None
        if abs(step[2 * size + 1]) > _CHORD * s:
            factors = None
        xr += step[top]
        xi += step[bottom]
        w += step[2 * size]
        s += step[2 * size + 1]
        if not s > 0:
            return None
        if abs(step[2 * size + 1]) <= 1e-14 * s and abs(step[2 * size]) <= 1e-12 * max(1.0, abs(w)):
            vector = xr + 1j * xi
            if w < 0:  # the conjugate member: keep Im >= 0
                w, vector = -w, vector.conj()
            return HopfPoint(1.0 / s, w, threshold, vector)
    return None


def _replay_bisection(blocks: StateBlocks, lo: float, hi: float, crossing: float, options: CriticalOptions) -> float:
    """The midpoint the stability code's bisection of ``(lo, hi)`` ends with, given the
    crossing inside it (module docstring, step 2)."""
    if options.tolerance == 0:
        return crossing
    threshold = options.threshold
    while hi - lo > options.tolerance:
        mid = 0.5 * (lo + hi)
        if abs(mid - crossing) <= _REPLAY_GUARD * crossing:
            unstable = blocks.sigma(mid) > threshold
        else:
            unstable = mid > crossing
        if unstable:
            hi = mid
        else:
            lo = mid
    return 0.5 * (lo + hi)


def _bisect(blocks: StateBlocks, lo: float, hi: float, options: CriticalOptions) -> float:
    """Plain bisection, as the stability code does it."""
    while hi - lo > max(options.tolerance, 1e-12 * hi):
        mid = 0.5 * (lo + hi)
        if blocks.sigma(mid) > options.threshold:
            hi = mid
        else:
            lo = mid
    return 0.5 * (lo + hi)


def _mode_frequency(blocks: StateBlocks, speed: float) -> float:
    """Frequency [Hz] of the least stable eigenvalue of ``A(v)`` (as the stability code
    reports the mode at the speed it returns)."""
    values = np.linalg.eigvals(blocks.matrix(float(speed)))
    return float(abs(values[int(np.argmax(values.real))].imag) / (2.0 * np.pi))


def _cell(grid: np.ndarray, speed: float) -> int:
    """Index ``i`` of the grid cell ``(grid[i-1], grid[i]]`` holding ``speed``."""
    return int(np.searchsorted(grid, speed, side="left"))


#: Relative distance below a crossing at which every mode must decay: close enough that
#: no other mode crosses in between unnoticed (two bogies' hunting modes cross within
#: 0.1 % of each other), far enough that the crossing mode's own real part is clearly
#: below the threshold (by about 1e-6 v dRe/dv, well above round-off).
_BELOW = 1e-6


def _locally_first(blocks: StateBlocks, crossing: HopfPoint, options: CriticalOptions) -> bool:
    """Stable just below the crossing and the crossing mode's real part rising with v."""
    below = crossing.speed * (1.0 - _BELOW)
    if not below > options.v_min or blocks.sigma(below) > options.threshold:
        return False
    return _real_part_rate(blocks, crossing) > 0


def _real_part_rate(blocks: StateBlocks, crossing: HopfPoint) -> float:
    """``d Re(lambda) / dv`` at the crossing, from the left eigenvector (1 LU)."""
    x = crossing.vector
    left = left_vector(blocks.matrix(crossing.speed), crossing.eigenvalue, x)
    rate = (left.conj() @ (-blocks.a1 / crossing.speed**2) @ x) / (left.conj() @ x)
    return float(rate.real)


def left_vector(a: np.ndarray, eigenvalue: complex, right: np.ndarray) -> np.ndarray:
    """Left eigenvector ``y`` (``y^H A = lambda y^H``) of a simple eigenvalue whose right
    eigenvector is known: the bordered system ``[[A - lambda I, x], [x^H, 0]]^H`` gives
    it without a second eigenvalue problem."""
    n2 = a.shape[0]
    bordered = np.zeros((n2 + 1, n2 + 1), dtype=complex)
    bordered[:n2, :n2] = a - eigenvalue * np.eye(n2)
    bordered[:n2, n2] = right
    bordered[n2, :n2] = right.conj()
    rhs = np.zeros(n2 + 1, dtype=complex)
    rhs[n2] = 1.0
    solution = np.linalg.solve(bordered.conj().T, rhs)
    return solution[:n2]


def _crossing_in_cell(blocks: StateBlocks, lo: float, hi: float, options: CriticalOptions) -> HopfPoint | None:
    """Newton's method from each unstable eigenpair at ``hi``; the lowest crossing inside
    ``(lo, hi]`` that is stable just below it.

    When Newton's method from ``hi`` leads out of the cell (a mode whose real part rises
    and falls again within a few cells: from ``hi`` it finds the falling crossing), it
    starts again from the nearest eigenpair at ``lo``, below the rising one."""
    blocks.evaluations += 1
    values, vectors = np.linalg.eig(blocks.matrix(hi))
    below = None
    found: list[HopfPoint] = []
    for k in np.flatnonzero((values.real > options.threshold) & (values.imag >= 0)):
        point = hopf_point(blocks, hi, float(values[k].imag), vectors[:, k], options.threshold)
        if point is None or not lo < point.speed <= hi:
            if below is None:
                blocks.evaluations += 1
                below = np.linalg.eig(blocks.matrix(lo))
            j = int(np.argmin(np.abs(below[0] - values[k]) + np.where(below[0].imag >= 0, 0.0, np.inf)))
            point = hopf_point(blocks, lo, float(below[0][j].imag), below[1][:, j], options.threshold)
        if point is not None and lo < point.speed <= hi:
            found.append(point)
    for point in sorted(found, key=lambda p: p.speed):
        if _locally_first(blocks, point, options):
            return point
    return None


def fast_critical_speed(
    vehicle: VehicleModel | StateBlocks, options: CriticalOptions = DEFAULT_OPTIONS, guess: HopfPoint | None = None
) -> CriticalResult:
    """Critical speed as :func:`~express.analysis.stability.stability.critical_speed` reports it,
    with the exact crossing (module docstring).

    Parameters
    ----------
    vehicle : VehicleModel or StateBlocks
    options : CriticalOptions
    guess : HopfPoint, optional
        The crossing of a similar vehicle (used with ``options.check == "local"``).

    Returns
    -------
    CriticalResult
    """
    search = CriticalSpeedSearch(options)
    search.crossing = guess
    return search(vehicle)


#: ``check = "local"``: grid speeds below the crossing checked besides the one just
#: below it, chosen by the largest real part seen there lately (unknown ones first).
WATCHED = 1
#: ``check = "local"``: points after which the whole grid is checked again.
REFRESH = 64


class CriticalSpeedSearch:
    """Critical speeds of a sequence of similar vehicles (the points of a worker).

    With ``check = "local"`` it keeps, from one vehicle to the next, the last crossing
    (the starting guess of Newton's method) and, for each grid speed, the largest real
    part seen there since the last full check: besides the grid speed below the crossing
    and the speed just below it, the :data:`WATCHED` grid speeds below the crossing
    (``v_min`` among them) that came closest to instability are checked (an instability
    window that opens at lower speeds, or at ``v_min``, is announced there by a mode
    approaching the axis), and every :data:`REFRESH` points the whole grid. A heuristic: a window that opens away from the
    watched speeds is missed until the next full check; ``check = "grid"`` checks every
    grid speed every time.

    Parameters
    ----------
    options : CriticalOptions
    """

    def __init__(self, options: CriticalOptions = DEFAULT_OPTIONS):
        self.options = options
        self.grid = options.grid
        self.crossing: HopfPoint | None = None
        self.sigma = np.full(self.grid.size, np.nan)
        self.since_grid = 0

    def _sigma(self, blocks: StateBlocks, j: int) -> float:
        value = blocks.sigma(float(self.grid[j]))
        self.sigma[j] = max(value, self.sigma[j]) if np.isfinite(self.sigma[j]) else value
        return value

    def __call__(self, vehicle: VehicleModel | StateBlocks) -> CriticalResult:
        blocks = vehicle if isinstance(vehicle, StateBlocks) else StateBlocks(vehicle)
        blocks.evaluations = 0
        if self.options.check == "local" and self.crossing is not None and self.since_grid < REFRESH:
            result = self._local(blocks)
            if result is not None:
                self.since_grid += 1
                self.crossing = result.crossing
                return result
        result = self._grid(blocks)
        self.since_grid = 0
        if result.crossing is not None:
            self.crossing = result.crossing
        return result

    def _grid(self, blocks: StateBlocks) -> CriticalResult:
        options, grid = self.options, self.grid
        self.sigma[:] = np.nan  # a full check starts the record again
        if self._sigma(blocks, 0) > options.threshold:
            self.sigma[0] = np.nan
            return CriticalResult(float(grid[0]), True, None, blocks.evaluations, "grid", _mode_frequency(blocks, grid[0]))
        first = next((i for i in range(1, grid.size) if self._sigma(blocks, i) > options.threshold), None)
        if first is None:
            return CriticalResult(float("nan"), False, None, blocks.evaluations, "grid", found=False)
        lo, hi = float(grid[first - 1]), float(grid[first])
        crossing = _crossing_in_cell(blocks, lo, hi, options)
        if crossing is None:
            speed = _bisect(blocks, lo, hi, options)
            return CriticalResult(speed, False, None, blocks.evaluations, "bisection", _mode_frequency(blocks, speed))
        speed = _replay_bisection(blocks, lo, hi, crossing.speed, options)
        return CriticalResult(speed, False, crossing, blocks.evaluations, "grid")

    def _local(self, blocks: StateBlocks) -> CriticalResult | None:
        """Newton's method from the last crossing, checked locally; None to fall back."""
        options, grid = self.options, self.grid
        guess = self.crossing
        assert guess is not None
        crossing = hopf_point(blocks, guess.speed, guess.omega, guess.vector, options.threshold)
        if crossing is None or not (grid[0] < crossing.speed <= grid[-1]):
            return None
        i = _cell(grid, crossing.speed)
        below = np.arange(0, i - 1)
        seen = np.where(np.isnan(self.sigma[below]), np.inf, self.sigma[below])
        watched = below[np.argsort(-seen, kind="stable")[:WATCHED]]
        for j in [*watched.tolist(), i - 1] if i > 1 else []:
            if self._sigma(blocks, j) > options.threshold:
                return None
        if not _locally_first(blocks, crossing, options):
            return None
        lo, hi = float(grid[i - 1]), float(grid[i])
        speed = _replay_bisection(blocks, lo, hi, crossing.speed, options)
        return CriticalResult(speed, False, crossing, blocks.evaluations, "local")
