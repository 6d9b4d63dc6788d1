"""Frequency response to a sinusoidal lateral track irregularity (paper Fig. 10).

The leading wheelset sees the alignment ``yR_1(t) = Y sin(2 pi f t)`` and wheelset n
the same, delayed by the time the vehicle takes to cover the distance between them
(``rail.md``)::

    yR_n(t) = Y sin(2 pi f (t - t_n)),   t_n = (x_lead - x_n) / v

(for the paper's car ``t_2 = 2a/v``, ``t_3 = 2 l_T / v``, ``t_4 = 2 (a + l_T) / v``).
The linear model (straight track, no flange contact, no creep saturation)
``M q'' + C(v) q' + K q = P(v) u + Pd u'`` is solved in the frequency domain.

Phase convention
----------------
Every sinusoid is the imaginary part of a complex amplitude times ``exp(i w t)``,
``w = 2 pi f``: ``yR_n(t) = Im(U_n exp(i w t))`` with ``U_n = Y exp(-i w t_n)``, and
every DOF ``q_i(t) = Im(X_i exp(i w t)) = |X_i| sin(w t + arg X_i)``. So ``|X_i|`` is
the amplitude and ``arg X_i`` the phase lead [rad] of ``q_i`` over the irregularity at
the leading wheelset (the paper's ``q_i = X_i sin 2 pi f t``). ``X`` solves::

    (-w^2 M + i w C(v) + K) X = (P(v) + i w Pd) U

with ``U`` zero except in the irregularity inputs ``W1.yR, ...``.

Output points
-------------
The model's ``[rail.outputs]`` (e.g. ``floor_front``, ``floor_rear``: the car-body
floor above the bogie centres) are points on bodies; their lateral displacement is
``u_y = y + rz lx - rx lz`` (:func:`express.numeric.model_numbers.point_lateral_row`) and their
lateral acceleration amplitude is ``-w^2 u_y``.

Examples
--------
>>> import numpy as np
>>> from express.io import load_model
>>> from express.numeric.statespace import vehicle_model
>>> car = vehicle_model(load_model("examples/forced-steering.toml"))
>>> frf = frequency_response(car, np.linspace(0.2, 20.0, 100))
>>> frf.acceleration_of("floor_front").shape
(100,)
>>> bool(np.abs(frf.amplitude_of("W1.y")).max() < 0.01)   # metres, for Y = 1 mm
True
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field

import numpy as np

from express.base.arguments import si_argument, si_arguments
from express.base.data import DataRecord, variable, xarray
from express.base.diagnostics import ArgumentError
from express.base.names import did_you_mean
from express.base.threads import large_problem_threads, limited_blas
from express.numeric.statespace import VehicleModel

__all__ = [
    "FrequencyResponse", "TransferFunctions", "dynamic_stiffness", "frequency_response", "ground_response",
    "irregularity_delays", "steady_response",
]


@dataclass(frozen=True, repr=False)
class FrequencyResponse(DataRecord):
    """Complex amplitudes of every DOF and output point against frequency.

    Attributes
    ----------
    frequencies : numpy.ndarray, shape (F,)
        [Hz].
    speed : float
        [m/s].
    amplitude : float
        ``Y``, amplitude of the irregularity [m].
    dofs : tuple of str
        DOF names, length n.
    X : numpy.ndarray, complex, shape (F, n)
        Complex displacement amplitudes [m or rad] (module docstring for the phase).
    outputs : dict of str to numpy.ndarray, complex, shape (F,)
        Complex lateral displacement amplitude of each output point [m].
    delays : numpy.ndarray, shape (n_wheelsets,)
        ``t_n`` [s] of each wheelset, in the order of :attr:`wheelsets`.
    wheelsets : tuple of str
        Wheelset body ids.
    irregularity : numpy.ndarray, complex, shape (F, n_wheelsets)
        ``U_n = Y exp(-i w t_n)`` [m].
    """

    frequencies: np.ndarray
    speed: float
    amplitude: float
    dofs: tuple[str, ...]
    X: np.ndarray
    outputs: dict[str, np.ndarray]
    delays: np.ndarray
    wheelsets: tuple[str, ...]
    irregularity: np.ndarray = field(repr=False)

    @property
    def omega(self) -> np.ndarray:
        """Circular frequencies ``2 pi f`` [rad/s], shape (F,)."""
        return 2.0 * np.pi * self.frequencies

    @property
    def names(self) -> tuple[str, ...]:
        """Every name :meth:`amplitude_of` accepts: DOFs, then output points."""
        return self.dofs + tuple(self.outputs)

    def amplitude_of(self, name: str) -> np.ndarray:
        """Complex displacement amplitude of a DOF or an output point, shape (F,).

        ``abs()`` of it is the amplitude [m or rad], ``numpy.angle()`` the phase lead
        over the irregularity at the leading wheelset [rad].

        Raises
        ------
        KeyError
            Naming what exists, for an unknown name.
        """
        if name in self.outputs:
            return self.outputs[name]
        if name in self.dofs:
            return self.X[:, self.dofs.index(name)]
        raise KeyError(f"unknown DOF or output {name!r}{did_you_mean(name, self.names)} (known: {', '.join(self.names)})")

    def velocity_of(self, name: str) -> np.ndarray:
        """Complex velocity amplitude ``i w X`` of a DOF or output, shape (F,)."""
        return 1j * self.omega * self.amplitude_of(name)

    def acceleration_of(self, name: str) -> np.ndarray:
        """Complex acceleration amplitude ``-w^2 X`` [m/s^2 or rad/s^2], shape (F,).

        Meant for the output points (car-body floor acceleration, paper Fig. 10);
        accepts DOFs too.
        """
        return -(self.omega**2) * self.amplitude_of(name)

    def to_xarray(self):
        """The response as an :class:`xarray.Dataset` over ``frequency`` [Hz]: ``X``
        (frequency x dof, complex, each DOF's unit in the ``dof_units`` coordinate),
        ``output`` (frequency x point, complex [m]) and ``irregularity`` (frequency x
        wheelset, complex [m]); ``speed`` [m/s] and ``amplitude`` [m] as attributes."""
        from express.model.modal_body import coordinate_unit

        xr = xarray()
        points = list(self.outputs)
        values = np.stack([self.outputs[p] for p in points], axis=1) if points else np.zeros((self.frequencies.size, 0))
        data = {
            "X": variable(self.X, ("frequency", "dof"), "m or rad (dof_units)", "complex displacement amplitude"),
            "output": variable(values.astype(complex), ("frequency", "point"), "m",
                               "complex lateral displacement amplitude of the output point"),
            "irregularity": variable(self.irregularity, ("frequency", "wheelset"), "m",
                                     "complex irregularity at the wheelset"),
            "delay": variable(np.asarray(self.delays, float), "wheelset", "s", "delay of the wheelset's input"),
        }
        coords = {"frequency": ("frequency", np.asarray(self.frequencies, float), {"units": "Hz", "long_name": "frequency"}),
                  "dof": list(self.dofs), "dof_units": ("dof", [coordinate_unit(d) for d in self.dofs]),
                  "point": points, "wheelset": list(self.wheelsets)}
        return xr.Dataset(data, coords=coords, attrs={"speed": self.speed, "speed_units": "m/s",
                                                      "amplitude": self.amplitude, "amplitude_units": "m"})

    def to_pandas(self):
        """The output points' and DOFs' amplitudes as a :class:`pandas.DataFrame`, one row
        per frequency, columns ``<name> [unit]`` (complex)."""
        import pandas as pd

        from express.model.modal_body import coordinate_unit

        columns = {f"{d} [{coordinate_unit(d)}]": self.X[:, i] for i, d in enumerate(self.dofs)}
        columns.update({f"{p} [m]": v for p, v in self.outputs.items()})
        return pd.DataFrame(columns, index=pd.Index(np.asarray(self.frequencies, float), name="frequency [Hz]"))

    def _summary(self) -> list[str]:
        f = self.frequencies
        return [f"{f.size} frequencies {f[0]:g}-{f[-1]:g} Hz at {self.speed:.3f} m/s, Y = {self.amplitude * 1e3:g} mm"
                if f.size else "no frequencies",
                f"{len(self.dofs)} DOFs, outputs: {', '.join(self.outputs) or 'none'}"[:120]]

    def rows(self, names: Iterable[str] | None = None) -> list[dict[str, float]]:
        """One dict per frequency for printing or CSV: ``f_hz`` and, for each name,
        ``<name>_amp`` (|X|), ``<name>_phase_deg`` and, for outputs, ``<name>_acc``
        (|acceleration| [m/s^2])."""
        names = list(self.outputs) if names is None else list(names)
        rows = []
        for k, f in enumerate(self.frequencies):
            row: dict[str, float] = {"f_hz": float(f)}
            for name in names:
                value = self.amplitude_of(name)[k]
                row[f"{name}_amp"] = float(abs(value))
                row[f"{name}_phase_deg"] = float(np.degrees(np.angle(value)))
                if name in self.outputs:
                    row[f"{name}_acc"] = float(abs(self.acceleration_of(name)[k]))
            rows.append(row)
        return rows


def dynamic_stiffness(vehicle: VehicleModel, omega: np.ndarray, speed: float) -> np.ndarray:
    """``-w^2 M + i w C(v) + K`` at every circular frequency, shape (F, n, n), complex.

    Built in place (real part ``K - w^2 M``, imaginary part ``w C``): one complex array
    and no complex temporaries, which is most of the cost of a solve over a few hundred
    frequencies of a small model.
    """
    w = np.asarray(omega, dtype=float)[:, None, None]
    result = np.empty((w.shape[0], vehicle.n, vehicle.n), dtype=complex)
    np.multiply(-(w**2), vehicle.mass, out=result.real)
    result.real += vehicle.stiffness
    np.multiply(w, vehicle.damping(speed), out=result.imag)
    return result


#: Size [bytes] of a stack of dynamic stiffnesses solved at once.
_CHUNK_BYTES = 1 << 20


def steady_response(
    vehicle: VehicleModel, frequencies: np.ndarray, speed: float, columns: list[int], amplitudes: np.ndarray,
    *, route: str | None = None,
) -> np.ndarray:
    """Complex amplitudes ``X`` of every DOF for input amplitudes ``U`` at every frequency.

    ``(-w^2 M + i w C(v) + K) X = (P(v) + i w Pd) U``, solved by the cheapest of three
    routes (:func:`express.analysis.frequency.banded.choose_route`, which charges the 0.25 s
    import of SciPy's LAPACK to the two routes that need it), all the same solution to
    rounding:

    - ``"stacked"``: a dense solve of the dynamic stiffness per frequency, in stacks
      (NumPy only); every small model at a few hundred frequencies, exact to ~1e-14
      of the largest amplitude;
    - ``"banded"``: a banded LU per frequency when the DOFs couple only near the
      diagonal (trains: :mod:`express.analysis.frequency.banded`), as exact;
    - ``"schur"``: one Schur form of the state matrix, then a back substitution per
      frequency (:func:`express.analysis.ride.spectral.resolvent_solve`),
      ``x = (i w I - A)^-1 (B + i w Bd) U`` and ``X = x[:n]``; for very many
      frequencies of a dense model; 1e-9-1e-8 of the largest amplitude on the steered
      cars, whose lever and yaw-bush modes are stiff (``tests/test_numeric_frequency.py``).

    Parameters
    ----------
    vehicle : VehicleModel
    frequencies : numpy.ndarray, shape (F,)
        [Hz], >= 0.
    speed : float
        [m/s].
    columns : list of int
        Indices of the ``k`` driven inputs.
    amplitudes : numpy.ndarray, complex, shape (F, k, J)
        ``U``: ``J`` sets of input amplitudes per frequency.
    route : {"stacked", "banded", "schur"}, optional
        Force one route (tests, benchmarks); chosen by cost by default.

    Returns
    -------
    numpy.ndarray, complex, shape (F, n, J)

    Raises
    ------
    AnalysisError
        At a frequency where the dynamic stiffness is singular.
    """
    from express.analysis.frequency.banded import band_layout, choose_route, solve_banded_stiffness

    w = 2.0 * np.pi * np.asarray(frequencies, dtype=float)
    damping = vehicle.damping(speed)
    layout = band_layout(vehicle.mass, damping, vehicle.stiffness)
    route = route or choose_route(vehicle.n, vehicle.form.size, w.size, layout)
    if route not in ("stacked", "banded", "schur"):
        raise ArgumentError(f"route must be 'stacked', 'banded' or 'schur', got {route!r}")
    try:
        if route == "schur":
            from express.analysis.ride.spectral import resolvent_solve

            b = vehicle.input_matrix(speed)[:, columns]
            bd = vehicle.input_rate_matrix(speed)[:, columns]
            rhs = b @ amplitudes + (1j * w)[:, None, None] * (bd @ amplitudes)
            with np.errstate(all="ignore"):
                return resolvent_solve(vehicle.state_matrix(speed), frequencies, rhs)[:, : vehicle.n]
        p = vehicle.forcing(speed)[:, columns]
        pd = vehicle.forcing_rate(speed)[:, columns]
        rhs = p @ amplitudes + (1j * w)[:, None, None] * (pd @ amplitudes)
        if route == "banded":
            return solve_banded_stiffness(vehicle.mass, damping, vehicle.stiffness, w, rhs, layout)
        out = np.empty((w.size, vehicle.n, rhs.shape[2]), dtype=complex)
        chunk = max(1, _CHUNK_BYTES // (16 * vehicle.n * vehicle.n))  # stacks that stay in cache
        for start in range(0, w.size, chunk):
            part = slice(start, start + chunk)
            out[part] = np.linalg.solve(dynamic_stiffness(vehicle, w[part], speed), rhs[part])
        return out
    except np.linalg.LinAlgError:
        from express.base.diagnostics import AnalysisError

        raise AnalysisError("the dynamic stiffness -w^2 M + i w C + K is singular at one of the frequencies") from None


def require_stable(vehicle: VehicleModel, speed: float) -> None:
    """Refuse a frequency response of a vehicle that is unstable at ``speed``: the
    response to a sinusoid is a steady state only when every free motion decays; an
    unstable one grows without bound whatever the excitation (issue 17).

    Every eigenvalue of ``A(v)`` is computed, block by diagonal block
    (:meth:`VehicleModel.eigenvalues`: the same set as a dense ``eigvals`` of ``A``,
    smaller problems when ``A`` splits, as the Manchester car's 42 + 20 states); no
    eigenvalue can be missed.  For a long coupled train this dense problem is most of
    the command (``docs/benchmarks.md``); it runs on the BLAS threads of one large
    problem (:func:`express.base.threads.large_problem_threads` of the largest block).

    Raises
    ------
    AnalysisError
        Naming the speed and the least-damped eigenvalue with its mode.
    """
    largest = max(block.size for block in vehicle.eigen_blocks.blocks)
    with large_problem_threads(largest):
        values = vehicle.eigenvalues(speed)
    from express.analysis.modes.modes import stability_threshold

    if values.size == 0 or not values.real.max() > stability_threshold(values):
        return  # rigid-body modes (eigenvalue 0) are rounding away from stable, not unstable
    from express.analysis.stability.stability import eigen_analysis
    from express.base.diagnostics import AnalysisError
    from express.base.units import KMH

    mode = eigen_analysis(vehicle, speed).modes[0]
    raise AnalysisError(
        f"the vehicle is unstable at {speed / KMH:.1f} km/h (least-damped eigenvalue {mode.real:.4g} "
        f"{'+' if mode.imag >= 0 else '-'} {abs(mode.imag):.4g}j 1/s, {mode.describe()}): its response to a "
        "sinusoid grows without bound, there is no steady state to report"
    )


def irregularity_delays(vehicle: VehicleModel, speed: float) -> np.ndarray:
    """``t_n = (x_lead - x_n) / v`` [s] for every wheelset, the leading one (largest x)
    at 0. Shape (n_wheelsets,)."""
    stations = np.array([w.station for w in vehicle.wheelsets], dtype=float)
    return (stations.max() - stations) / speed


@limited_blas
def frequency_response(
    vehicle: VehicleModel,
    frequencies: Iterable[float],
    *,
    amplitude: float = 1e-3,
    speed: float | None = None,
) -> FrequencyResponse:
    """Steady response to a sinusoidal lateral alignment, the same at every wheelset
    delayed by its distance behind the leading one.

    Parameters
    ----------
    vehicle : VehicleModel
        Numerical vehicle with rail data (wheelsets and irregularity inputs).
    frequencies : sequence of float, shape (F,)
        Excitation frequencies ``f`` [Hz], >= 0 (the track wavelength is ``v / f``).
        Numbers are SI; quantities carry their unit (``["1 Hz", "10 rad/s"]``, a pint array).
    amplitude : float, str or pint.Quantity
        ``Y`` [m]; default 1 mm as in the paper. The response is linear in it.
    speed : float, str or pint.Quantity, optional
        [m/s] (a number is SI, never km/h; ``"120 km/h"``); the model's own speed by default.

    Returns
    -------
    FrequencyResponse

    Raises
    ------
    ArgumentError
        For a model without wheelsets or a non-positive speed.
    AnalysisError
        For a frequency at which the dynamic stiffness is singular, or a vehicle that
        is unstable at the speed (:func:`require_stable`).

    Examples
    --------
    >>> from express.io import load_model
    >>> from express.numeric.statespace import vehicle_model
    >>> car = vehicle_model(load_model("examples/conventional.toml"))
    >>> frf = frequency_response(car, [1.0, 2.0], speed=120 / 3.6)
    >>> [round(float(t), 4) for t in frf.delays]  # 0, 2a/v, 2 lT/v, 2 (a + lT)/v
    [0.0, 0.069, 0.432, 0.501]
    >>> abs(frf.amplitude_of("floor_front")).shape
    (2,)
    """
    if vehicle.layout is None or not vehicle.wheelsets:
        raise ArgumentError("the model has no rail data (wheelsets): nothing excites it")
    v = float(vehicle.speed if speed is None else si_argument(speed, "speed", "speed"))
    if not v > 0:
        raise ArgumentError(f"speed must be positive, got {v}")
    f = np.atleast_1d(si_arguments(frequencies, "frequency", "frequencies"))
    if f.ndim != 1 or not np.all(np.isfinite(f)) or np.any(f < 0):
        raise ArgumentError("frequencies must be a 1-D sequence of finite values >= 0 [Hz]")
    amplitude = si_argument(amplitude, "length", "amplitude")
    require_stable(vehicle, v)
    w = 2.0 * np.pi * f
    inputs = list(vehicle.inputs)
    columns = [inputs.index(name) for name in vehicle.layout.irregularity]
    delays = irregularity_delays(vehicle, v)
    irregularity = amplitude * np.exp(-1j * w[:, None] * delays[None, :])  # (F, nw)
    X = steady_response(vehicle, f, v, columns, irregularity[:, :, None])[..., 0]
    outputs: dict[str, np.ndarray] = {}
    for point in vehicle.facts.outputs:
        outputs[point.name] = X @ np.array(point.row(vehicle.dofs))
    return FrequencyResponse(
        frequencies=f,
        speed=v,
        amplitude=float(amplitude),
        dofs=vehicle.dofs,
        X=X,
        outputs=outputs,
        delays=delays,
        wheelsets=tuple(w_.name for w_ in vehicle.wheelsets),
        irregularity=irregularity,
    )


# ---------------------------------------------------------------------------------------
# Any model: transfer functions from the ground inputs
# ---------------------------------------------------------------------------------------


@dataclass(frozen=True, repr=False)
class TransferFunctions(DataRecord):
    """Steady response of every DOF to a unit sinusoid of each input, one at a time.

    ``H[k, i, j]`` is the complex amplitude of DOF ``i`` [m or rad] per unit amplitude of
    input ``j`` [m or rad] at ``frequencies[k]``: ``q_i = Im(H u_j exp(i w t))`` for
    ``u_j = Im(exp(i w t))`` (the phase convention of the module docstring).

    Attributes
    ----------
    frequencies : numpy.ndarray, shape (F,)
        [Hz].
    speed : float
        [m/s] (nan for a model without rail data).
    dofs : tuple of str
        Length n.
    inputs : tuple of str
        Length m: the inputs of the columns.
    H : numpy.ndarray, complex, shape (F, n, m)
    """

    frequencies: np.ndarray
    speed: float
    dofs: tuple[str, ...]
    inputs: tuple[str, ...]
    H: np.ndarray

    def to_xarray(self):
        """``H`` as an :class:`xarray.Dataset` (frequency [Hz] x dof x input, complex;
        the unit of each DOF per unit input in ``dof_units``)."""
        from express.model.modal_body import coordinate_unit

        xr = xarray()
        coords = {"frequency": ("frequency", np.asarray(self.frequencies, float), {"units": "Hz", "long_name": "frequency"}),
                  "dof": list(self.dofs), "dof_units": ("dof", [coordinate_unit(d) for d in self.dofs]),
                  "input": list(self.inputs)}
        return xr.Dataset({"H": variable(self.H, ("frequency", "dof", "input"), "m or rad per unit input (dof_units)",
                                         "transfer function")}, coords=coords,
                          attrs={"speed": self.speed, "speed_units": "m/s"})

    def _summary(self) -> list[str]:
        f = self.frequencies
        return [f"{len(self.dofs)} DOFs x {len(self.inputs)} inputs ({', '.join(self.inputs)})"[:120],
                f"{f.size} frequencies" + (f" {f[0]:g}-{f[-1]:g} Hz" if f.size else "")]

    def of(self, dof: str, input_name: str) -> np.ndarray:
        """``H`` of one DOF and one input, shape (F,) (KeyError naming what exists)."""
        if dof not in self.dofs:
            raise KeyError(f"unknown DOF {dof!r}{did_you_mean(dof, self.dofs)} (DOFs: {', '.join(self.dofs)})")
        if input_name not in self.inputs:
            raise KeyError(f"unknown input {input_name!r}; inputs: {', '.join(self.inputs)}")
        return self.H[:, self.dofs.index(dof), self.inputs.index(input_name)]


def ground_inputs(vehicle: VehicleModel) -> tuple[str, ...]:
    """The model's own inputs (ground motions ``<ground>.<axis>``), without the rail inputs."""
    rail = set(vehicle.layout.inputs) if vehicle.layout is not None else set()
    return tuple(name for name in vehicle.inputs if name not in rail)


@limited_blas
def ground_response(
    vehicle: VehicleModel,
    frequencies: Iterable[float],
    *,
    inputs: Iterable[str] | None = None,
    speed: float | None = None,
) -> TransferFunctions:
    """Transfer functions of every DOF from the ground inputs (any model).

    Solves ``(-w^2 M + i w C(v) + K) H = P(v) + i w Pd`` column by column: works with a
    singular ``M`` (series elements' strokes) as long as the dynamic stiffness is not.

    Parameters
    ----------
    vehicle : VehicleModel
    frequencies : sequence of float, shape (F,)
        [Hz], >= 0 (numbers SI; quantities carry their unit).
    inputs : sequence of str, optional
        Input names; by default every ground input (:func:`ground_inputs`).
    speed : float, str or pint.Quantity, optional
        [m/s] (a number is SI), for a model with rail data (creep damping); the model's own by default.
        Ignored without rail data.

    Raises
    ------
    ArgumentError
        For unknown inputs, a model without any input, bad frequencies or speed.
    AnalysisError
        At a frequency where the dynamic stiffness is singular.

    Examples
    --------
    >>> from express.io import load_model
    >>> from express.numeric.statespace import vehicle_model
    >>> values = {"J1": 2.0, "J2": 0.5, "b": 0.4, "c": 300.0, "kLL": 5.5e6, "kLU": 5e5,
    ...           "lLL": 0.06, "lLU": 0.3, "m": 20.0}
    >>> from express.model.parameters import with_values
    >>> lever = vehicle_model(with_values(load_model("examples/lever.exp"), values))
    >>> tf = ground_response(lever, [0.0, 10.0])
    >>> tf.inputs
    ('G1.x', 'G2.x', 'G3.x')
    >>> tf.H.shape
    (2, 2, 3)
    """
    names = ground_inputs(vehicle) if inputs is None else tuple(inputs)
    if not names:
        raise ArgumentError("the model has no ground inputs (no element attached to a ground): nothing excites it")
    unknown = [name for name in names if name not in vehicle.inputs]
    if unknown:
        raise ArgumentError(f"unknown input{'s' if len(unknown) > 1 else ''} {', '.join(unknown)}; "
                         f"inputs: {', '.join(vehicle.inputs) or 'none'}")
    rail = vehicle.layout is not None and bool(vehicle.wheelsets)
    v = float(vehicle.speed if speed is None else si_argument(speed, "speed", "speed")) if rail else 1.0
    if not v > 0:
        raise ArgumentError(f"speed must be positive, got {v}")
    f = np.atleast_1d(si_arguments(frequencies, "frequency", "frequencies"))
    if f.ndim != 1 or not np.all(np.isfinite(f)) or np.any(f < 0):
        raise ArgumentError("frequencies must be a 1-D sequence of finite values >= 0 [Hz]")
    columns = [vehicle.inputs.index(name) for name in names]
    unit = np.broadcast_to(np.eye(len(columns), dtype=complex), (f.size, len(columns), len(columns)))
    h = steady_response(vehicle, f, v, columns, unit)
    return TransferFunctions(f, v if rail else float("nan"), vehicle.dofs, names, h)
