"""Derived parameters in the exports: which parameters an export takes and which it computes.

A model's parameters are *given* (a number, from the file or ``--set``) or *derived*
from others: closed forms (``P0 = g*(mc + 2*mt + 4*mw)/8``) and function nodes without a
closed form (``[rail.creep]``: f1, f2 from the Hertz ellipse and Kalker's table).  The
equations record keeps these steps in evaluation order
(:attr:`~express.assembly.equations.EquationsOfMotion.derivation`); this module owns

* :func:`derivation_plan`: the steps an export needs for the parameters of its matrices
  (in order), the parameters they compute and the given parameters the export takes;
* :func:`derivation_json`: the steps as the JSON contract writes them
  (``docs/conventions.md``);
* :data:`FUNCTIONS`: the derivation functions an export can ship as code, with their
  arguments and results.  The code itself is in :mod:`express.export.kalker_code`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import sympy as sp

from express.assembly.equations import DerivationCall, DerivationStep, DerivedParameter, EquationsOfMotion

__all__ = ["FUNCTIONS", "DerivationPlan", "derivation_json", "derivation_plan", "step_outputs"]

#: Derivation functions the exports can compute: kind -> (arguments in call order,
#: results in return order).  ``"kalker"`` is :func:`express.rail.contact.creep_coefficients`
#: restricted to f11, f22 (``express.rail.build`` registers it for ``[rail.creep]``).
FUNCTIONS: dict[str, tuple[tuple[str, ...], tuple[str, ...]]] = {
    "kalker": (
        ("wheel_load", "wheel_radius", "rail_head_radius", "youngs_modulus", "poisson"),
        ("f11", "f22"),
    ),
}


@dataclass(frozen=True)
class DerivationPlan:
    """What an export computes and what it takes.

    Attributes
    ----------
    given : tuple of str
        Sorted names of the parameters the export takes: the parameters of the
        matrices and the inputs of the steps, less the derived ones.
    derived : tuple of str
        Names the steps compute, in evaluation order.
    steps : tuple of DerivedParameter or DerivationCall
        The steps needed by the matrices, in evaluation order (a subsequence of the
        record's :attr:`~express.assembly.equations.EquationsOfMotion.derivation`).
    """

    given: tuple[str, ...]
    derived: tuple[str, ...]
    steps: tuple[DerivationStep, ...]


def step_outputs(step: DerivationStep) -> tuple[str, ...]:
    """Names of the parameters a step sets."""
    if isinstance(step, DerivedParameter):
        return (step.name,)
    return tuple(name for _, name in step.outputs)


def _step_inputs(step: DerivationStep) -> set[str]:
    if isinstance(step, DerivedParameter):
        return {s.name for s in sp.sympify(step.expression).free_symbols}
    return {s.name for _, e in step.inputs for s in sp.sympify(e).free_symbols}


def _check_call(step: DerivationCall) -> None:
    if step.kind not in FUNCTIONS:
        raise ValueError(
            f"{step.item}: derivation {step.kind!r} cannot be exported as code "
            f"(known: {', '.join(sorted(FUNCTIONS))})"
        )
    arguments, results = FUNCTIONS[step.kind]
    given = tuple(argument for argument, _ in step.inputs)
    if sorted(given) != sorted(arguments):
        raise ValueError(
            f"{step.item}: derivation {step.kind!r} takes the arguments {', '.join(arguments)}, "
            f"got {', '.join(given) or 'none'}"
        )
    unknown = [key for key, _ in step.outputs if key not in results]
    if unknown:
        raise ValueError(f"{step.item}: derivation {step.kind!r} has no result {', '.join(unknown)}")


def derivation_plan(eom: EquationsOfMotion) -> DerivationPlan:
    """The derivation steps an export of ``eom`` needs, and the parameters it takes.

    Parameters
    ----------
    eom : EquationsOfMotion
        The record; without derivation steps every parameter is given.

    Returns
    -------
    DerivationPlan
        Only the steps that lead to a parameter of the matrices are kept (a step whose
        results no matrix uses is left out, with the given parameters only it needs).

    A function step of a kind the exports cannot write as code (the conicity from
    wheel and rail profiles, a contact-geometry computation) is left out: its results
    are given parameters of the export, with the values they had at generation.

    Raises
    ------
    ValueError
        For a known function step with other arguments, or a parameter set by two steps.
    """
    needed = set(eom.parameters)
    kept: list[DerivationStep] = []
    for step in reversed(eom.derivation):
        if isinstance(step, DerivationCall):
            if step.kind not in FUNCTIONS:
                continue  # computed numerically only (e.g. "profiles"): its results are given values
            _check_call(step)
        if needed & set(step_outputs(step)):
            kept.append(step)
            needed |= _step_inputs(step)
    kept.reverse()
    derived: list[str] = []
    for step in kept:
        for name in step_outputs(step):
            if name in derived:
                raise ValueError(f"parameter {name!r} is set by two derivation steps")
            derived.append(name)
    given = tuple(sorted(needed - set(derived)))
    return DerivationPlan(given=given, derived=tuple(derived), steps=tuple(kept))


def derivation_json(plan: DerivationPlan) -> list[dict[str, Any]]:
    """The steps of ``plan`` as the JSON document lists them (``docs/conventions.md``).

    Returns
    -------
    list of dict
        ``{"parameter": name, "expression": text}`` for a closed form;
        ``{"function": kind, "item": item, "arguments": {argument: text, ...},
        "results": {result key: parameter name, ...}}`` for a function node.  Texts
        are in SymPy syntax, like the matrix entries.
    """
    out: list[dict[str, Any]] = []
    for step in plan.steps:
        if isinstance(step, DerivedParameter):
            out.append({"parameter": step.name, "expression": sp.sstr(step.expression)})
        else:
            out.append({
                "function": step.kind,
                "item": step.item,
                "arguments": {argument: sp.sstr(expression) for argument, expression in step.inputs},
                "results": dict(step.outputs),
            })
    return out
