"""Step control of an assessed time run: the EN 14363 quantities at the run's step against
the same run at twice the step, the step halved until they agree (issue 32, item 3).

The march takes the linear part of every step exactly and feeds the nonlinear forces back
held over the step (:mod:`express.analysis.time.integrator`), so a run's error falls with
its step.  With ``v(dt)`` an assessed quantity at step ``dt``, ``|v(dt) - v(2 dt)|``
estimates the error of ``v(2 dt)`` and bounds that of ``v(dt)`` for a method of order one
or more (Richardson: ``|v(dt) - v(0)| ~ |v(dt) - v(2 dt)| / (2^p - 1)``).  Each
difference is measured against the criterion's limit (a quantity without a limit against
its own size); the run is **converged** when every one is within :data:`TOLERANCE` of it.
Otherwise the step is halved and the finer run compared with the last, at most
:data:`MAX_HALVINGS` times.  A converged check costs 1.5 runs.

What it cannot see: a motion faster than either step follows (above ``1 / (4 dt)``);
``simulate`` warns of the one such motion we know, undamped wheelsets on vertical contact
springs (``docs/contact.md``, "Damp the contact springs").
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from express.base.diagnostics import AnalysisError

__all__ = ["MAX_HALVINGS", "TOLERANCE", "StepCheck", "checked_run", "checked_simulation"]

#: Largest accepted change of an assessed quantity between the step and twice the step,
#: as a fraction of its limit [-].
TOLERANCE = 0.01
#: Halvings of the step at most when the quantities move more.
MAX_HALVINGS = 3


@dataclass(frozen=True)
class StepCheck:
    """The step check of an assessed run.

    Attributes
    ----------
    dt : float
        The step of the reported run [s].
    compared_dt : float
        The step it was checked against, ``2 dt`` [s].
    errors : dict of str to float
        Each criterion's change between the two runs, its estimated step error [its unit].
    scales : dict of str to float
        What each error is measured against: the criterion's limit, or its value's size
        when it has none [its unit].
    tolerance : float
        The largest accepted ``error / scale`` [-].
    steps : tuple of float
        Every step run, in order [s].
    """

    dt: float
    compared_dt: float
    errors: dict[str, float]
    scales: dict[str, float]
    tolerance: float
    steps: tuple[float, ...]

    @property
    def fractions(self) -> dict[str, float]:
        """``error / scale`` of each criterion [-]."""
        return {name: self.errors[name] / self.scales[name] for name in self.errors}

    @property
    def worst(self) -> tuple[str, float]:
        """The criterion that moved most, and its fraction (``("", 0.0)`` with none)."""
        fractions = self.fractions
        if not fractions:
            return "", 0.0
        name = max(fractions, key=lambda key: fractions[key])
        return name, fractions[name]

    @property
    def converged(self) -> bool:
        """Every criterion within the tolerance."""
        return self.worst[1] <= self.tolerance

    def sentence(self) -> str:
        """One line for the command's summary."""
        name, fraction = self.worst
        state = "converged" if self.converged else "NOT converged"
        return (f"step {self.dt * 1e3:g} ms, checked against {self.compared_dt * 1e3:g} ms: {state}, the largest "
                f"change {fraction:.2%} of its limit ({name or 'none'}), tolerance {self.tolerance:.0%}"
                + ("" if len(self.steps) <= 2 else f"; steps run {', '.join(f'{s * 1e3:g}' for s in self.steps)} ms"))

    def as_dict(self) -> dict[str, Any]:
        """JSON form (SI)."""
        return {"dt": self.dt, "compared_dt": self.compared_dt, "converged": self.converged,
                "tolerance": self.tolerance, "worst": self.worst[0], "worst_fraction": self.worst[1],
                "errors": dict(self.errors), "scales": dict(self.scales), "steps": list(self.steps)}


def _compare(fine, coarse, tolerance: float, steps: list[float]) -> StepCheck:
    """The check of ``fine`` (an Assessment at ``steps[-1]``) against ``coarse`` (None:
    the coarse run diverged, which no tolerance accepts)."""
    errors, scales = {}, {}
    values = {} if coarse is None else {c.name: c.value for c in coarse.criteria}
    for criterion in fine.criteria:
        scale = criterion.limit if criterion.limit else abs(criterion.value)
        if not scale:
            continue
        errors[criterion.name] = abs(criterion.value - values[criterion.name]) if coarse is not None else float("inf")
        scales[criterion.name] = abs(scale)
    return StepCheck(steps[-1], 2 * steps[-1], errors, scales, tolerance, tuple(steps))


def checked_run(run: Callable[[float], tuple[Any, Any] | None], dt: float, *, first: tuple[Any, Any] | None = None,
                tolerance: float = TOLERANCE, max_halvings: int = MAX_HALVINGS,
                smallest: float = 1e-5) -> tuple[Any, Any, StepCheck]:
    """Run at ``dt`` and at ``2 dt``, halving ``dt`` until the assessed quantities agree.

    Parameters
    ----------
    run : callable
        ``run(dt)`` gives ``(result, assessment)`` of the run at step ``dt`` [s], or None
        when it diverges (the first run, at ``dt``, must not).
    dt : float
        The step asked for [s].
    first : (result, assessment), optional
        The run at ``dt`` when it has been made already.
    tolerance : float
        :data:`TOLERANCE` by default.
    max_halvings : int
        Halvings at most (:data:`MAX_HALVINGS`).
    smallest : float
        No step below this [s].

    Returns
    -------
    result, assessment, StepCheck
        Of the finest run.
    """
    first = run(dt) if first is None else first
    if first is None:
        raise AnalysisError("the run at the step asked for diverged")
    result, assessment = first
    steps = [2 * dt, dt]
    coarse = run(2 * dt)
    check = _compare(assessment, None if coarse is None else coarse[1], tolerance, steps)
    for _ in range(max_halvings):
        if check.converged or dt / 2 < smallest:
            break
        finer = run(dt / 2)
        if finer is None:
            break
        dt /= 2
        steps.append(dt)
        previous = assessment
        result, assessment = finer
        check = _compare(assessment, previous, tolerance, steps)
    return result, assessment, check


def checked_simulation(vehicle: Any, simulate_at: Callable[[float], Any], assess: Callable[[Any], tuple[Any, Any]],
                       dt: float, *, first: tuple[Any, Any] | None = None,
                       smallest: float = 1e-5) -> tuple[Any, Any, StepCheck]:
    """:func:`checked_run` of a time run of ``vehicle``: ``simulate_at(dt)`` makes the run
    at step ``dt`` [s], a diverged one
    (:func:`~express.analysis.time.divergence.find_divergence`) counts as none, and
    ``assess(run)`` gives its ``(result, assessment)``."""
    from express.analysis.time.divergence import find_divergence

    def run(step: float) -> tuple[Any, Any] | None:
        result = simulate_at(step)
        return None if find_divergence(result, vehicle) is not None else assess(result)

    return checked_run(run, dt, first=first, smallest=smallest)
