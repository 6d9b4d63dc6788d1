"""EXPRESS: exact symbolic equations of motion for rail vehicles with linkages.

Re-creates and extends the program of Tanifuji & Suzuki (2001): describe a vehicle
as rigid bodies, connection points, spring/damper elements and pinned joints, and get
its linear equations of motion ``M q'' + C q' + K q = P u + Pd u'`` as exact,
simplified symbolic matrices, plus the rail modules and analyses built on them.

The names a user needs are here, imported on first use (so that ``import express`` and
``express --help`` stay quick)::

    import express

    vehicle = express.load_vehicle("examples/conventional.toml")
    express.critical_speed(vehicle).speed_kmh           # about 421 km/h
    express.eigen(vehicle, 30.0).modes[0].describe()
    run = express.simulate(vehicle, express.paper_curve())

Every name is listed in :data:`__all__`; each is defined in its stage package
(``docs/architecture.md``), which the name's ``__module__`` gives.
"""

from __future__ import annotations

import importlib
from typing import Any

__version__ = "0.1.0"

#: Public name -> "module:attribute" it is read from on first use.
_PUBLIC = {
    # reading and generating
    "load_model": "express.io:load_model",
    "ModelBuilder": "express.io.builder:ModelBuilder",
    "model_to_toml": "express.io:model_to_toml",
    "with_values": "express.model.parameters:with_values",
    "generate": "express.assembly.generator:generate",
    "generate_vehicle": "express.rail.build:generate_vehicle",
    "EquationsOfMotion": "express.assembly.equations:EquationsOfMotion",
    "Matrices": "express.assembly.equations:Matrices",
    # the numerical vehicle
    "load_vehicle": "express.numeric.statespace:load_vehicle",
    "vehicle_model": "express.numeric.statespace:vehicle_model",
    "VehicleModel": "express.numeric.statespace:VehicleModel",
    # analyses
    "eigen": "express.analysis.stability.stability:eigen_analysis",
    "eigen_analysis": "express.analysis.stability.stability:eigen_analysis",
    "root_locus": "express.analysis.stability.stability:root_locus",
    "critical_speed": "express.analysis.stability.stability:critical_speed",
    "critical_speed_vs_conicity": "express.analysis.stability.stability:critical_speed_vs_conicity",
    "CriticalOptions": "express.analysis.stability.critical_options:CriticalOptions",
    "nonlinear_critical_speed": "express.analysis.stability.nonlinear_stability:nonlinear_critical_speed",
    "frequency_response": "express.analysis.frequency.frequency:frequency_response",
    "ground_response": "express.analysis.frequency.frequency:ground_response",
    "simulate": "express.analysis.time.simulate:simulate",
    "steady_curving": "express.analysis.curving.steady:steady_curving",
    "SteadyCurve": "express.analysis.curving.curves:SteadyCurve",
    "statistical_ride": "express.analysis.ride.statistical:statistical_ride",
    "Linearisation": "express.forces.linearisation_choice:Linearisation",
    "linearised": "express.forces.linearisation:linearised",
    "ride_response": "express.analysis.ride.vehicle:ride_response",
    "run_study": "express.analysis.study.run:run_study",
    "study": "express.analysis.study.run:study",
    "steady_curving_sensitivity": "express.analysis.study.curving_sensitivity:steady_curving_sensitivity",
    "time_run_sensitivity": "express.analysis.study.time_run_sensitivity:time_run_sensitivity",
    # tracks and profiles
    "load_track": "express.rail.track:load_track",
    "paper_curve": "express.rail.track:paper_curve",
    "read_profile": "express.rail.profile_formats:read_profile",
    "standard_profile": "express.rail.profiles:standard_profile",
    # exports
    "to_json": "express.export:to_json",
    "to_matlab": "express.export:to_matlab",
    "to_python": "express.export:to_python",
    "to_latex": "express.export:to_latex",
    "to_text": "express.export:to_text",
    # result records: every one has to_xarray(), to_pandas() and a short repr (issue 35 item 2)
    "CriticalSpeed": "express.analysis.stability.critical_result:CriticalSpeed",
    "EigenResult": "express.analysis.modes.modes:EigenResult",
    "FrequencyResponse": "express.analysis.frequency.frequency:FrequencyResponse",
    "NonlinearCriticalSpeed": "express.analysis.stability.nonlinear_stability:NonlinearCriticalSpeed",
    "RideResponse": "express.analysis.ride.vehicle:RideResponse",
    "SimulationResult": "express.analysis.time.simulate:SimulationResult",
    "SteadyCurving": "express.analysis.curving.steady:SteadyCurving",
    "StatisticalRide": "express.analysis.ride.statistical:StatisticalRide",
    "SteadyCurvingSensitivity": "express.analysis.study.curving_sensitivity:SteadyCurvingSensitivity",
    "TimeRunSensitivity": "express.analysis.study.time_run_sensitivity:TimeRunSensitivity",
    # errors
    "ExpressError": "express.base.diagnostics:ExpressError",
    "InputError": "express.base.diagnostics:InputError",
    "ModelError": "express.base.diagnostics:ModelError",
    "ArgumentError": "express.base.diagnostics:ArgumentError",
    "AnalysisError": "express.base.diagnostics:AnalysisError",
}

__all__ = ["__version__", *sorted(_PUBLIC)]


def __getattr__(name: str) -> Any:
    """The public name ``name``, imported from its module on first use (PEP 562)."""
    try:
        module, _, attribute = _PUBLIC[name].partition(":")
    except KeyError:
        raise AttributeError(f"module 'express' has no attribute {name!r}") from None
    value = getattr(importlib.import_module(module), attribute)
    globals()[name] = value  # later look-ups skip this function
    return value


def __dir__() -> list[str]:
    return sorted({*globals(), *_PUBLIC})
