"""Running stability: eigenvalues, root locus and critical speed (paper section 4.4, Fig. 11).

The state matrix of the linear vehicle (straight track, no flange contact, no creep
saturation) is ``A(v) = [[0, I], [-M^-1 K, -M^-1 (C0 + C1 / v)]]`` (``rail.md``): the
speed enters only through the creep damping ``C1 / v``. Its eigenvalues
``lambda = Re + j Im`` [1/s] give the free motions ``exp(lambda t)``; the vehicle is
stable at ``v`` when every real part is negative. The **critical speed** ``v_cr`` is the
lowest speed at which the largest real part turns from negative to positive.

Functions
---------
eigen_analysis
    Every mode at one speed (one of each conjugate pair), sorted least stable first,
    each with its frequency, damping ratio, dominant DOFs and a short label.
root_locus
    Eigenvalues at many speeds at once (about 0.25 ms per speed for the 24-DOF car).
critical_speed
    Coarse geometric scan of the largest real part, then bisection of the first
    stable-to-unstable bracket to ``tolerance_kmh``.
critical_speed_vs_conicity
    ``critical_speed`` for each value of a parameter (the tread conicity ``Gamma`` by
    default), re-evaluating the matrices with :meth:`VehicleModel.with_values`.

Examples
--------
>>> from express.io import load_model
>>> from express.numeric.statespace import vehicle_model
>>> car = vehicle_model(load_model("examples/conventional.toml"))
>>> result = eigen_analysis(car, 30.0)
>>> result.modes[0].real < 0          # stable at 30 m/s
True
>>> cs = critical_speed(car)
>>> round(cs.speed_kmh)
421
>>> cs.mode.describe()
'hunting, both bogies (W1.y, T1.y, W3.y)'
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import replace
from typing import Any

import numpy as np

from express.analysis.modes.modes import EigenResult, Mode, modes_of
from express.analysis.stability.critical_options import CriticalOptions
from express.analysis.stability.critical_result import CriticalSpeed
from express.base.arguments import si_argument, si_arguments
from express.base.diagnostics import AnalysisError, ArgumentError
from express.base.threads import large_problem_threads, limited_blas
from express.base.units import KMH
from express.numeric.statespace import VehicleModel

__all__ = [
    "WINDOW_JUMP",
    "CriticalOptions",
    "CriticalSpeed",
    "EigenResult",
    "Mode",
    "critical_speed",
    "critical_speed_vs_conicity",
    "eigen_analysis",
    "max_real_part",
    "modes_of",
    "natural_frequencies",
    "root_locus",
    "search_options",
    "sweep_as_dict",
    "unstable_windows",
]

#: Relative change of V_cr from one conicity to the next above which both points are
#: checked for an unstable window (:func:`unstable_windows`; a smaller step is drawn as a line either way).
WINDOW_JUMP = 0.2

# ---------------------------------------------------------------------------------------
# Analyses
# ---------------------------------------------------------------------------------------


def _check_speed_dependent(vehicle: VehicleModel) -> None:
    if vehicle.layout is None or not vehicle.wheelsets:
        raise ArgumentError("the model has no rail data (wheelsets): its eigenvalues do not depend on the speed")


def _least_stable_mode(vehicle: VehicleModel, speed: float) -> Mode:
    values, vectors = np.linalg.eig(vehicle.state_matrix(float(speed)))
    return modes_of(vehicle, values, vectors, limit=1, speed=float(speed))[0]


@limited_blas
def eigen_analysis(vehicle: VehicleModel, speed: float | None = None) -> EigenResult:
    """Every mode of the linear vehicle at one speed (any model: without rail data the
    modes do not depend on the speed).

    Parameters
    ----------
    vehicle : VehicleModel
        Numerical vehicle (:func:`express.numeric.statespace.vehicle_model`).
    speed : float, str or pint.Quantity, optional
        Forward speed ``v`` [m/s], > 0 (a number is SI, never km/h; a quantity carries its
        unit: ``"120 km/h"``); the model's own speed by default.  Ignored
        for a model without rail data (:attr:`EigenResult.speed` is then nan).

    Returns
    -------
    EigenResult
        Modes sorted by descending real part, one per conjugate pair, and every
        eigenvalue (:attr:`EigenResult.eigenvalues`), all from one :func:`numpy.linalg.eig`.

    Raises
    ------
    ArgumentError
        For a speed that is not positive (a model with rail data).
    AnalysisError
        When ``A`` has non-finite entries.

    Notes
    -----
    Names (:attr:`Mode.kind`) come from the distribution of each mode's kinetic
    energy over the bodies and directions, hunting from the wheelsets' kinematic
    displacement (:mod:`express.analysis.modes.mode_names`, ``docs/analyses.md``).

    Examples
    --------
    >>> from express.io import load_model
    >>> from express.numeric.statespace import vehicle_model
    >>> car = vehicle_model(load_model("examples/forced-steering.toml"))
    >>> result = eigen_analysis(car, 120 / 3.6)
    >>> print(result.table())                                    # doctest: +ELLIPSIS
    eigenvalues at 33.333 m/s (120.0 km/h)
        Re [1/s]   Im [rad/s]    f [Hz]     zeta  mode
         -0.2957    1023.3335   162.869   0.0003  steering lever pitch, both bogies (L...
    ...
    """
    rail = vehicle.layout is not None and bool(vehicle.wheelsets)  # without rail data A does not depend on the speed
    speed = vehicle.speed if speed is None else si_argument(speed, "speed", "speed")
    if rail and not speed > 0:
        raise ArgumentError(f"speed must be positive, got {speed}")
    state_matrix = vehicle.state_matrix(float(speed) if rail else 1.0)
    if not np.all(np.isfinite(state_matrix)):
        raise AnalysisError("the state matrix A has non-finite entries")
    with large_problem_threads(state_matrix.shape[0]):  # a long train's A: threads pay
        values, vectors = np.linalg.eig(state_matrix)
    every = values[np.lexsort((-values.imag, -values.real))]
    if not rail:
        return EigenResult(float("nan"), modes_of(vehicle, values, vectors), every)
    return EigenResult(float(speed), modes_of(vehicle, values, vectors, speed=float(speed)), every)


@limited_blas
def natural_frequencies(vehicle: VehicleModel) -> np.ndarray:
    """Undamped natural frequencies ``sqrt(eig(M^-1 K)) / (2 pi)`` [Hz], ascending.

    For a model without rail data (``K`` symmetric); with rail data ``K`` holds the
    creep terms and the undamped problem has no physical meaning.

    Raises
    ------
    ArgumentError
        For a model with rail data or with first-order coordinates (series elements:
        no mass, so no undamped oscillation of their own), or a negative eigenvalue
        (an unstable static equilibrium, e.g. too much gravity stiffness).
    """
    if vehicle.layout is not None and vehicle.wheelsets:
        raise ArgumentError("natural frequencies of a rail vehicle: its K holds creep terms; use eigen_analysis")
    if vehicle.form.first_order.size:
        raise ArgumentError("the model has first-order coordinates (series elements): use eigen_analysis")
    import scipy.linalg

    squares = scipy.linalg.eigh(0.5 * (vehicle.stiffness + vehicle.stiffness.T), vehicle.mass, eigvals_only=True)
    tolerance = 1e-9 * max(1.0, float(np.abs(squares).max()) if squares.size else 1.0)
    if np.any(squares < -tolerance):
        raise ArgumentError("K is not positive semi-definite: the static equilibrium is unstable")
    return np.sqrt(np.clip(squares, 0.0, None)) / (2.0 * np.pi)


def _speeds(speeds: Iterable[float] | float) -> np.ndarray:
    array = np.atleast_1d(si_arguments(speeds, "speed", "speeds"))
    if array.ndim != 1:
        raise ArgumentError("speeds must be a 1-D sequence of speeds [m/s]")
    if array.size and not np.all(array > 0):
        raise ArgumentError("every speed must be positive [m/s]")
    return array


@limited_blas
def root_locus(vehicle: VehicleModel, speeds: Iterable[float]) -> np.ndarray:
    """Eigenvalues of ``A(v)`` at every speed.

    ``A(v)`` is assembled from blocks computed once (``-M^-1 K``, ``-M^-1 C0``,
    ``-M^-1 C1``), split once into the diagonal blocks that carry its eigenvalues
    (:attr:`VehicleModel.eigen_blocks`, exact: the conventional car's 40 states are
    34 + 6, the Manchester car's 62 are 42 + 20), and the eigenvalues of all speeds are
    computed by stacked :func:`numpy.linalg.eigvals` calls per block: a 1000-speed
    locus of the 24-DOF car takes about 0.25 s.

    Parameters
    ----------
    vehicle : VehicleModel
    speeds : sequence of float, shape (S,)
        Speeds [m/s], > 0 (numbers SI; quantities carry their unit: ``["60 km/h", 20.0]``
        or a pint array).

    Returns
    -------
    numpy.ndarray, complex, shape (S, 2n)
        Row ``i`` holds every eigenvalue [1/s] at ``speeds[i]`` (both members of each
        conjugate pair), sorted by descending real part, ties by descending imaginary
        part. Branches are not tracked from one speed to the next.

    Examples
    --------
    >>> from express.io import load_model
    >>> from express.numeric.statespace import vehicle_model
    >>> car = vehicle_model(load_model("examples/conventional.toml"))
    >>> locus = root_locus(car, np.linspace(10.0, 150.0, 1000))
    >>> locus.shape
    (1000, 40)
    >>> bool(locus[0, 0].real < 0 < locus[-1, 0].real)      # stable at 10, not at 150 m/s
    True
    """
    _check_speed_dependent(vehicle)
    v = _speeds(speeds)
    values = vehicle.eigen_blocks.eigenvalues(v)
    order = np.lexsort((-values.imag, -values.real), axis=-1)
    return np.take_along_axis(values, order, axis=-1)


@limited_blas
def max_real_part(vehicle: VehicleModel, speeds: Iterable[float]) -> np.ndarray:
    """Largest real part of the eigenvalues [1/s] at every speed, shape (S,)."""
    _check_speed_dependent(vehicle)
    v = _speeds(speeds)
    return vehicle.eigen_blocks.eigenvalues(v).real.max(axis=1)


@limited_blas
def critical_speed(
    vehicle: VehicleModel,
    options: CriticalOptions | None = None,
    *,
    v_min: float | None = None,
    v_max: float | None = None,
    tolerance_kmh: float | None = None,
    threshold: float | None = None,
    points: int | None = None,
) -> CriticalSpeed:
    """Lowest speed at which the largest real part of the eigenvalues becomes positive.

    Algorithm: the largest real part ``sigma(v)`` is computed on ``points`` speeds
    spaced geometrically from ``v_min`` to ``v_max`` (equal ratios, 13.7 % apart with the
    defaults); the first interval where ``sigma`` goes from ``<= threshold`` to
    ``> threshold`` is bisected until it is narrower than ``tolerance_kmh``.

    Why a geometric grid: the speed enters ``A`` only as ``1 / v`` (creep damping), so
    the eigenvalues change fastest at low speed (``dA/d ln v = M^-1 C1 / v``). Equal
    ratios resolve the low speeds, where a steered vehicle with a small conicity goes
    unstable, as finely as the high speeds relative to the speed itself, with 40
    points from 1 to 150 m/s. Equal steps in ``1 / v`` would leave the high speeds
    far too coarse, equal steps in ``v`` the low ones. An instability confined to a
    window narrower than one grid step (unstable, then stable again) can be missed;
    raise ``points`` if that is a concern.

    Parameters
    ----------
    vehicle : VehicleModel
        The vehicle (with rail data: its eigenvalues depend on the speed).
    options : CriticalOptions, optional
        The search's options in SI (:class:`~express.analysis.stability.critical_options.CriticalOptions`,
        the one set of defaults); the keywords below override single ones.
    v_min, v_max : float, str or pint.Quantity, optional
        Speed range scanned [m/s], ``0 < v_min < v_max`` (a number is SI; ``"400 km/h"``).
    tolerance_kmh : float, optional
        Width of the final bracket [km/h]; the speed returned (its midpoint) is within
        half of it of the crossing.
    threshold : float, optional
        A real part counts as positive only above this [1/s], so that modes whose real
        part is zero up to round-off (rigid-body modes, undamped modes) are not taken
        for an instability. Raise it (e.g. to 1e-4) when the model has a repeated zero
        eigenvalue, whose computed real part is of order ``sqrt(eps) |A|``: at
        ``Gamma = 0`` the bundled cars have no lateral restoring stiffness and reach
        4e-6 1/s.
    points : int, optional
        Number of speeds of the coarse scan (>= 2).

    Returns
    -------
    CriticalSpeed
        Always a record: ``found=False`` (``speed`` nan, ``reason`` "stable up to v_max",
        ``mode`` the least stable one at ``v_max``) when the vehicle is stable over the
        whole range. When it is already unstable at ``v_min`` the result has
        ``unstable_at_min=True`` and ``speed = v_min``. (Before issue 35 a stable vehicle
        gave ``None``: test ``result.found`` instead of ``result is None``.)

    Examples
    --------
    >>> from express.io import load_model
    >>> from express.numeric.statespace import vehicle_model
    >>> car = vehicle_model(load_model("examples/conventional.toml"))
    >>> cs = critical_speed(car)
    >>> cs.unstable_at_min, 50.0 < cs.speed < 150.0
    (False, True)
    >>> stable = critical_speed(car, v_max=40.0)
    >>> stable.found, stable.reason
    (False, 'stable up to v_max')
    """
    v_min = None if v_min is None else si_argument(v_min, "speed", "v_min")
    v_max = None if v_max is None else si_argument(v_max, "speed", "v_max")
    options = search_options(options, v_min=v_min, v_max=v_max, tolerance_kmh=tolerance_kmh, threshold=threshold,
                             points=points)
    if not options.tolerance > 0:
        raise ArgumentError(f"tolerance_kmh must be positive, got {options.tolerance_kmh}")
    v_min, v_max, threshold = options.v_min, options.v_max, options.threshold
    _check_speed_dependent(vehicle)
    pieces = vehicle.eigen_blocks
    grid = options.grid
    sigma = pieces.eigenvalues(grid).real.max(axis=1)
    evaluations = grid.size
    unstable = sigma > threshold
    low, high = float(v_min), float(v_max)
    if not unstable.any():
        mode = _least_stable_mode(vehicle, float(v_max))
        return CriticalSpeed(float("nan"), mode, False, (float(v_max), float("nan")), evaluations + 1, False, low, high)
    first = int(np.argmax(unstable))
    if first == 0:
        mode = _least_stable_mode(vehicle, float(v_min))
        return CriticalSpeed(float(v_min), mode, True, (float(v_min), float(v_min)), evaluations + 1, True, low, high)
    lo, hi = float(grid[first - 1]), float(grid[first])
    tolerance = options.tolerance
    while hi - lo > tolerance:
        mid = 0.5 * (lo + hi)
        evaluations += 1
        if pieces.eigenvalues(np.array([mid])).real.max() > threshold:
            hi = mid
        else:
            lo = mid
    speed = 0.5 * (lo + hi)
    mode = _least_stable_mode(vehicle, speed)
    return CriticalSpeed(speed, mode, False, (lo, hi), evaluations + 1, True, low, high)


def search_options(options: CriticalOptions | None = None, **changes: float | None) -> CriticalOptions:
    """``options`` (default :class:`CriticalOptions`) with the keywords that are not None
    changed; ``tolerance_kmh`` [km/h] sets ``tolerance`` [m/s].

    Parameters
    ----------
    options : CriticalOptions, optional
        The starting options.
    **changes : float or None
        ``v_min``, ``v_max`` [m/s], ``tolerance_kmh`` [km/h], ``threshold`` [1/s], ``points``.

    Returns
    -------
    CriticalOptions
    """
    given: dict[str, Any] = {key: value for key, value in changes.items() if value is not None}
    if "tolerance_kmh" in given:
        given["tolerance"] = given.pop("tolerance_kmh") * KMH
    if "points" in given:
        given["points"] = int(given["points"])
    return replace(options or CriticalOptions(), **given)


@limited_blas
def critical_speed_vs_conicity(
    vehicle: VehicleModel,
    conicities: Iterable[float],
    options: CriticalOptions | None = None,
    *,
    parameter: str = "Gamma",
    **keywords,
) -> list[CriticalSpeed]:
    """Critical speed for each value of the tread conicity (paper Fig. 11).

    Parameters
    ----------
    vehicle : VehicleModel
    conicities : sequence of float
        Values of ``parameter`` [-].
    options : CriticalOptions, optional
        The search's options (:func:`critical_speed`).
    parameter : str
        Name of the model parameter varied (``"Gamma"`` in the bundled vehicles).
    **keywords
        Passed to :func:`critical_speed` (``v_min``, ``v_max``, ``tolerance_kmh``,
        ``threshold``, ``points``).

    Returns
    -------
    list of CriticalSpeed
        One per conicity, in order (``found=False`` where stable over the range).

    Raises
    ------
    ArgumentError
        When the model has no parameter ``parameter``.

    Examples
    --------
    >>> from express.io import load_model
    >>> from express.numeric.statespace import vehicle_model
    >>> car = vehicle_model(load_model("examples/conventional.toml"))
    >>> [round(c.speed_kmh) for c in critical_speed_vs_conicity(car, [0.1, 0.2])]
    [421, 361]
    """
    if parameter not in vehicle.facts.parameters:
        known = ", ".join(vehicle.facts.parameters) or "none"
        raise ArgumentError(f"the model has no parameter {parameter!r} (parameters: {known})")
    return [critical_speed(vehicle.with_values({parameter: float(g)}), options, **keywords) for g in conicities]


def sweep_as_dict(parameter: str, values: Iterable[float], sweep: list[CriticalSpeed]) -> dict:
    """A sweep of :func:`critical_speed_vs_conicity` as plain data.

    Parameters
    ----------
    parameter : str
        The parameter swept.
    values : sequence of float
        Its values, in the sweep's order.
    sweep : list of CriticalSpeed
        The results (not ``found``: stable over the range, given as ``nan``).

    Returns
    -------
    dict
        ``parameter``, ``values``, ``critical_speeds`` [m/s] and ``critical_speeds_kmh``
        (arrays), ``unstable_at_min`` and ``modes`` (lists).
    """
    speeds = np.array([c.speed if c.found else np.nan for c in sweep])
    return {
        "parameter": parameter, "values": list(values), "critical_speeds": speeds,
        "critical_speeds_kmh": speeds / KMH,
        "unstable_at_min": [bool(c.unstable_at_min) for c in sweep],
        "modes": [c.mode.describe() if c.found else None for c in sweep],
    }


def unstable_windows(vehicle: VehicleModel, conicities: np.ndarray, speeds_kmh: np.ndarray,
                     unstable_at_min: np.ndarray, *, parameter: str = "Gamma", v_max: float = 200.0,
                     tolerance_kmh: float = 0.1) -> np.ndarray:
    """Where ``V_cr`` jumps, the top of the unstable range that starts at ``V_cr``.

    A car can be unstable only in a window of speeds and stable again above it; as the
    conicity changes the window can close, and ``V_cr`` then jumps to the next crossing.
    Where ``V_cr`` changes by more than :data:`WINDOW_JUMP` between neighbours, both are
    checked; the unstable ranges ``[V_cr, top]`` of two neighbours that do not overlap
    mean a jump (``figure_critical_speed`` breaks its line there).

    Parameters
    ----------
    vehicle : VehicleModel
        The vehicle at its nominal values.
    conicities : numpy.ndarray, shape (G,)
        The values of ``parameter`` of the sweep [-].
    speeds_kmh : numpy.ndarray, shape (G,)
        Their critical speeds [km/h] (``nan``: stable over the range).
    unstable_at_min : numpy.ndarray of bool, shape (G,)
        Already unstable at the lowest speed (not checked).
    parameter : str
        The parameter swept.
    v_max : float
        Top of the speeds checked [m/s].
    tolerance_kmh : float
        Width of the bisection bracket of each top [km/h].

    Returns
    -------
    numpy.ndarray, shape (G,)
        The speed [km/h] from which the car is stable again (to the bisection tolerance;
        ``inf``: unstable up to ``v_max``); nan where not checked.
    """
    tops = np.full(conicities.size, np.nan)
    usable = np.isfinite(speeds_kmh) & ~np.asarray(unstable_at_min, bool)
    for i in range(conicities.size - 1):
        if usable[i] and usable[i + 1]:
            low, high = sorted((speeds_kmh[i], speeds_kmh[i + 1]))
            if high > (1 + WINDOW_JUMP) * low:
                for j in (i, i + 1):
                    if np.isnan(tops[j]):
                        varied = vehicle.with_values({parameter: float(conicities[j])})
                        tops[j] = _stable_again(varied, speeds_kmh[j], v_max / KMH, tolerance_kmh)
    return tops


def _stable_again(vehicle: VehicleModel, from_kmh: float, to_kmh: float, tolerance_kmh: float,
                  points: int = 36) -> float:
    """The lowest speed [km/h] in (from, to] at which ``vehicle`` is stable again, or inf."""
    speeds = np.linspace(from_kmh * KMH, to_kmh * KMH, points + 1)[1:]
    stable = np.flatnonzero(max_real_part(vehicle, speeds) <= 0.0)
    if not stable.size:
        return np.inf
    k = int(stable[0])
    low, high = (speeds[k - 1] if k > 0 else from_kmh * KMH), speeds[k]
    while (high - low) / KMH > tolerance_kmh:
        middle = 0.5 * (low + high)
        if max_real_part(vehicle, [middle])[0] <= 0.0:
            high = middle
        else:
            low = middle
    return float(high / KMH)
