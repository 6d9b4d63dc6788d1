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

from .comfort import (
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
from .figures import figure_ride_spectra
from .spectral import (
    delay_factors,
    frequency_response,
    harmonic_realisation,
    output_autospectra,
    output_spectra,
    resolvent_solve,
    spatial_to_temporal,
    spectral_rms,
    spectral_variance,
    track_input_spectrum,
    two_point_filter,
    two_point_filter_zeros,
    wheelbase_filter,
    wheelset_delays,
)
from .summaries import (
    PointComfort,
    WheelForces,
    comfort_from_psd,
    comfort_from_time_histories,
    point_comfort,
    simulation_accelerations,
    wheel_forces,
    y_over_q_level,
)
from .vehicle import TRACK_CLASSES, RailInputs, RideResponse, rail_inputs, ride_response, track_class_spectra
from .weighting import (
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
    "frequency_response",
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
