"""Dimensions of a model's parameters, checked against every place a value is used.

Every value of a model is used somewhere that fixes its dimension: a body's mass is
a mass, a CP offset a length, a translational element's stiffness N/m and a
rotational one's N*m/rad, a wheelset's conicity a pure number, the rail speed a
speed (:func:`use_sites` lists them all).  A parameter written with a unit has that
unit's dimension; a bare number (SI) takes the dimension of its use; a derived
parameter the dimension of its expression, checked through its operations (``kLU/2``
is N/m when kLU is, ``a + mc`` adds a length and a mass and is refused).  A number
inside an expression is a pure number in a product and takes the dimension of the
sum it is added to (``h1 - 0.3`` is a length).

:func:`infer_dimensions` returns the dimension of every parameter it could settle
and one :class:`~express.base.diagnostics.Problem` per mismatch, e.g.
``bad.toml:12: parameter hc: used as a length (body CB position) but has unit kg``.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from fractions import Fraction

import sympy as sp

from express.base.diagnostics import Problem
from express.base.units import DIMENSIONS, Dimension, UnitError, describe_dimension, dimension_of, unit_dimension
from express.model.records import AXES, Model

__all__ = ["UseSite", "infer_dimensions", "use_sites"]

#: Dimensions of the wheel/rail data of a wheelset (``docs/model-format.md``).
WHEELSET_DIMENSIONS = {
    "f1": "force",
    "f2": "force",
    "conicity": "dimensionless",
    "r0": "length",
    "b": "length",
    "flange_clearance": "length",
    "rail_stiffness": "stiffness",
    "friction": "dimensionless",
    "wheel_load": "force",
}
_CUBIC = Dimension(Fraction(1), Fraction(-2), Fraction(-2))  # N/m^3, a progressive stiffness


@dataclass(frozen=True)
class UseSite:
    """One place a value is used: ``what`` of ``item`` must have ``dimension``.

    ``dimension`` is a name of :data:`express.base.units.DIMENSIONS` or a
    :class:`~express.base.units.Dimension`; ``line`` the line of the item.
    """

    expression: sp.Expr
    dimension: str | Dimension
    item: str
    what: str
    line: int | None

    @property
    def where(self) -> str:
        return f"{self.item} {self.what}".strip()


def use_sites(model: Model) -> Iterator[UseSite]:
    """Every value of ``model`` with the dimension its place requires."""
    for body in model.bodies:
        item = f"body {body.id}"
        yield UseSite(body.mass, "mass", item, "mass", body.line)
        for axis, value in zip(AXES, body.inertia, strict=True):
            yield UseSite(value, "inertia", item, f"inertia I{axis}", body.line)
        for value in body.position:
            yield UseSite(value, "length", item, "position", body.line)
    for point in model.points:
        for value in point.offset:
            yield UseSite(value, "length", f"CP {point.id}", "offset", point.line)
    for element in model.elements:
        item = f"TSD {element.id}"
        rotational = getattr(element, "rotational", False)
        checked = getattr(element, "checked", ())
        if not checked or getattr(element, "characteristic", None) is not None:  # else derived from the checked
            yield UseSite(element.stiffness, "rotational_stiffness" if rotational else "stiffness", item, "stiffness",
                          element.line)
            yield UseSite(element.damping, "rotational_damping" if rotational else "damping", item, "damping",
                          element.line)
        gap = getattr(element, "gap", None)
        if gap is not None:
            yield UseSite(gap, "angle" if rotational else "length", item, "gap", element.line)
            progressive = getattr(element, "progressive", sp.S.Zero)
            cubic = DIMENSIONS["rotational_stiffness"] if rotational else _CUBIC
            yield UseSite(progressive, cubic, item, "progressive stiffness", element.line)
        friction = getattr(element, "friction", sp.S.Zero)
        if sp.sympify(friction) != 0 and getattr(element, "friction_of", ""):  # mu (rotational: mu r) of a load
            yield UseSite(friction, "length" if rotational else "dimensionless", item,
                          "friction mu" + (" times radius" if rotational else ""), element.line)
        elif sp.sympify(friction) != 0:
            yield UseSite(friction, DIMENSIONS["force"] * DIMENSIONS["length"] if rotational else "force", item,
                          "friction limit", element.line)
        for what, value, dimension, _ in checked:
            yield UseSite(value, dimension, item, what, element.line)
    gravity = getattr(model, "gravity", None)
    if gravity is not None:
        yield UseSite(gravity, "acceleration", "gravity", "acceleration", None)
    rail = model.rail
    if rail is not None:
        yield UseSite(rail.speed, "speed", "rail", "speed", rail.line)
        yield UseSite(rail.cant_base, "length", "rail", "cant_base", rail.line)
        yield UseSite(rail.gravity, "acceleration", "rail", "gravity", rail.line)
        for wheelset in rail.wheelsets:
            for key, name in WHEELSET_DIMENSIONS.items():
                yield UseSite(getattr(wheelset, key), name, f"wheelset {wheelset.body}", key, wheelset.line)
        for output in rail.outputs:
            for value in output.offset:
                yield UseSite(value, "length", f"output {output.name}", "offset", output.line)
    for flexible in getattr(model, "flexible", ()):  # express.model.modal_body
        for mode in flexible.modes:
            yield UseSite(mode.zeta, "dimensionless", f"flexible {flexible.body} mode {mode.name}", "damping", mode.line)
    for derivation in model.derivations:
        for argument, expression, kind in derivation.inputs:
            yield UseSite(expression, kind, derivation.item, argument, derivation.line)


class _MismatchError(Exception):
    """An expression that adds quantities of different dimensions."""


_ANY = "any"  # a bare number: the dimension of the sum it is in, pure in a product


def _words(dim: Dimension | str, unit: bool = True) -> str:
    """``"a stiffness (N/m)"`` (``unit=False``: ``"a stiffness"``), ``"a quantity in kg*m"``."""
    words = describe_dimension(dim)
    if isinstance(dim, Dimension) and words == dim.si():
        return f"a quantity in {words}"
    if not unit:
        words = words.rsplit(" (", 1)[0]
    return ("an " if words[0] in "aeiou" else "a ") + words


class _Inference:
    def __init__(self, model: Model):
        self.model = model
        self.parameters = model.parameters
        self.dims: dict[str, Dimension] = {}
        self.why: dict[str, str] = {}
        self.angles: set[str] = set()
        self.problems: list[Problem] = []
        self.reporting = False
        self.seen: set[tuple] = set()
        self.pending: list[tuple] = []
        self.draining = False
        for name, parameter in self.parameters.items():
            if parameter.is_primary and parameter.unit.strip() not in ("",):
                try:
                    self.dims[name] = unit_dimension(parameter.unit)
                    if dimension_of(parameter.unit) == "angle":
                        self.angles.add(name)
                except UnitError:
                    continue  # the reader reports the unit
                self.why[name] = f"has unit {parameter.unit.strip()}"
        for derivation in model.derivations:
            for _, name, dim in derivation.outputs:
                if name in self.parameters and self.parameters[name].derived_by == derivation.item:
                    if dim is None:
                        continue  # a flexible beam's angular frequency: a bare number in rad/s
                    self.dims[name] = DIMENSIONS[dim] if isinstance(dim, str) else dim  # a flexible beam's shapes
                    self.why[name] = f"is computed by {derivation.item} as {_words(dim)}"

    # -- forward: the dimension of an expression (None: not known yet)
    def dim(self, expression) -> Dimension | str | None:
        expression = sp.sympify(expression)
        if expression.is_Number:
            return _ANY
        if expression.is_Symbol:
            return self.dims.get(expression.name)
        if expression.is_Add:
            known: list[tuple[sp.Expr, Dimension]] = []
            unknown = False
            for term in expression.args:
                d = self.dim(term)
                if d is None:
                    unknown = True
                elif d != _ANY:
                    known.append((term, d))  # type: ignore[arg-type]
            for term, d in known[1:]:
                if d != known[0][1]:
                    first, dim0 = known[0]
                    raise _MismatchError(
                        f"adds {_words(dim0)} ({sp.sstr(first)}) and {_words(d)} ({sp.sstr(term)})"
                    )
            if known:
                return known[0][1]
            return None if unknown else _ANY
        if expression.is_Mul:
            total, unknown, pure = Dimension(), False, True
            for factor in expression.args:
                d = self.dim(factor)
                if d is None:
                    unknown = True
                elif d != _ANY:
                    total, pure = total * d, False  # type: ignore[operator]
            if unknown:
                return None
            return _ANY if pure else total
        if expression.is_Pow and expression.exp.is_Rational:
            base = self.dim(expression.base)
            if base is None or base == _ANY:
                return base
            return base ** Fraction(int(expression.exp.p), int(expression.exp.q))  # type: ignore[operator]
        return None

    # -- backward: an expression used where ``wanted`` is required
    def expect(self, expression, wanted: Dimension, site: UseSite) -> None:
        expression = sp.sympify(expression)
        try:
            found = self.dim(expression)
        except _MismatchError as mismatch:
            if expression.is_Add:  # blame the terms that are not what the use needs
                for term in expression.args:
                    self.expect(term, wanted, site)
            else:
                self.report(site.line, site.item, f'{site.what} "{sp.sstr(expression)}" {mismatch}'.strip())
            return
        if found == _ANY:
            return
        if isinstance(found, Dimension):
            if found != wanted:
                self.blame(expression, found, wanted, site)
            elif site.dimension == "dimensionless" and expression.is_Symbol and expression.name in self.angles:
                parameter = self.parameters[expression.name]
                self.report(
                    parameter.line,
                    f"parameter {expression.name}",
                    f"used as a pure number ({site.where}) but has the angle unit {parameter.unit.strip()}",
                )
            return
        if expression.is_Symbol:
            self.assign(expression.name, wanted, site)
        elif expression.is_Add:
            for term in expression.args:
                self.expect(term, wanted, site)
        elif expression.is_Mul or expression.is_Pow:
            known, unknown = Dimension(), []
            for factor in sp.Mul.make_args(expression):
                d = self.dim(factor)
                if d is None:
                    unknown.append(factor)
                elif d != _ANY:
                    known = known * d  # type: ignore[operator]
            if len(unknown) == 1:
                base, power = unknown[0].as_base_exp()
                if power.is_Rational and power != 0:
                    needed = (wanted / known) ** (1 / Fraction(int(power.p), int(power.q)))
                    self.expect(base, needed, site)

    def assign(self, name: str, wanted: Dimension, site: UseSite) -> None:
        parameter = self.parameters.get(name)
        if parameter is None:
            return  # an undefined name: reported where values are needed
        self.dims[name] = wanted
        line = f", line {site.line}" if site.line is not None else ""
        self.why[name] = f"is used as {_words(wanted, unit=False)} ({site.where}{line})"
        if parameter.expression is None:
            return
        # a chain of thousands of parameters goes backwards through a work list, not the stack
        self.pending.append((parameter.expression, wanted, UseSite(parameter.expression, wanted, f"parameter {name}", "",
                                                                   parameter.line)))
        if self.draining:
            return
        self.draining = True
        try:
            while self.pending:
                self.expect(*self.pending.pop())
        finally:
            self.draining = False

    def blame(self, expression: sp.Expr, found: Dimension, wanted: Dimension, site: UseSite) -> None:
        named = isinstance(site.dimension, str) and DIMENSIONS.get(site.dimension) == wanted
        wanted_words = _words(site.dimension if named else wanted, unit=False)
        symbols = [s for s in expression.free_symbols if s.name in self.parameters]
        single = len(expression.free_symbols) == 1 and len(symbols) == 1 and (expression.is_Symbol or (expression.is_Mul and expression.as_coeff_Mul()[1].is_Symbol))
        if single:
            name = symbols[0].name
            parameter = self.parameters[name]
            if parameter.expression is not None:
                because = f"its expression {sp.sstr(parameter.expression)} is {_words(found)}"
            else:
                because = self.why.get(name, f"is {_words(found)}")
                because = ("but " if because.startswith(("has", "is computed")) else "and ") + because
                self.report(parameter.line, f"parameter {name}", f"used as {wanted_words} ({site.where}) {because}")
                return
            self.report(parameter.line, f"parameter {name}", f"used as {wanted_words} ({site.where}) but {because}")
            return
        self.report(site.line, site.item, f'{site.what} "{sp.sstr(expression)}" is {_words(found)}, expected {wanted_words}')

    def report(self, line: int | None, item: str, message: str) -> None:
        key = (item, message.split(" (")[0])
        if self.reporting and key not in self.seen:
            self.seen.add(key)
            self.problems.append(Problem(self.model.source, line, item, message))

    def definitions(self) -> None:
        """Derived parameters: their dimension from their expression, or backwards."""
        for name, parameter in self.parameters.items():
            if parameter.expression is None:
                continue
            try:
                found = self.dim(parameter.expression)
            except _MismatchError as mismatch:
                self.report(parameter.line, f"parameter {name}", f'"{sp.sstr(parameter.expression)}" {mismatch}')
                continue
            if isinstance(found, Dimension) and name not in self.dims:
                self.dims[name] = found
                self.why[name] = f"is {sp.sstr(parameter.expression)}"
            elif isinstance(found, Dimension) and self.dims[name] != found:
                because = self.why[name].removeprefix("is ")
                self.report(
                    parameter.line,
                    f"parameter {name}",
                    f"{because} but its expression {sp.sstr(parameter.expression)} is {_words(found)}",
                )
            elif found is None and name in self.dims:
                site = UseSite(parameter.expression, self.dims[name], f"parameter {name}", "", parameter.line)
                self.expect(parameter.expression, self.dims[name], site)

    def run(self, sites: list[UseSite]) -> None:
        for final in (False, True):
            self.reporting = final
            for _ in range(len(self.parameters) + 2 if not final else 1):
                before = len(self.dims)
                self.definitions()
                for site in sites:
                    wanted = DIMENSIONS[site.dimension] if isinstance(site.dimension, str) else site.dimension
                    self.expect(site.expression, wanted, site)
                if len(self.dims) == before and not final:
                    break


def infer_dimensions(model: Model) -> tuple[dict[str, Dimension], list[Problem]]:
    """The dimension of every parameter that can be settled, and every mismatch.

    Returns
    -------
    dims : dict of str to Dimension
        By parameter name; parameters used nowhere and without unit are missing.
    problems : list of Problem
        One per mismatch (a parameter reported once, at its first conflicting use).
    """
    if _LAST and _LAST[0] is model:  # a reader checks, then resolves, the same model
        dims, problems = _LAST[1]
        return dict(dims), list(problems)
    inference = _Inference(model)
    inference.run(list(use_sites(model)))
    _LAST[:] = [model, (dict(inference.dims), list(inference.problems))]
    return inference.dims, inference.problems


#: The last model inferred and its result: the records are frozen, so the same object has
#: the same dimensions (a 100-car train's inference takes 2.8 s and was run three times).
_LAST: list = []
