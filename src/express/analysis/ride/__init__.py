"""Ride: comfort weightings (EN 12299, Sperling), comfort indices and spectral response tools.

- :mod:`.weighting`: the frequency weightings Wb, Wc, Wd (Wk) as transfer functions,
  Sperling's B(f), weighting of time histories;
- :mod:`.comfort`: Sperling's Wz and EN 12299 N_MV from spectra and time histories;
- :mod:`.spectral`: output spectra ``H G_u H^H``, RMS, wheelbase delays and filters,
  seeded random realisations.  PSDs are one-sided in Hz throughout (``docs/ride.md``);
- :mod:`.vehicle`: a vehicle's response to random track irregularity (accelerations of
  the output points, wheel forces); :mod:`.summaries`: comfort per point, Y/Q;
- :mod:`.figures`: acceleration PSDs with their weighted curves.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from express.analysis.ride.comfort import (
        EN12299_WINDOW,
        SPERLING_BAND,
        SPERLING_CONSTANT,
        MeanComfort,
        mean_comfort,
        mean_comfort_spectral,
        p95_from_spectrum,
        sperling_index,
        sperling_index_harmonics,
        sperling_index_time,
        window_rms,
    )
    from express.analysis.ride.figures import figure_ride_spectra
    from express.analysis.ride.spectral import (
        delay_factors,
        harmonic_realisation,
        output_autospectra,
        output_spectra,
        resolvent_solve,
        spatial_to_temporal,
        spectral_rms,
        spectral_variance,
        state_space_response,
        track_input_spectrum,
        two_point_filter,
        two_point_filter_zeros,
        wheelbase_filter,
        wheelset_delays,
    )
    from express.analysis.ride.summaries import (
        PointComfort,
        WheelForces,
        comfort_from_psd,
        comfort_from_time_histories,
        point_comfort,
        simulation_accelerations,
        wheel_forces,
        y_over_q_level,
    )
    from express.analysis.ride.vehicle import (
        TRACK_CLASSES,
        RailInputs,
        RideResponse,
        rail_inputs,
        ride_response,
        track_class_spectra,
    )
    from express.analysis.ride.weighting import (
        WB,
        WC,
        WD,
        WEIGHTINGS,
        WK,
        FrequencyWeighting,
        get_weighting,
        sperling_transfer,
        sperling_weighting,
        weigh_time_history,
    )

#: Public name -> the module it is read from on first use (PEP 562): a numerical command
#: that uses one solver of :mod:`.spectral` does not import the ride analyses (and SymPy).
_LAZY = {
    "EN12299_WINDOW": "express.analysis.ride.comfort",
    "SPERLING_BAND": "express.analysis.ride.comfort",
    "SPERLING_CONSTANT": "express.analysis.ride.comfort",
    "MeanComfort": "express.analysis.ride.comfort",
    "mean_comfort": "express.analysis.ride.comfort",
    "mean_comfort_spectral": "express.analysis.ride.comfort",
    "p95_from_spectrum": "express.analysis.ride.comfort",
    "sperling_index": "express.analysis.ride.comfort",
    "sperling_index_harmonics": "express.analysis.ride.comfort",
    "sperling_index_time": "express.analysis.ride.comfort",
    "window_rms": "express.analysis.ride.comfort",
    "figure_ride_spectra": "express.analysis.ride.figures",
    "delay_factors": "express.analysis.ride.spectral",
    "harmonic_realisation": "express.analysis.ride.spectral",
    "output_autospectra": "express.analysis.ride.spectral",
    "output_spectra": "express.analysis.ride.spectral",
    "resolvent_solve": "express.analysis.ride.spectral",
    "spatial_to_temporal": "express.analysis.ride.spectral",
    "spectral_rms": "express.analysis.ride.spectral",
    "spectral_variance": "express.analysis.ride.spectral",
    "state_space_response": "express.analysis.ride.spectral",
    "track_input_spectrum": "express.analysis.ride.spectral",
    "two_point_filter": "express.analysis.ride.spectral",
    "two_point_filter_zeros": "express.analysis.ride.spectral",
    "wheelbase_filter": "express.analysis.ride.spectral",
    "wheelset_delays": "express.analysis.ride.spectral",
    "PointComfort": "express.analysis.ride.summaries",
    "WheelForces": "express.analysis.ride.summaries",
    "comfort_from_psd": "express.analysis.ride.summaries",
    "comfort_from_time_histories": "express.analysis.ride.summaries",
    "point_comfort": "express.analysis.ride.summaries",
    "simulation_accelerations": "express.analysis.ride.summaries",
    "wheel_forces": "express.analysis.ride.summaries",
    "y_over_q_level": "express.analysis.ride.summaries",
    "TRACK_CLASSES": "express.analysis.ride.vehicle",
    "RailInputs": "express.analysis.ride.vehicle",
    "RideResponse": "express.analysis.ride.vehicle",
    "rail_inputs": "express.analysis.ride.vehicle",
    "ride_response": "express.analysis.ride.vehicle",
    "track_class_spectra": "express.analysis.ride.vehicle",
    "WB": "express.analysis.ride.weighting",
    "WC": "express.analysis.ride.weighting",
    "WD": "express.analysis.ride.weighting",
    "WEIGHTINGS": "express.analysis.ride.weighting",
    "WK": "express.analysis.ride.weighting",
    "FrequencyWeighting": "express.analysis.ride.weighting",
    "get_weighting": "express.analysis.ride.weighting",
    "sperling_transfer": "express.analysis.ride.weighting",
    "sperling_weighting": "express.analysis.ride.weighting",
    "weigh_time_history": "express.analysis.ride.weighting",
}

__all__ = [
    "EN12299_WINDOW",
    "SPERLING_BAND",
    "SPERLING_CONSTANT",
    "TRACK_CLASSES",
    "WB",
    "WC",
    "WD",
    "WEIGHTINGS",
    "WK",
    "FrequencyWeighting",
    "MeanComfort",
    "PointComfort",
    "RailInputs",
    "RideResponse",
    "WheelForces",
    "comfort_from_psd",
    "comfort_from_time_histories",
    "delay_factors",
    "figure_ride_spectra",
    "get_weighting",
    "harmonic_realisation",
    "mean_comfort",
    "mean_comfort_spectral",
    "output_autospectra",
    "output_spectra",
    "p95_from_spectrum",
    "point_comfort",
    "rail_inputs",
    "resolvent_solve",
    "ride_response",
    "simulation_accelerations",
    "spatial_to_temporal",
    "spectral_rms",
    "spectral_variance",
    "sperling_index",
    "sperling_index_harmonics",
    "sperling_index_time",
    "sperling_transfer",
    "sperling_weighting",
    "state_space_response",
    "track_class_spectra",
    "track_input_spectrum",
    "two_point_filter",
    "two_point_filter_zeros",
    "weigh_time_history",
    "wheel_forces",
    "wheelbase_filter",
    "wheelset_delays",
    "window_rms",
    "y_over_q_level",
]


def __getattr__(name: str) -> Any:
    """The public name ``name``, imported from its module on first use."""
    if name not in _LAZY:
        raise AttributeError(f"module 'express.analysis.ride' has no attribute {name!r}")
    value = getattr(importlib.import_module(_LAZY[name]), name)
    globals()[name] = value
    return value
