"""The demo's Fig. 3: the lever of the paper's Figs. 2 and 5 after a step of ``q1``.

The leverage cases are Table 1's (:data:`express.paper.numbers.PAPER`); a case whose
printed numbers violate its own condition is used with its arms swapped when that
satisfies it (case 3), and the summary says so.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from express.paper.demo_common import write_figure, write_table
from express.paper.numbers import PAPER, LeverCase

__all__ = [
    "LEVER_DAMPING",
    "LEVER_STEP",
    "LEVER_VALUES",
    "LeverStep",
    "lever_cases",
    "lever_step_response",
    "measure_lever",
    "swapped_cases",
    "write_lever",
]

#: Values of the lever model that Table 1 does not give (our choice, stated in Fig. 3):
#: inertias J1, J2 [kg m^2], mass m [kg], pin offset b [m], damper c [N s/m].
LEVER_VALUES = {"J1": 10.0, "m": 20.0, "J2": 0.5, "b": 1.0, "c": 0.0}
#: A rotational damper on the lever c_L [N m s/rad], added so that the curve settles.
LEVER_DAMPING = 40.0
#: Step of q1 [rad].
LEVER_STEP = 1e-3


def lever_cases(printed: tuple[LeverCase, ...] = PAPER.table1) -> tuple[LeverCase, ...]:
    """Table 1's cases as used: a case whose numbers violate its own condition gets its
    arms swapped if that satisfies it (case 3: 60 against 1500 kN becomes 300 = 300 kN)."""
    used = []
    for case in printed:
        if not case.satisfies_condition():
            swapped = replace(case, upper_arm=case.lower_arm, lower_arm=case.upper_arm)
            if swapped.satisfies_condition():
                case = swapped
        used.append(case)
    return tuple(used)


def _case_values(case: LeverCase | Mapping[str, float]) -> dict[str, float]:
    if isinstance(case, LeverCase):
        return {"lLU": case.upper_arm, "lLL": case.lower_arm, "kLU": case.upper_stiffness, "kLL": case.lower_stiffness}
    return {k: float(case[k]) for k in ("lLU", "lLL", "kLU", "kLL")}


def lever_step_response(equations, case: LeverCase | Mapping[str, float], time_s: np.ndarray, *,
                        step: float = LEVER_STEP, damping: float = LEVER_DAMPING) -> tuple[np.ndarray, float]:
    """``q2(t)`` of the lever after a step ``q1 = step`` at ``t = 0`` (``q1`` prescribed).

    The lever row of the generated equations, ``M22 q2'' + (C22 + c_L) q2' + K22 q2 =
    -K21 q1``, is integrated exactly (matrix exponential); ``c_L`` is the added damper.

    Parameters
    ----------
    equations : EquationsOfMotion
        Of ``examples/lever.exp`` (DOFs ``B1.rz`` and ``B2.ry``).
    case : LeverCase or mapping
        The arms and link stiffnesses; a mapping names them as the lever model does:
        ``lLU``, ``lLL`` [m], ``kLU``, ``kLL`` [N/m].
    time_s : numpy.ndarray, shape (T,)
        Equally spaced times [s]; the step is at 0.

    Returns
    -------
    (numpy.ndarray of shape (T,), float)
        ``q2`` [rad] and its static value ``-K21 step / K22`` [rad].
    """
    from scipy.linalg import expm

    from express.numeric.derivation import evaluate_matrices

    values = {**LEVER_VALUES, **_case_values(case)}
    values = {name: values[name] for name in equations.parameters}
    matrices = evaluate_matrices(equations, values)
    i1, i2 = equations.dofs.index("B1.rz"), equations.dofs.index("B2.ry")
    mass = matrices.M[i2, i2]
    damping_total = matrices.C[i2, i2] + damping
    stiffness = matrices.K[i2, i2]
    static = -matrices.K[i2, i1] * step / stiffness
    a = np.array([[0.0, 1.0], [-stiffness / mass, -damping_total / mass]])
    phi = expm(a * float(time_s[1] - time_s[0]))
    # the deviation from the static value starts at -static (q2 = 0, at rest) at t = 0
    deviation = np.array([-static, 0.0])
    q2 = np.zeros(time_s.size)
    for k, t in enumerate(time_s):
        if t < 0:
            continue
        q2[k] = static + deviation[0]
        deviation = phi @ deviation
    return q2, float(static) + 0.0  # no negative zero


@dataclass(frozen=True)
class LeverStep:
    """Fig. 3: the lever's response to a step of ``q1`` in each leverage case.

    Attributes
    ----------
    printed, cases : tuple of LeverCase
        Table 1 as printed, and as used (:func:`lever_cases`).
    time : numpy.ndarray, shape (T,)
        [s].
    q2 : tuple of numpy.ndarray, each shape (T,)
        Lever angle [rad] per case.
    static_q2 : tuple of float
        Static lever angle [rad] per case.
    step, damping : float
        The ``q1`` step [rad] and the added lever damper [N m s/rad].
    """

    printed: tuple[LeverCase, ...]
    cases: tuple[LeverCase, ...]
    time: np.ndarray
    q2: tuple[np.ndarray, ...]
    static_q2: tuple[float, ...]
    step: float
    damping: float


def measure_lever(equations, *, step: float = LEVER_STEP, damping: float = LEVER_DAMPING) -> LeverStep:
    """Step responses of every Table 1 case with the lever ``equations``."""
    time_s = np.round(np.arange(-0.01, 0.12 + 1e-12, 1e-4), 6)
    cases = lever_cases()
    responses = [lever_step_response(equations, case, time_s, step=step, damping=damping) for case in cases]
    return LeverStep(PAPER.table1, cases, time_s, tuple(q for q, _ in responses),
                     tuple(s for _, s in responses), step, damping)


def _label(case: LeverCase) -> str:
    condition = case.condition.replace("lLU kLU", "$l_{LU}k_{LU}$").replace("lLL kLL", "$l_{LL}k_{LL}$")
    return (f"case {case.case}: {condition}  ($l_{{LU}}$ {case.upper_arm:.2f} m, $l_{{LL}}$ {case.lower_arm:.2f} m, "
            f"$k_{{LU}}$ {case.upper_stiffness / 1e3:.0f}, $k_{{LL}}$ {case.lower_stiffness / 1e3:.0f} kN/m)")


def swapped_cases(lever: LeverStep) -> list[tuple[LeverCase, LeverCase]]:
    """``(printed, used)`` of each case whose arms were swapped."""
    return [(p, u) for p, u in zip(lever.printed, lever.cases, strict=True) if p != u]


def write_lever(outdir: Path, lever: LeverStep, log: Callable[[str], None]) -> list[Path]:
    """Draw Fig. 3 and write it with its data; returns the paths written."""
    from express.analysis.plots import figure_lever_step

    columns: dict[str, object] = {"time_s": lever.time}
    drawn = []
    for case, q2, static in zip(lever.cases, lever.q2, lever.static_q2, strict=True):
        drawn.append({"label": _label(case), "q2": q2, "steady": static})
        columns[f"q2_case{case.case}_rad"] = q2
    swaps = "".join(
        f" Case {p.case} as printed in Table 1 (lLU {p.upper_arm:.2f} m, lLL {p.lower_arm:.2f} m) violates {p.condition}; "
        f"the arms are swapped here ({u.upper_arm:.2f}/{u.lower_arm:.2f} m) so that it holds." for p, u in swapped_cases(lever))
    caption = (f"examples/lever.exp, q1 prescribed as a step of {lever.step * 1e3:g} mrad. Our choices: J2 = "
               f"{LEVER_VALUES['J2']:g} kg m², an added lever damper c_L = {lever.damping:g} N m s/rad, "
               f"b = {LEVER_VALUES['b']:g} m.{swaps}")
    figure = figure_lever_step(lever.time, drawn, step=lever.step, caption=caption)
    paths = write_figure(figure, outdir / "fig3_lever_step")
    paths.append(write_table(outdir / "fig3_lever_step.csv", columns))
    log(f"  Fig. 3: static q2 = {', '.join(f'{v * 1e3:+.3f}' for v in lever.static_q2)} mrad")
    return paths
