"""The attractors the ramp-down follows: each limit cycle it finds, with the speeds it
lives at, its amplitude and whether a flange touches its rail on it (issue 32, item 4).

The ramp (:mod:`express.analysis.stability.nonlinear_stability`) starts on a large cycle
and lowers the speed, each run starting from the last state; where a cycle dies the
motion may settle on another one (the S1002 car: a flange-contact cycle, then a tread
cycle of a few tenths of a millimetre) and the ramp follows that one on.  A new
attractor begins at a ramp point whose amplitude differs by more than a factor
:data:`JUMP` from the previous live point's (a fold: along one branch the amplitude
changes by a few per cent a speed step: on the bundled S1002 car by 20 % at most along
either of its two branches, and by a factor 1.88 at the fold between them, 301 to
296 km/h).

On each attractor the flange contact is stated per ramp speed (a flange touched its rail
in the run's last third: :func:`express.analysis.stability.limit_cycles.flange_touched`,
the contact angle above 30 degrees): :attr:`Attractor.flange_lowest` is the lowest speed
at which the cycle still runs in flange contact.  That is usually what an engineer signs
off; a cycle whose amplitude stays below the search's ``threshold`` is not counted at all
(``express critical-speed --nonlinear --threshold``).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Protocol

from express.base.units import KMH

__all__ = ["JUMP", "Attractor", "attractors"]

#: The amplitude ratio between neighbouring live ramp points beyond which they lie on
#: two attractors (either way).
JUMP = 1.5


class _Point(Protocol):
    @property
    def speed(self) -> float: ...
    @property
    def amplitude(self) -> float: ...
    @property
    def alive(self) -> bool: ...
    @property
    def flange_force(self) -> float: ...
    @property
    def flange_contact(self) -> bool: ...
    @property
    def instability(self) -> float: ...


@dataclass(frozen=True)
class Attractor:
    """One limit cycle the ramp followed down in speed.

    Attributes
    ----------
    highest, lowest : float
        The highest and the lowest ramp speed it lived at [m/s].
    below : float
        The next ramp speed, where it was gone (it died, or the motion had moved to
        another attractor) [m/s]; ``nan`` when it lived down to the ramp's end.
    amplitudes : tuple of float
        The watched wheelset's amplitude at each of its ramp speeds, highest speed first [m].
    flange_lowest : float
        The lowest of its ramp speeds at which a flange touched its rail [m/s]; ``nan``
        when none did.
    flange_force : float
        The largest lateral force of a wheel of the watched wheelset on it [N].
    instability : float
        The largest of its runs' EN 14363 instability ratios, ``ΣY`` rms over 100 m
        against ``(ΣY)lim / 2`` (``> 1`` fails; ``nan`` when no run had one).
    """

    highest: float
    lowest: float
    below: float
    amplitudes: tuple[float, ...]
    flange_lowest: float
    flange_force: float
    instability: float = math.nan

    @property
    def flange_contact(self) -> bool:
        """A flange touched its rail on the cycle at some ramp speed."""
        return math.isfinite(self.flange_lowest)

    def describe(self) -> str:
        """One line: its speeds, amplitude and flange contact."""
        gone = f", gone at {self.below / KMH:.1f}" if math.isfinite(self.below) else ", alive at the ramp's end"
        flange = (f"flange contact down to {self.flange_lowest / KMH:.1f} km/h" if self.flange_contact
                  else "no flange contact")
        criterion = (f", ΣY rms up to {self.instability:.2f} of (ΣY)lim/2 ({'FAIL' if self.instability > 1 else 'pass'})"
                     if math.isfinite(self.instability) else "")
        return (f"limit cycle from {self.highest / KMH:.1f} down to {self.lowest / KMH:.1f} km/h{gone}: "
                f"amplitude {self.amplitudes[0] * 1e3:.2f} to {self.amplitudes[-1] * 1e3:.2f} mm, {flange}, "
                f"largest lateral force {self.flange_force / 1e3:.1f} kN{criterion}")

    def as_dict(self) -> dict:
        """Plain data (SI; speeds also in km/h; nan as None is the caller's)."""
        return {"highest": self.highest, "lowest": self.lowest, "below": self.below,
                "highest_kmh": self.highest / KMH, "lowest_kmh": self.lowest / KMH,
                "amplitudes": list(self.amplitudes), "flange_contact": self.flange_contact,
                "flange_lowest": self.flange_lowest, "flange_lowest_kmh": self.flange_lowest / KMH,
                "flange_force": self.flange_force, "instability": self.instability}


def attractors(points: Sequence[_Point]) -> tuple[Attractor, ...]:
    """The attractors of the ramp's ``points`` (in the order run, speeds falling; module
    docstring): the live points split where the amplitude jumps by more than
    :data:`JUMP`; each attractor's :attr:`~Attractor.below` is the next point's speed."""
    groups: list[list[_Point]] = []
    ends: list[float] = []
    for point in points:
        open_group = bool(groups) and len(ends) < len(groups)
        if not point.alive:
            if open_group:
                ends.append(point.speed)
            continue
        if open_group and 1.0 / JUMP <= point.amplitude / groups[-1][-1].amplitude <= JUMP:
            groups[-1].append(point)
            continue
        if open_group:
            ends.append(point.speed)
        groups.append([point])
    ends += [math.nan] * (len(groups) - len(ends))
    return tuple(Attractor(group[0].speed, group[-1].speed, below, tuple(p.amplitude for p in group),
                           min((p.speed for p in group if p.flange_contact), default=math.nan),
                           _largest(p.flange_force for p in group), _largest(p.instability for p in group))
                 for group, below in zip(groups, ends, strict=True))


def _largest(values) -> float:
    """The largest finite value, ``nan`` when none is."""
    return max((v for v in values if math.isfinite(v)), default=math.nan)
