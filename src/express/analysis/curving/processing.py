"""EN 14363's processing of a time run's wheel/rail forces before they are assessed: the
20 Hz low-pass filter, and the percentiles of each quantity per wheel and wheelset
(issue 32, item 7; ``docs/curving.md``, "Processing").

* **Filter.** The forces Y and Q of every wheel are low-pass filtered at
  :data:`CUTOFF` (20 Hz) before the running-safety quantities are formed from them:
  ``Y/Q`` from the filtered Y and Q, ``ΣY`` from the filtered Y, ``ΔQ/Q0`` from the
  filtered Q.  The filter is a Butterworth of order :data:`ORDER` applied forwards and
  backwards (zero phase, so a 2 m sliding mean sits where the forces act; the pair has
  twice the order and -6 dB at the cut-off).  The standard's 20 Hz low-pass for the
  running-safety forces is stated in the public summaries we could read (UIC 518 and
  EN 14363 course material, e.g. the GENSYS notes); its filter type and order are not,
  so the Butterworth of order 4 and the zero phase are our choice.  The run's ends are
  extended by their odd reflection (a force that ends changing fast keeps an end effect
  within about ``1 / cutoff`` of the end).  A run sampled below
  :data:`MINIMUM_RATE` times the cut-off is not filtered, and its assessment says so.
* **Percentiles.** Of every filtered quantity over the run (the samples are equally
  spaced in distance at a constant speed), the 0.15 %, 50 % and 99.85 % values: the
  statistics the standard takes of each test section (the 50 % value is its
  quasi-static value, ``Yqst``, ``Qqst``; the outer two its extremes of a normally
  distributed signal, mean -+ 3 sigma).  A simulation is one section.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from express.analysis.curving.outputs import SIDES, WheelRailOutputs

__all__ = ["CUTOFF", "MINIMUM_RATE", "ORDER", "PERCENTILES", "Filtering", "Percentiles", "filtered",
           "percentiles"]

#: Cut-off of the low-pass filter of the running-safety forces [Hz].
CUTOFF = 20.0
#: Order of the Butterworth filter (applied twice: forwards and backwards).
ORDER = 4
#: A run is filtered only when sampled at least this many times the cut-off.
MINIMUM_RATE = 2.5
#: The percentiles of each quantity [%].
PERCENTILES = (0.15, 50.0, 99.85)


@dataclass(frozen=True)
class Filtering:
    """How a run's forces were filtered.

    Attributes
    ----------
    applied : bool
    cutoff : float
        [Hz].
    rate : float
        The run's sample rate [Hz] (``inf`` for one instant).
    note : str
        One line for the command's summary.
    """

    applied: bool
    cutoff: float
    rate: float
    note: str

    def as_dict(self) -> dict[str, Any]:
        return {"applied": self.applied, "cutoff": self.cutoff, "rate": self.rate, "note": self.note}


def filtered(outputs: WheelRailOutputs, distance: np.ndarray, speed: float,
             cutoff: float = CUTOFF) -> tuple[WheelRailOutputs, Filtering]:
    """``outputs`` with Y and Q of every wheel low-pass filtered (module docstring).

    Parameters
    ----------
    outputs : WheelRailOutputs
        N instants.
    distance : numpy.ndarray, shape (N,)
        Distance run [m], equally spaced.
    speed : float
        [m/s].
    cutoff : float
        [Hz].
    """
    from scipy.signal import butter, sosfiltfilt

    d = np.asarray(distance, dtype=float)
    if d.size < 2:
        return outputs, Filtering(False, cutoff, float("inf"), "one instant: not filtered")
    rate = float(speed / np.mean(np.diff(d)))
    if rate < MINIMUM_RATE * cutoff:
        return outputs, Filtering(False, cutoff, rate, f"sampled at {rate:.4g} Hz, below {MINIMUM_RATE:g} x "
                                                       f"the {cutoff:g} Hz cut-off: forces not filtered")
    sos = butter(ORDER, cutoff, fs=rate, output="sos")
    # the ends extended by their odd reflection over four periods of the cut-off: the
    # filter's own transient dies out inside it
    pad = min(d.size - 1, max(3 * (2 * len(sos) + 1), int(4 * rate / cutoff)))

    def low(values: np.ndarray) -> np.ndarray:
        return sosfiltfilt(sos, values, axis=0, padlen=pad)

    note = f"Y and Q low-pass filtered at {cutoff:g} Hz (Butterworth order {ORDER}, zero phase; docs/curving.md)"
    return (replace(outputs, vertical_load=low(outputs.vertical_load), lateral_force=low(outputs.lateral_force)),
            Filtering(True, cutoff, rate, note))


@dataclass(frozen=True)
class Percentiles:
    """The :data:`PERCENTILES` of each quantity of a run (module docstring).

    Attributes
    ----------
    names : tuple of str
        ``Q1L``, ``Y1L``, ``YQ1L``, ... per wheel, ``SY1`` ... per wheelset.
    units : tuple of str
        Each name's unit (``N`` or empty).
    values : numpy.ndarray, shape (len(names), len(PERCENTILES))
        SI.
    """

    names: tuple[str, ...]
    units: tuple[str, ...]
    values: np.ndarray

    def as_dict(self) -> dict[str, Any]:
        return {"percentiles": list(PERCENTILES),
                "quantities": {name: {"unit": unit, "values": row.tolist()}
                               for name, unit, row in zip(self.names, self.units, self.values, strict=True)}}

    def to_pandas(self) -> Any:
        """A :class:`pandas.DataFrame`: a row per quantity, a column per percentile."""
        import pandas as pd

        frame = pd.DataFrame(self.values, index=pd.Index(self.names, name="quantity"),
                             columns=pd.Index([f"p{p:g}" for p in PERCENTILES], name="percentile"))
        frame.attrs["units"] = dict(zip(self.names, self.units, strict=True))
        return frame


def percentiles(outputs: WheelRailOutputs) -> Percentiles:
    """The :class:`Percentiles` of ``outputs`` (filtered first, :func:`filtered`)."""
    names, units, rows = [], [], []
    for j in range(outputs.wheelsets):
        for prefix, values, unit in (("Q", outputs.vertical_load, "N"), ("Y", outputs.lateral_force, "N"),
                                     ("YQ", outputs.y_over_q, "")):
            for k, side in enumerate(SIDES):
                names.append(f"{prefix}{j + 1}{side}")
                units.append(unit)
                rows.append(np.percentile(values[:, j, k], PERCENTILES))
    for j in range(outputs.wheelsets):
        names.append(f"SY{j + 1}")
        units.append("N")
        rows.append(np.percentile(outputs.track_shift_force[:, j], PERCENTILES))
    return Percentiles(tuple(names), tuple(units), np.array(rows))
