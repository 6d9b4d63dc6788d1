"""Physical valid ranges of a model's values, from the place each value is used.

A value means something only where it is used: a body's mass is a mass, and may not
be negative; a wheelset's friction coefficient must be positive (the creep forces
saturate at ``mu N``); a cant base of zero divides the cant by nothing.  :func:`range_problems` evaluates every use of the model
(:func:`express.model.parameter_units.use_sites`) at the current values and reports each
one outside its range, naming the parameter (its file and line, or the ``--set``
that gave it), the use and the range; :func:`check_ranges` raises them together and
issues the warnings.  The readers (through :func:`express.model.parameters.resolve`) and
:func:`express.model.parameters.with_values` (``--set``, studies) call it, so a bad value
is refused before any work, with status 2 on the command line.

Valid ranges (SI; "warns" marks a value below zero that is allowed with a warning):

- body mass 0 <= m <= 1e8 kg, inertia Ix, Iy, Iz 0 <= I <= 1e11 kg m^2; zero is a
  massless idealization (the paper's lever), allowed when a pin gives the DOF its
  mass: a DOF whose generalized mass is zero is a warning of ``generate`` and is
  refused by every numerical analysis (:mod:`express.numeric.statespace`), naming the DOF;
- positions, CP offsets, output offsets: |x| <= 1e5 m;
- element stiffness and damping: |x| <= 1e15 (N/m, N s/m, N m/rad, N m s/rad), warns;
  progressive stiffness |x| <= 1e24 N/m^3 (rotational 1e15 N m/rad), warns;
  gap 0 <= gap <= 1e5 m (rotational: pi rad);
- gravity and rail gravity: 0 <= g <= 100 m/s^2; rail speed 0 < v <= 1000 km/h;
  cant base 0 < G <= 5 m;
- wheelset: creep coefficients 0 <= f1, f2 <= 1e12 N; conicity 0 <= lambda <= 1;
  rolling radius and contact half distance 0 < r0, b <= 2 m; flange clearance
  0 <= delta <= 0.1 m; rail stiffness 0 <= kR <= 1e15 N/m; friction 0 < mu <= 1;
  wheel load 0 < P <= 1e12 N.

The upper bounds lie far beyond any vehicle (a 100 000 t body, a 1e15 N/m spring:
the rigid elements of the tests use 1e12): they catch a value such as ``ky1=1e300``,
whose matrices are numerically meaningless, and a slip of units by many orders of
magnitude.  A negative stiffness or damping of an ordinary element is legal (a
modelling device: a negative-stiffness mechanism, a fitted element) but is worth a
:class:`~express.base.diagnostics.ModelWarning`; its consequences are the analyses' to
judge (a simulation that diverges ends with status 1).

A wheelset must carry its own weight: its mass times gravity may not exceed the load
of its two wheels (``m g <= 2 P``; the static wheel load includes the wheelset).  A
car body listed among the wheelsets (30 t on wheels loaded with 50 kN) is refused.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Mapping
from dataclasses import dataclass

import sympy as sp

from express.base.caches import IdentityCache
from express.base.diagnostics import ModelError, ModelWarning, Problem
from express.base.expressions import expression_value
from express.base.units import KMH, format_quantity, unit_factor
from express.model.parameter_units import UseSite, use_sites
from express.model.records import Model

__all__ = ["ValidRange", "check_ranges", "parameter_bounds", "range_problems"]

MASS_MAX = 1e8  # kg
INERTIA_MAX = 1e11  # kg m^2
LENGTH_MAX = 1e5  # m
ELEMENT_MAX = 1e15  # N/m, N s/m, N m/rad, N m s/rad
PROGRESSIVE_MAX = 1e24  # N/m^3
FORCE_MAX = 1e12  # N
GRAVITY_MAX = 100.0  # m/s^2


@dataclass(frozen=True)
class ValidRange:
    """``low <(=) value <= high`` in SI, shown in ``unit``; ``warn_negative``: a
    value below zero is allowed with a warning (``low`` is then the magnitude bound)."""

    low: float
    high: float
    unit: str = ""
    open_low: bool = False
    warn_negative: bool = False
    note: str = ""

    def contains(self, value: float) -> bool:
        above = value > self.low if self.open_low else value >= self.low
        return math.isfinite(value) and above and value <= self.high

    def show(self, value: float) -> str:
        return format_quantity(value, self.unit)

    def text(self, what: str) -> str:
        """``0 < mass <= 1e+08 kg``."""
        factor = unit_factor(self.unit) if self.unit else 1.0
        sign = "<" if self.open_low else "<="
        unit = f" {self.unit}" if self.unit else ""
        return f"{self.low / factor:g} {sign} {what} <= {self.high / factor:g}{unit}"


def _symmetric(high: float, unit: str, warn_negative: bool = False) -> ValidRange:
    return ValidRange(-high, high, unit, warn_negative=warn_negative)


_RAIL = {
    "speed": ValidRange(0.0, 1000.0 * KMH, "km/h", open_low=True),
    "cant_base": ValidRange(0.0, 5.0, "m", open_low=True, note="the cant is divided by it"),
    "gravity": ValidRange(0.0, GRAVITY_MAX, "m/s^2"),
}
_WHEELSET = {
    "f1": ValidRange(0.0, FORCE_MAX, "N"),
    "f2": ValidRange(0.0, FORCE_MAX, "N"),
    "conicity": ValidRange(0.0, 1.0, ""),
    "r0": ValidRange(0.0, 2.0, "m", open_low=True),
    "b": ValidRange(0.0, 2.0, "m", open_low=True),
    "flange_clearance": ValidRange(0.0, 0.1, "m"),
    "rail_stiffness": ValidRange(0.0, ELEMENT_MAX, "N/m"),
    "friction": ValidRange(0.0, 1.0, "", open_low=True, note="the creep forces saturate at friction x wheel load"),
    "wheel_load": ValidRange(0.0, FORCE_MAX, "N", open_low=True),
}


def _site_range(site: UseSite, bodies: dict, elements: dict) -> ValidRange | None:
    """The valid range of one use of a value (None: any finite value)."""
    kind, _, name = site.item.partition(" ")
    if kind == "body" and name in bodies:
        if site.what == "mass":
            return ValidRange(0.0, MASS_MAX, "kg")
        if site.what.startswith("inertia I"):
            return ValidRange(0.0, INERTIA_MAX, "kg*m^2")
        return _symmetric(LENGTH_MAX, "m")
    if kind in ("CP", "output"):
        return _symmetric(LENGTH_MAX, "m")
    if kind == "TSD" and name in elements:
        rotational = elements[name].rotational
        if site.what == "stiffness":
            return _symmetric(ELEMENT_MAX, "N*m/rad" if rotational else "N/m", warn_negative=True)
        if site.what == "damping":
            return _symmetric(ELEMENT_MAX, "N*m*s/rad" if rotational else "N*s/m", warn_negative=True)
        if site.what == "gap":
            return ValidRange(0.0, math.pi, "rad") if rotational else ValidRange(0.0, LENGTH_MAX, "m")
        if site.what == "friction limit":
            return ValidRange(0.0, FORCE_MAX, "N*m" if rotational else "N", open_low=True)
        if site.what == "progressive stiffness":
            return _symmetric(ELEMENT_MAX, "N*m/rad", True) if rotational else _symmetric(PROGRESSIVE_MAX, "N/m^3", True)
    if kind == "gravity":
        return ValidRange(0.0, GRAVITY_MAX, "m/s^2")
    if kind == "rail":
        return _RAIL.get(site.what)
    if kind == "wheelset":
        return _WHEELSET.get(site.what)
    return None  # derivation inputs: the derivation checks its own arguments


@dataclass(frozen=True)
class _Check:
    """One distinct value to check: its expression, range and first use."""

    expression: sp.Expr
    valid: ValidRange
    site: UseSite
    uses: int


class _Checks:
    """The checks of a model's structure (bodies, elements, rail data), built once and
    reused while only the parameter values change (``with_values`` in a study)."""

    def __init__(self, model: Model):
        bodies = {body.id: body for body in model.bodies}
        elements = {element.id: element for element in model.elements}
        found: dict[tuple, list] = {}
        for site in use_sites(model):
            valid = _site_range(site, bodies, elements)
            expression = sp.sympify(site.expression)
            if valid is None or (expression.is_Number and valid.contains(float(expression)) and float(expression) >= 0):
                continue  # a constant inside its range stays inside it
            key = (expression, valid)
            if key in found:
                found[key][1] += 1
            else:
                found[key] = [site, 1]
        self.checks = tuple(_Check(expression, valid, site, uses) for (expression, valid), (site, uses) in found.items())
        self.wheelsets = []
        if model.rail is not None:
            for wheelset in model.rail.wheelsets:
                if wheelset.body in bodies:
                    self.wheelsets.append((wheelset, bodies[wheelset.body].mass, model.rail.gravity))


_CACHE: IdentityCache[_Checks] = IdentityCache(8)


def _checks(model: Model) -> _Checks:
    parts = (model.bodies, model.points, model.elements, model.rail, model.gravity, model.derivations)
    return _CACHE.get_or_make(parts, lambda: _Checks(model))


def _value(expression: sp.Expr, values: Mapping[str, float]) -> float | None:
    """The value of a use, or None when it cannot be computed yet (missing names:
    reported elsewhere, or a symbolic model)."""
    if expression.is_Symbol:
        value = values.get(expression.name)
        return None if value is None or math.isnan(value) else float(value)
    try:
        value = expression_value(expression, values)
    except (KeyError, ValueError):
        return None
    return None if math.isnan(value) else value


def _origin(model: Model, expression: sp.Expr, overridden: Mapping[str, object]) -> str:
    names = sorted(s.name for s in expression.free_symbols if s.name in overridden)
    return f" (with {', '.join(names)} set)" if names else ""


def _uses(check: _Check) -> str:
    more = check.uses - 1
    return check.site.where + (f" and {more} more use{'s' if more > 1 else ''}" if more else "")


def _problem(model: Model, check: _Check, value: float, overridden: Mapping[str, object]) -> Problem:
    valid, site, expression = check.valid, check.site, check.expression
    shown = valid.show(value)
    note = f" ({valid.note})" if valid.note else ""
    where = site.what if site.what else "value"
    if expression.is_Symbol and expression.name in model.parameters:
        name = expression.name
        parameter = model.parameters[name]
        if name in overridden:
            return Problem(
                model.source, None, f"parameter {name}",
                f"set to {shown}, outside the valid range {valid.text(where)} of its use as {_uses(check)}{note}",
            )
        if parameter.expression is not None:
            shown = f"{sp.sstr(parameter.expression)} = {shown}{_origin(model, parameter.expression, overridden)}"
        return Problem(
            model.source, parameter.line, f"parameter {name}",
            f"{shown} is outside the valid range {valid.text(where)} of its use as {_uses(check)}{note}",
        )
    return Problem(
        model.source, site.line, site.item,
        f'{where} "{sp.sstr(expression)}" = {shown}{_origin(model, expression, overridden)} is outside '
        f"the valid range {valid.text(where)}{note}",
    )


def _warning(model: Model, check: _Check) -> str:
    expression, site = check.expression, check.site
    subject = f"parameter {expression.name}" if expression.is_Symbol else f'{site.item}: {site.what} "{sp.sstr(expression)}"'
    return (
        f"{model.source}: {subject}: a negative {site.what} ({_uses(check)}) is a modelling device, "
        "not a physical element; the analyses check their own results (a diverging simulation ends with status 1)"
    )


def _wheelset_problems(model: Model, checks: _Checks, values: Mapping[str, float]) -> list[Problem]:
    """A wheelset must carry its own weight: ``m g <= 2 P``."""
    problems = []
    for wheelset, mass, gravity in checks.wheelsets:
        m, g, load = _value(sp.sympify(mass), values), _value(sp.sympify(gravity), values), _value(sp.sympify(wheelset.wheel_load), values)
        if m is None or g is None or load is None or not (m > 0 and g > 0 and load > 0):
            continue  # reported as a range problem, or not known
        if m * g > 2.0 * load * (1.0 + 1e-9):
            problems.append(Problem(
                model.source, wheelset.line, f"wheelset {wheelset.body}",
                f"body {wheelset.body} weighs {format_quantity(m * g, 'kN')} ({format_quantity(m, 't')}), more than its "
                f"two wheels carry (2 x wheel_load = {format_quantity(2 * load, 'kN')}): not a wheelset (a wheelset's "
                "weight is part of its wheel load)",
            ))
    return problems


def range_problems(model: Model, overridden: Mapping[str, object] | None = None) -> tuple[list[Problem], list[str]]:
    """Every use of a value outside its valid range, and the warnings.

    Parameters
    ----------
    model : Model
        With its parameter values evaluated (a use whose value is unknown is skipped).
    overridden : mapping of str to object, optional
        Values given on the command line (``--set``) by name, as given: a problem of
        one of them names the ``--set`` instead of the file's line.

    Returns
    -------
    problems : list of Problem
        One per parameter (or per use of an expression) outside its range.
    warnings : list of str
        One per parameter with a negative stiffness or damping.
    """
    overridden = overridden or {}
    checks = _checks(model)
    values = model.values()
    problems, notes, reported = [], [], set()
    locked = {f"TSD {element.id}" for element in model.elements if element.series}
    for check in checks.checks:
        value = _value(check.expression, values)
        if value is None:
            continue
        if value == float("inf") and check.site.what == "damping" and check.site.item in locked:
            continue  # a series element's locked damper: the element is its spring
        key = check.expression.name if check.expression.is_Symbol else (check.site.item, check.site.what)
        if not check.valid.contains(value):
            if key not in reported:
                reported.add(key)
                problems.append(_problem(model, check, value, overridden))
        elif check.valid.warn_negative and value < 0 and ("warn", key) not in reported:
            reported.add(("warn", key))
            notes.append(_warning(model, check))
    return problems + _wheelset_problems(model, checks, values), notes


def check_ranges(model: Model, overridden: Mapping[str, object] | None = None) -> None:
    """Raise every range problem of ``model`` together; warn of negative elements.

    Raises
    ------
    ModelError
        Naming each value outside its valid range (see :func:`range_problems`).
    """
    problems, notes = range_problems(model, overridden)
    if problems:
        raise ModelError(problems)
    for note in notes:
        warnings.warn(note, ModelWarning, stacklevel=3)


def parameter_bounds(model: Model) -> dict[str, tuple[float, float, bool]]:
    """The valid range of each parameter used by name, from every use of it:
    ``(low, high, open_low)`` in SI, the intersection of its uses' ranges.

    A vehicle read back without its model file (the warm entry of
    :mod:`express.numeric.warm`) checks its values against these, so that a value the
    model file could not give is never used.  A series element's locked damper
    (``inf``) is left out, as :func:`range_problems` leaves it.
    """
    locked = {f"TSD {element.id}" for element in model.elements if element.series}
    bounds: dict[str, tuple[float, float, bool]] = {}
    skipped: set[str] = set()
    for check in _checks(model).checks:
        expression = check.expression
        if not (expression.is_Symbol and expression.name in model.parameters):
            continue
        name, valid = expression.name, check.valid
        if check.site.what == "damping" and check.site.item in locked:
            skipped.add(name)
            continue
        low, high, open_low = bounds.get(name, (-math.inf, math.inf, False))
        if valid.low > low or (valid.low == low and valid.open_low):
            low, open_low = valid.low, valid.open_low
        bounds[name] = (low, min(high, valid.high), open_low)
    return {name: bound for name, bound in bounds.items() if name not in skipped}

