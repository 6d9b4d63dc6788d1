"""A wheel-wear prediction over mileage (issue 37, items 3 and 4; ``docs/wear.md``, "Wear
prediction"): wear steps, each the route's cases as steady states on the current profile
(in parallel), their depths weighted by the route's shares, smoothed, scaled to the step's
distance and removed from the profile; the step's distance bounded so the profile changes
by at most ``bound`` anywhere.  After every step the outputs and a checkpoint are written
whole (:mod:`express.io.output`), so that the same call resumes where a run stopped and
gives the same bytes as one uninterrupted run.
"""

from __future__ import annotations

import hashlib
import json
import math
import os
import tempfile
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

import numpy as np

from express.analysis.wear.cases import ProfileGrid, case_depth, initial_grid, profile_text, with_wheel_profile
from express.analysis.wear.route import Route
from express.analysis.wear.stepping import METHODS, euler_step, heun_step
from express.base.data import DataRecord, variable, xarray
from express.base.diagnostics import ArgumentError, UsageError
from express.io.output import output_transaction, write_csv, write_text
from express.numeric.statespace import VehicleModel
from express.rail.options import DEFAULT_CREEP_LAW
from express.rail.wear_profile import smooth_depth
from express.rail.wheel_dimensions import flange_dimensions

__all__ = ["CHECKPOINT", "FORMAT", "UNITS", "WearPrediction", "WearSettings", "predict_wear", "prediction_identity",
           "profile_path"]

#: The checkpoint's name in the output directory, and its format's name.
CHECKPOINT, FORMAT = "checkpoint.json", "express-wear 2"

#: The columns of ``wear.csv`` and their units.
UNITS = {"step": "", "distance": "m", "step_distance": "m", "largest_change": "m", "step_error": "m",
         "evaluations": "", "max_depth": "m",
         "worn_volume": "m^3", "profile_volume": "m^3", "conicity": "", "critical_speed": "m/s",
         "flange_thickness": "m", "flange_height": "m", "flange_slope": "m"}


@dataclass(frozen=True)
class WearSettings:
    """How a prediction steps (``docs/wear.md``, "The steps"), SI.

    Attributes
    ----------
    bound : float
        Largest change of the profile in one step [m] (default 0.1 mm).
    smoothing : float
        Standard deviation of the Gaussian the step's depth is smoothed with [m] (1 mm).
    spacing : float
        Lateral spacing of the profile's nodes and wear cells [m] (0.1 mm).
    creep_law : str
        Creep law of the steady states and time runs (``"table"``, :data:`~express.rail.options.DEFAULT_CREEP_LAW`).
    method : {"euler", "heun"}
        ``"euler"`` (default): the rate at the start only (first order, the length from
        ``bound``); ``"heun"``: the depth rate at the step's start and on the profile the
        first predicts, averaged (second order), the step's length chosen so that their
        difference, the local error estimate, stays within ``tolerance``
        (:mod:`express.analysis.wear.stepping`).
    tolerance : float
        Largest local error estimate of a Heun step [m] (default 0.01 mm).
    """

    bound: float = 0.1e-3
    smoothing: float = 1e-3
    spacing: float = 0.1e-3
    creep_law: str = DEFAULT_CREEP_LAW
    method: str = "euler"
    tolerance: float = 0.01e-3

    def __post_init__(self) -> None:
        if not (self.bound > 0 and self.smoothing >= 0 and 1e-6 <= self.spacing <= 1e-3):
            raise ArgumentError("the step bound must be > 0, the smoothing >= 0, the spacing 1 um .. 1 mm")
        if self.method not in METHODS or not self.tolerance > 0:
            raise ArgumentError(f"the method is one of {', '.join(METHODS)} and the tolerance > 0, got "
                                f"{self.method!r} and {self.tolerance!r} m")


#: The long names of the columns of :data:`UNITS` (CF ``long_name``).
LONG_NAMES = {"distance": "distance run", "step_distance": "distance of the step",
              "largest_change": "largest change of the profile in the step",
              "step_error": "local error estimate of the step (Heun against Euler)",
              "evaluations": "evaluations of the route's depth rate in the step", "max_depth": "largest worn depth",
              "worn_volume": "worn volume", "profile_volume": "volume of the profile", "conicity": "equivalent conicity",
              "critical_speed": "linear critical speed", "flange_thickness": "flange thickness",
              "flange_height": "flange height", "flange_slope": "flange slope (qR)"}


@dataclass(frozen=True, repr=False)
class WearPrediction(DataRecord):
    """What :func:`predict_wear` left in ``directory``: a row per step (step 0 the new
    profile; columns :data:`UNITS`, SI), whether it reached the distance, and how many
    steps were run now (the rest came from the checkpoint).

    As data (:meth:`to_xarray`): every column of :data:`UNITS` over ``step``;
    ``to_pandas()`` one row per step (``"distance [m]"``, ...).
    """

    rows: list[dict[str, float]]
    directory: Path
    finished: bool
    run_now: int

    def to_xarray(self) -> Any:
        """The rows over ``step`` (:class:`xarray.Dataset`, CF-style ``units``/``long_name``;
        a missing value, e.g. no critical speed, is nan)."""
        steps = [int(row["step"]) for row in self.rows]
        data = {name: variable(np.array([np.nan if row.get(name) is None else float(row[name]) for row in self.rows]),
                               "step", unit or "1", LONG_NAMES.get(name, name))
                for name, unit in UNITS.items() if name != "step"}
        return xarray().Dataset(data, coords={"step": steps}, attrs={"directory": str(self.directory),
                                                                     "finished": int(self.finished),
                                                                     "run_now": self.run_now})

    def _summary(self) -> list[str]:
        last = self.rows[-1] if self.rows else {}
        return [f"{len(self.rows)} steps to {float(last.get('distance', 0.0)) / 1e3:.1f} km "
                f"({'finished' if self.finished else 'not finished'}; {self.run_now} run now) in {self.directory}"]


def prediction_identity(model_text: str, overrides: dict[str, str], route: Route, settings: WearSettings) -> dict:
    """What a checkpoint must match to be resumed: the model file's and the route's
    SHA-256, the overrides and the settings (not the distance: a longer one continues)."""
    return {"model": hashlib.sha256(model_text.encode("utf-8")).hexdigest(), "overrides": dict(sorted(overrides.items())),
            "route": route.digest, "settings": asdict(settings)}


# ---------------------------------------------------------------- the workers

#: What a worker holds: the vehicle of the model and, for the current profile, the worn
#: vehicle and its steady-state solvers by speed (forked workers inherit the vehicle).
_STATE: dict[str, Any] = {}


def _worn_vehicle(path: str) -> tuple[VehicleModel, dict]:
    held = _STATE.get("worn")
    if held is None or held[0] != path:
        held = (path, with_wheel_profile(_STATE["vehicle"], path), {})
        _STATE["worn"] = held
    return held[1], held[2]


def _case(task: tuple) -> tuple[np.ndarray, dict[str, float]]:
    """The depth per metre of one case (:func:`express.analysis.wear.cases.case_depth`)."""
    from express.analysis.curving.settled import settled_curving
    from express.analysis.curving.steady import NoSteadyStateError, SteadyCurve, SteadyCurvingSolver
    from express.analysis.wear.random_track import random_track_run

    path, grid, case, speed, creep_law = task
    vehicle, solvers = _worn_vehicle(path)
    if case.track is not None:  # the random track's time run (docs/wear.md, "Random track")
        return case_depth(vehicle, grid, [random_track_run(vehicle, case, speed, creep_law=creep_law)])
    if case.straight:  # the centred wheelset's steady state wears nothing (docs/wear.md)
        return case_depth(vehicle, grid, [])
    solver = solvers.get(speed)
    if solver is None:
        solver = solvers[speed] = SteadyCurvingSolver(vehicle, speed, creep_law=creep_law)
    curve = SteadyCurve(case.radius, case.cant, "right")
    try:
        state = solver.solve(curve)
    except NoSteadyStateError as error:  # the worn profile may have none: the vehicle run into the curve instead
        return case_depth(vehicle, grid, [settled_curving(vehicle, curve, speed, f"no equilibrium found ({error})",
                                                          creep_law=creep_law)])
    return case_depth(vehicle, grid, [state])


class _Cases:
    """The cases of the steps on ``workers`` processes (forked: they inherit the vehicle),
    or in this process for one."""

    def __init__(self, vehicle: VehicleModel, workers: int):
        _STATE.clear()
        _STATE["vehicle"] = vehicle
        self.pool = None
        if workers > 1:
            import multiprocessing
            from concurrent.futures import ProcessPoolExecutor

            self.pool = ProcessPoolExecutor(workers, mp_context=multiprocessing.get_context("fork"))

    def run(self, tasks: list[tuple]) -> list[tuple[np.ndarray, dict[str, float]]]:
        if self.pool is None:
            return [_case(task) for task in tasks]
        return list(self.pool.map(_case, tasks))

    def close(self) -> None:
        if self.pool is not None:
            self.pool.shutdown(cancel_futures=True)


# ---------------------------------------------------------------- the steps


@dataclass(frozen=True)
class _Rate:
    """The route's depth rate on any profile of step ``step`` (trial profiles written in
    ``scratch``, each under its own name: the workers keep a vehicle per file)."""

    cases: _Cases
    route: Route
    speeds: Sequence[float | None]
    settings: WearSettings
    scratch: Path
    step: int

    def __call__(self, grid: ProfileGrid, trial: int) -> np.ndarray:
        path = self.scratch / f"trial-{self.step:03d}-{trial}.csv"
        write_text(path, profile_text(grid, f"trial profile {trial} of step {self.step + 1}"))
        return _step_depth(self.cases, self.route, self.speeds, path, grid, self.settings)


def profile_path(directory: Path, step: int) -> Path:
    """The profile file of step ``step`` in the output ``directory``."""
    return directory / "profiles" / f"wheel-{step:03d}.csv"


def _measure(vehicle: VehicleModel, grid: ProfileGrid, first: ProfileGrid) -> dict[str, float]:
    """Conicity, linear critical speed and flange dimensions of the worn vehicle."""
    from express.analysis.stability.stability import critical_speed
    from express.rail.profile_contact import wheelset_contacts

    setup = wheelset_contacts(vehicle.model, vehicle.values, vehicle.wheelsets)[0].tables.setup  # type: ignore[union-attr]
    found = critical_speed(vehicle)
    speed = found.speed if found.found and not found.unstable_at_min else math.nan  # stable to the limit: nan
    dims = flange_dimensions(grid.y, grid.z, setup.tapeline_offset)
    worn = grid.z - first.z
    return {"max_depth": float(worn.max()), "profile_volume": float(worn.sum() * grid.spacing * _circumference(vehicle)),
            "conicity": float(vehicle.wheelsets[0].conicity), "critical_speed": speed,
            "flange_thickness": dims.thickness, "flange_height": dims.height, "flange_slope": dims.slope}


def _circumference(vehicle: VehicleModel) -> float:
    return 2.0 * math.pi * float(vehicle.wheelsets[0].r0)


def _step_depth(cases: _Cases, route: Route, speeds: Sequence[float | None], path: Path, grid: ProfileGrid,
                settings: WearSettings) -> np.ndarray:
    """The route's smoothed depth per metre run on ``grid`` [m/m]."""
    tasks = [(str(path), grid, case, speed, settings.creep_law)
             for case, speed in zip(route.cases, speeds, strict=True)]
    rate = np.zeros(grid.z.size)
    for case, (depth, _) in zip(route.cases, cases.run(tasks), strict=True):
        rate += case.share * depth
    return smooth_depth(rate, grid.spacing, settings.smoothing)


def _write_step(directory: Path, rows: list[dict], grid: ProfileGrid, first: ProfileGrid, identity: dict,
                figures: bool, proposal: float | None = None) -> None:
    """wear.csv, the figures and the checkpoint, together (the step's profile is written first)."""
    with output_transaction():
        write_csv(directory / "wear.csv", {name: [row[name] for row in rows] for name in UNITS}, UNITS,
                  markers=["critical_speed", "step_error"])
        if figures:
            from express.analysis.wear.figures import save_wear_figures

            save_wear_figures(directory, rows, grid.y, [_read_grid(directory, row["step"]) for row in rows])
        state = {"format": FORMAT, "identity": identity, "rows": rows, "start": grid.start, "spacing": grid.spacing,
                 "z": grid.z.tolist(), "z0": first.z.tolist(), "proposal": proposal}
        write_text(directory / CHECKPOINT, json.dumps(state, indent=1, allow_nan=True) + "\n")


def _read_grid(directory: Path, step: int) -> np.ndarray:
    """The heights of a step's profile file [m] (for the figures)."""
    return np.loadtxt(profile_path(directory, int(step)), delimiter=",", skiprows=2)[:, 1] * 1e-3


def _resume(directory: Path, identity: dict) -> tuple[list[dict], ProfileGrid, ProfileGrid, float | None] | None:
    path = directory / CHECKPOINT
    if not path.exists():
        return None
    try:
        state = json.loads(path.read_text(encoding="utf-8"))
        ok = state.get("format") == FORMAT
    except (OSError, ValueError, AttributeError):
        ok = False
    if not ok:
        raise UsageError(f"{path}: not a checkpoint of a wear prediction (or damaged); give another -o DIR")
    if state["identity"] != json.loads(json.dumps(identity)):
        raise UsageError(f"{directory}: holds a wear prediction of another model, route or settings; give another -o "
                         f"DIR (or the same model, route and options to resume it)")
    grid = ProfileGrid(float(state["start"]), float(state["spacing"]), np.array(state["z"], dtype=float))
    first = ProfileGrid(grid.start, grid.spacing, np.array(state["z0"], dtype=float))
    return state["rows"], grid, first, state.get("proposal")


def predict_wear(vehicle: VehicleModel, route: Route, speeds: Sequence[float | None], distance: float,
                 directory: str | os.PathLike, *, identity: dict, settings: WearSettings | None = None,
                 workers: int = 1, stop_after: int | None = None, figures: bool = True,
                 progress: Callable[[dict], None] | None = None) -> WearPrediction:
    """Wear the vehicle's wheel profile over ``distance`` [m] of ``route``.

    Parameters
    ----------
    vehicle : VehicleModel
        With the contact from profiles (one wheel profile for every wheelset).
    route : Route
    speeds : sequence of float or None
        Each case's speed [m/s] (:func:`express.analysis.wear.route.route_problems`).
    distance : float
        Distance run [m], > 0.
    directory : path
        Output directory: ``profiles/wheel-NNN.csv``, ``wear.csv``, ``wear.png``,
        ``profiles.png`` and the checkpoint; an existing checkpoint of the same
        ``identity`` (:func:`prediction_identity`) is resumed.
    identity : dict
        What the checkpoint must match (:func:`prediction_identity`).
    settings : WearSettings, optional
    workers : int
        Processes the cases of a step run on (1: this process).
    stop_after : int, optional
        Stop after this many steps of this call (the checkpoint resumes it).
    figures : bool
        Write the PNG figures after every step.
    progress : callable, optional
        Called with each new row.

    Returns
    -------
    WearPrediction
    """
    settings = settings or WearSettings()
    if not (math.isfinite(distance) and distance > 0):
        raise ArgumentError(f"the distance must be positive, got {distance!r} m")
    directory = Path(directory)
    if vehicle.origin.cached:
        vehicle = vehicle.origin.twin()
    resumed = _resume(directory, identity)
    if resumed is None:
        grid = first = initial_grid(vehicle, settings.spacing)
        write_text(profile_path(directory, 0), profile_text(grid, f"{vehicle.name}: new wheel profile, step 0, 0 km"))
        row = {"step": 0, "distance": 0.0, "step_distance": 0.0, "largest_change": 0.0, "step_error": 0.0,
               "evaluations": 0, "worn_volume": 0.0,
               **_measure(with_wheel_profile(vehicle, profile_path(directory, 0)), grid, first)}
        rows = [{name: row[name] for name in UNITS}]
        _write_step(directory, rows, grid, first, identity, figures)
        if progress:
            progress(rows[0])
        proposal = None
    else:
        rows, grid, first, proposal = resumed
    if rows[-1]["distance"] > distance:
        raise UsageError(f"{directory}: the prediction there has run {rows[-1]['distance'] / 1e3:g} km already, more "
                         f"than --distance {distance / 1e3:g} km; give another -o DIR")
    cases = _Cases(vehicle, workers)
    run_now = 0
    try:
        with tempfile.TemporaryDirectory(prefix="express-wear-") as scratch:
            while rows[-1]["distance"] < distance and (stop_after is None or run_now < stop_after):
                step = int(rows[-1]["step"])
                rate = _step_depth(cases, route, speeds, profile_path(directory, step), grid, settings)
                remaining = distance - rows[-1]["distance"]
                if settings.method == "heun":
                    rate_on = _Rate(cases, route, speeds, settings, Path(scratch), step)
                    advance = heun_step(rate_on, grid, rate, remaining, proposal, settings.bound, settings.tolerance)
                else:
                    advance = euler_step(rate, remaining, settings.bound)
                proposal = advance.proposal
                grid = grid.worn(advance.change)
                path = profile_path(directory, step + 1)
                reached = rows[-1]["distance"] + advance.length if advance.length < remaining else distance
                write_text(path, profile_text(grid, f"{vehicle.name}: worn wheel profile, step {step + 1}, "
                                                    f"{reached / 1e3:.9g} km"))
                volume = float(advance.change.sum() * grid.spacing * _circumference(vehicle))
                row = {"step": step + 1, "distance": reached, "step_distance": advance.length,
                       "largest_change": float(advance.change.max()), "step_error": advance.error,
                       "evaluations": advance.evaluations, "worn_volume": rows[-1]["worn_volume"] + volume,
                       **_measure(with_wheel_profile(vehicle, path), grid, first)}
                rows.append({name: row[name] for name in UNITS})
                _write_step(directory, rows, grid, first, identity, figures, proposal)
                run_now += 1
                if progress:
                    progress(rows[-1])
    finally:
        cases.close()
    return WearPrediction(rows, directory, rows[-1]["distance"] >= distance, run_now)
