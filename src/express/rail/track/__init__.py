"""The track a vehicle runs on, as data: layout, irregularity, spectra, files.

The package is split by what each module owns:

* :mod:`~express.rail.track.geometry`: segments (:class:`Straight`,
  :class:`Transition`, :class:`Curve`), the :class:`Track` with its curvature, cant,
  their rates and the exact centreline, and the paper's curve (:func:`paper_curve`);
* :mod:`~express.rail.track.tables`: the arrays a track precomputes from its segments;
* :mod:`~express.rail.track.irregularity`: the lateral irregularity ``yR(s)``
  (:class:`NoIrregularity`, :class:`SinusoidIrregularity`,
  :class:`ProfileIrregularity`, :class:`SpectrumIrregularity`);
* :mod:`~express.rail.track.spectra`: published spectra (FRA, ERRI) and their registry
  (:func:`get_spectrum`, :func:`register_spectrum`);
* :mod:`~express.rail.track.component_spectra`: the random components of a track, their
  seeds (:func:`component_seed`) and band-limited spectra (:class:`BandLimitedSpectrum`,
  :func:`track_spectra`, what ``express ride --track FILE.toml`` uses);
* :mod:`~express.rail.track.reader`: track files in TOML and CSV profiles
  (:func:`load_track`, :func:`track_from_dict`, :func:`read_profile_csv`), errors as
  :class:`express.base.diagnostics.ModelError`.

Conventions and formats: ``docs/track.md``. Every public name is re-exported here, so
``from express.rail.track import paper_curve, load_track, Track`` works.
"""

from express.rail.track.component_spectra import BandLimitedSpectrum, component_seed, track_spectra
from express.rail.track.geometry import (
    DIRECTIONS,
    MAX_CANT,
    MAX_TRACK_LENGTH,
    TRACK_COMPONENTS,
    TRANSITION_SHAPES,
    Curve,
    Segment,
    Straight,
    Track,
    Transition,
    paper_curve,
)
from express.rail.track.irregularity import (
    MAX_HARMONICS,
    MAX_LATERAL_IRREGULARITY,
    MAX_SAMPLES,
    Harmonics,
    Irregularity,
    NoIrregularity,
    ProfileIrregularity,
    SinusoidIrregularity,
    SpectrumIrregularity,
)
from express.rail.track.reader import (
    EXCERPT_CHARS,
    MAX_PROFILE_BYTES,
    MAX_ROW_PROBLEMS,
    MAX_TRACK_FILE_BYTES,
    MAX_TRACK_SPEED,
    load_track,
    read_profile_csv,
    track_from_dict,
)
from express.rail.track.spectra import (
    COMPONENTS,
    ERRI_HIGH,
    ERRI_LOW,
    FRA_CLASS_5,
    FRA_CLASS_6,
    SPECTRA,
    SPECTRA_BY_COMPONENT,
    AlignmentSpectrum,
    ERRIAlignmentSpectrum,
    FRAAlignmentSpectrum,
    TrackSpectrum,
    get_spectrum,
    register_spectrum,
)
from express.rail.track.tables import CentrelineTable, SegmentTables

__all__ = [
    "COMPONENTS",
    "DIRECTIONS",
    "ERRI_HIGH",
    "ERRI_LOW",
    "EXCERPT_CHARS",
    "FRA_CLASS_5",
    "FRA_CLASS_6",
    "MAX_CANT",
    "MAX_HARMONICS",
    "MAX_LATERAL_IRREGULARITY",
    "MAX_PROFILE_BYTES",
    "MAX_ROW_PROBLEMS",
    "MAX_SAMPLES",
    "MAX_TRACK_FILE_BYTES",
    "MAX_TRACK_LENGTH",
    "MAX_TRACK_SPEED",
    "SPECTRA",
    "SPECTRA_BY_COMPONENT",
    "TRACK_COMPONENTS",
    "TRANSITION_SHAPES",
    "AlignmentSpectrum",
    "BandLimitedSpectrum",
    "CentrelineTable",
    "Curve",
    "ERRIAlignmentSpectrum",
    "FRAAlignmentSpectrum",
    "Harmonics",
    "Irregularity",
    "NoIrregularity",
    "ProfileIrregularity",
    "Segment",
    "SegmentTables",
    "SinusoidIrregularity",
    "SpectrumIrregularity",
    "Straight",
    "Track",
    "TrackSpectrum",
    "Transition",
    "component_seed",
    "get_spectrum",
    "load_track",
    "paper_curve",
    "read_profile_csv",
    "register_spectrum",
    "track_from_dict",
    "track_spectra",
]
