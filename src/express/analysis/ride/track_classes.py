"""The named track classes of the ride analysis (``ERRI-low``/``-high``, ``FRA-1`` ...
``FRA-6``, ``AAR-1`` ... ``AAR-6``): their spectra by component
(:func:`track_class_spectra`; the spectra themselves are :mod:`express.rail.track.spectra`)."""

from __future__ import annotations

import re

from express.base.diagnostics import InputError
from express.base.names import did_you_mean
from express.rail.track.spectra import AAR_CLASSES, COMPONENTS, ERRI_LEVELS, FRA_CLASSES, TrackSpectrum

__all__ = ["TRACK_CLASSES", "track_class_spectra"]

#: Named track classes: every component their source defines (all four).
TRACK_CLASSES = ("ERRI-low", "ERRI-high", *(f"FRA-{k}" for k in range(1, 7)), *(f"AAR-{k}" for k in range(1, 7)))


def _key(name: str) -> str:
    return name.strip().lower().replace("_", "-").replace(" ", "-")


def track_class_spectra(name: str) -> dict[str, TrackSpectrum]:
    """The spectra of a named track class, by component.

    ``ERRI-low`` / ``ERRI-high``: ORE B176 alignment and vertical, DB cross level and
    gauge; ``FRA-1`` ... ``FRA-6`` and ``AAR-1`` ... ``AAR-6`` (the same US class
    spectra under either name, :data:`~express.rail.track.spectra.AAR_CLASSES`):
    alignment, vertical, cross level and gauge (``docs/ride.md``). Case, ``_`` and
    spaces are ignored.

    Raises
    ------
    InputError
        For an unknown name, listing the known ones.
    """
    key = _key(str(name))
    if key in ("erri-low", "erri-high"):
        level = key.split("-")[1]
        return {component: ERRI_LEVELS[component][level] for component in COMPONENTS}
    match = re.fullmatch(r"(fra|aar)-?([1-6])", key)
    if match:
        classes, k = (FRA_CLASSES if match.group(1) == "fra" else AAR_CLASSES), int(match.group(2)) - 1
        return {component: classes[component][k] for component in COMPONENTS}
    raise InputError(f"unknown track class {name!r}{did_you_mean(name, TRACK_CLASSES)} (known: {', '.join(TRACK_CLASSES)})")


# --- inputs ------------------------------------------------------------------------------
