"""The choice of how the linear analyses see the nonlinear elements (:class:`Linearisation`:
``tangent``, ``equivalent`` at an amplitude and frequency, ``statistical`` at levels),
light enough for a warm command to read its options without the symbolic model
(``docs/analyses.md``, "Linearisation of the nonlinear elements";
:mod:`express.forces.linearisation` applies it)."""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field

from express.base.arguments import si_argument
from express.base.diagnostics import ArgumentError

__all__ = ["KINDS", "Linearisation"]

#: The linearisations the linear analyses take (module docstring).
KINDS = ("tangent", "equivalent", "statistical")


@dataclass(frozen=True)
class Linearisation:
    """A choice of linearisation of the nonlinear elements (:mod:`express.forces.linearisation`).

    Attributes
    ----------
    kind : str
        One of :data:`KINDS`.
    amplitude : float
        ``equivalent``: deflection amplitude of the translational elements [m].
    angle : float
        ``equivalent``: deflection amplitude of the rotational elements [rad].
    frequency : float
        ``equivalent``: frequency of the harmonic motion [Hz].
    levels : mapping of str to (float, float)
        ``statistical``: each element's rms deflection [m; rad] and rate [m/s; rad/s];
        an element without one is taken at its tangent.
    """

    kind: str = "tangent"
    amplitude: float = 1e-3
    angle: float = 1e-3
    frequency: float = 2.0
    levels: Mapping[str, tuple[float, float]] = field(default_factory=dict)

    def __post_init__(self) -> None:
        if self.kind not in KINDS:
            raise ArgumentError(f"linearisation must be one of {', '.join(KINDS)}, not {self.kind!r}")
        object.__setattr__(self, "amplitude", si_argument(self.amplitude, "length", "amplitude"))
        object.__setattr__(self, "angle", si_argument(self.angle, "angle", "angle"))
        object.__setattr__(self, "frequency", si_argument(self.frequency, "frequency", "frequency"))
        bad = [name for name, value in (("amplitude", self.amplitude), ("angle", self.angle), ("frequency", self.frequency))
               if not (math.isfinite(value) and value > 0.0)]
        if bad:
            raise ArgumentError(f"linearisation: {', '.join(bad)} must be finite and > 0")

    def describe(self) -> str:
        """One line for the outputs: which linearisation, at what."""
        if self.kind == "equivalent":
            return (f"equivalent (describing functions) at amplitude {self.amplitude * 1e3:g} mm, "
                    f"{self.angle * 1e3:g} mrad, frequency {self.frequency:g} Hz")
        if self.kind == "statistical":
            return "statistical (Gaussian) at each element's rms response"
        return "tangent at the static state (friction stuck)"
