"""The steady state of a vehicle with friction, reached through the curve's transition
(issue 31, item 7; ``docs/curving.md``, "Friction: the state reached through the
transition").

With friction elements the equilibria in a curve form a continuum: every slider position
whose spring force stays within its limit is one. Which the vehicle sits in depends on the
path into the curve. :class:`~express.analysis.curving.steady.SteadyCurvingSolver` (its
``path = "transition"``, the default for a vehicle with friction) therefore

1. runs the vehicle into the curve as a track takes it (:func:`march_into`): straight
   track, a linear transition of curvature and cant (:func:`transition_length`), then the
   circular curve for :data:`SETTLE_TIME` of running, at a step that resolves the friction
   elements' pre-slip springs (:func:`resolved_dt`);
2. takes the sliders where the run leaves them and solves the equilibrium for them
   (:func:`hold_sliders`): every element held stuck at its slider, the smooth equations
   solved by the solver's pseudo-transient iteration. Where a spring force then exceeds
   its limit, the equations with the law itself (the sliders return-mapped from the
   held ones, the march's rule: those elements slip) are solved from there, the sliders
   taken where that leaves them, and held again — until every force is within its limit:
   an exact equilibrium (residual ~1e-11) on the path's own sliders.

``path = "rest"`` keeps the earlier answer: the sliders at rest, the curve loaded from
straight track in one step (a monotone, proportional loading).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

__all__ = ["HOLD_ROUNDS", "LEAD", "SETTLE_TIME", "hold_sliders", "march_into", "resolved_dt", "transition_length"]

#: Straight track before the transition [m].
LEAD = 20.0
#: Running time in the circular curve before the sliders are read [s].
SETTLE_TIME = 6.0
#: Largest number of hold-and-return rounds of :func:`hold_sliders`.
HOLD_ROUNDS = 50
#: The default step of the time runs [s]: ``simulate``'s.
DEFAULT_DT = 0.005


def transition_length(radius: float) -> float:
    """The transition into a curve of ``radius`` [m]: ``max(50 m, R / 4)`` [m] (a clothoid
    with a cant ramp of the usual 1:400 to 1:1000 for the cants of such curves)."""
    return max(50.0, 0.25 * float(radius))


def resolved_dt(forces: Any, mass: np.ndarray) -> float:
    """The step of a time run that resolves the force elements' stiffest explicit
    feedback (``ForceSet.resolved_step``), at most :data:`DEFAULT_DT` [s]."""
    resolved = forces.resolved_step(mass)
    return DEFAULT_DT if resolved is None else min(DEFAULT_DT, float(resolved))


def march_into(vehicle: Any, curve: Any, speed: float, dt: float, ids: tuple[str, ...],
               **options) -> tuple[np.ndarray, np.ndarray, str]:
    """Run ``vehicle`` through a transition into ``curve`` at ``speed`` [m/s], step ``dt``
    [s]: ``(state, sliders, path)`` at the end, the friction elements ``ids``' slider
    positions [m; rad] and a sentence saying the path.

    ``options``: ``contact``, ``creep_law``, ``flange``, ``saturation`` of
    :func:`~express.analysis.time.simulate.simulate`.
    """
    from express.analysis.time.simulate import simulate
    from express.rail.track import Curve, Straight, Track, Transition

    transition = transition_length(curve.radius)
    settle = max(60.0, SETTLE_TIME * speed)
    track = Track((Straight(LEAD), Transition(transition), Curve(settle, curve.radius, curve.direction, curve.cant)))
    run = simulate(vehicle, track, speed=speed, dt=dt, progress=False, **options)
    state = np.concatenate([run.q[-1], run.q_dot[-1][vehicle.form.massive]])
    sliders = np.array([run.outputs[f"slip_{name}"][-1] for name in ids])
    path = (f"through a {transition:g} m transition from straight track (time march at {dt * 1e3:.3g} ms, "
            f"{settle:g} m into the curve), the sliders where the run left them")
    return state, sliders, path


def hold_sliders(equations: Callable, friction: Any, start: np.ndarray, scale: float,
                 solve: Callable) -> tuple[np.ndarray, int, float, int]:
    """The equilibrium for the sliders of ``friction`` (module docstring, step 2):
    ``(state, evaluations, residual, rounds)``.

    Parameters
    ----------
    equations : callable
        ``x -> (f, jacobian)`` of the steady state, through ``friction``'s forces.
    friction : FrictionElement
        Its ``slider`` is the start and is left at the answer's sliders.
    start : numpy.ndarray, shape (N,)
    scale : float
        The residual's scale (``|B u|``).
    solve : callable
        ``(equations, x, scale) -> (x, evaluations, residual)``: the solver's iteration.
    """
    x, evaluations, residual, rounds = start, 0, np.inf, 0
    try:
        for rounds in range(1, HOLD_ROUNDS + 1):  # noqa: B007 (the count is returned)
            friction.frozen = True
            x, count, residual = solve(equations, x, scale)
            evaluations += count
            friction.frozen = False
            if not friction.beyond(x, 0).any():
                break
            x, count, _ = solve(equations, x, scale)  # the law itself: sliders return-mapped from the held ones
            evaluations += count
            friction.slider[:] = friction.return_mapped(x, 0)
    finally:
        friction.frozen = False
    return x, evaluations, residual, rounds
