"""The critical speed's result record (:class:`CriticalSpeed`): what
:func:`express.analysis.stability.stability.critical_speed` found, as data."""

from __future__ import annotations

from dataclasses import dataclass

from express.analysis.modes.modes import Mode
from express.base.data import DataRecord, one_row, variable, xarray
from express.base.units import KMH

__all__ = ["CriticalSpeed"]


@dataclass(frozen=True, repr=False)
class CriticalSpeed(DataRecord):
    """Result of :func:`express.analysis.stability.stability.critical_speed`: always a record (as scipy's ``OptimizeResult``),
    with :attr:`found` and :attr:`reason` saying what the search found.

    Attributes
    ----------
    speed : float
        Critical speed ``v_cr`` [m/s]: the midpoint of the final bisection bracket, so
        within ``tolerance_kmh / 2`` of the crossing. Equal to ``v_min`` when
        :attr:`unstable_at_min`; ``nan`` when the vehicle is stable up to ``v_max``
        (not :attr:`found`).
    mode : Mode
        The least stable mode at :attr:`speed` (the one that crosses; at ``v_min`` when
        :attr:`unstable_at_min`; at ``v_max``, still stable, when not :attr:`found`).
    unstable_at_min : bool
        True when the vehicle is already unstable at the lowest speed scanned: then no
        crossing was found and :attr:`speed` is only an upper bound of where it happens.
    bracket : tuple of float
        ``(lo, hi)`` [m/s]: stable at ``lo``, unstable at ``hi`` (``(v_min, v_min)``
        when :attr:`unstable_at_min`, ``(v_max, nan)`` when not :attr:`found`).
    evaluations : int
        Number of eigenvalue problems solved.
    found : bool
        True when the vehicle is unstable somewhere in ``[v_min, v_max]`` (a crossing, or
        :attr:`unstable_at_min`); False when it is stable up to the search limit.
    v_min, v_max : float
        The speeds searched [m/s] (``v_max`` is the search limit).
    """

    speed: float
    mode: Mode
    unstable_at_min: bool
    bracket: tuple[float, float]
    evaluations: int = 0
    found: bool = True
    v_min: float = float("nan")
    v_max: float = float("nan")

    @property
    def stable(self) -> bool:
        """True when the vehicle is stable over the whole range searched (not :attr:`found`)."""
        return not self.found

    @property
    def reason(self) -> str:
        """Why the search ended: ``"crossing"`` (a stable-to-unstable bracket bisected),
        ``"unstable at v_min"`` or ``"stable up to v_max"``."""
        if not self.found:
            return "stable up to v_max"
        return "unstable at v_min" if self.unstable_at_min else "crossing"

    @property
    def speed_kmh(self) -> float:
        """Critical speed [km/h] (nan when not :attr:`found`)."""
        return self.speed / KMH

    def describe(self) -> str:
        """One line: the speed and the mode that goes unstable (or the search limit)."""
        if not self.found:
            return (f"stable up to {self.v_max / KMH:.1f} km/h (no critical speed in the range); "
                    f"least stable there: {self.mode.describe()}")
        if self.unstable_at_min:
            return (f"already unstable at the lowest speed {self.speed:.2f} m/s "
                    f"({self.speed_kmh:.1f} km/h): {self.mode.describe()}")
        return (f"critical speed {self.speed:.2f} m/s ({self.speed_kmh:.1f} km/h), "
                f"{self.mode.frequency_hz:.2f} Hz: {self.mode.describe()}")

    def as_dict(self) -> dict:
        """The result as plain data (SI, and the speed in km/h): ``critical_speed`` [m/s],
        ``critical_speed_kmh``, ``mode`` (its description), ``frequency_hz``, ``unstable_at_min``;
        every value None but ``unstable_at_min`` (False) when not :attr:`found`."""
        if not self.found:
            return {"critical_speed": None, "critical_speed_kmh": None, "mode": None, "frequency_hz": None,
                    "unstable_at_min": False}
        return {"critical_speed": self.speed, "critical_speed_kmh": self.speed_kmh, "mode": self.mode.describe(),
                "frequency_hz": self.mode.frequency_hz, "unstable_at_min": bool(self.unstable_at_min)}

    def to_xarray(self):
        """The result as an :class:`xarray.Dataset` of scalars (``speed`` [m/s], the mode's
        ``frequency`` [Hz], ``damping_ratio`` and ``real_part`` [1/s], the bracket and the
        range searched), ``found``, ``reason`` and the mode's description as attributes."""
        xr = xarray()
        mode = self.mode
        data = {
            "speed": variable(self.speed, (), "m/s", "critical speed"),
            "bracket_low": variable(self.bracket[0], (), "m/s", "highest speed found stable"),
            "bracket_high": variable(self.bracket[1], (), "m/s", "lowest speed found unstable"),
            "v_min": variable(self.v_min, (), "m/s", "lowest speed searched"),
            "v_max": variable(self.v_max, (), "m/s", "search limit"),
            "frequency": variable(mode.frequency_hz, (), "Hz", "frequency of the least stable mode"),
            "real_part": variable(mode.real, (), "1/s", "real part of the least stable mode"),
            "damping_ratio": variable(mode.damping_ratio, (), "1", "damping ratio of the least stable mode"),
        }
        return xr.Dataset(data, attrs={"found": int(self.found), "reason": self.reason,
                                       "unstable_at_min": int(self.unstable_at_min), "mode": mode.describe(),
                                       "evaluations": self.evaluations})

    def to_pandas(self):
        """The result as a one-row :class:`pandas.DataFrame`, units in the column names."""
        return one_row(self.to_xarray())

    def _summary(self) -> list[str]:
        return [self.describe(), f"found={self.found}, reason={self.reason!r}, "
                f"searched {self.v_min:.3g}-{self.v_max:.3g} m/s, {self.evaluations} eigenvalue problems"]
