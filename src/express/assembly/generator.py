"""The generator: model -> exact symbolic M, C, K, P, Pd with pinned joints eliminated.

Paper sections 2.1 and 2.2 in 3-D.  Each element's deflection is a linear form
``delta = g . q + h . u`` (``g`` over the generalized coordinates, ``h`` over the
inputs); the element adds ``k g g^T`` to K, ``c g g^T`` to C and ``-k g h^T``,
``-c g h^T`` to the input matrices P and Pd (eq. 3 and its dissipative twin).

Pinned joints are eliminated exactly by ``q = T q_r`` (``M_r = T^T M T``, likewise C,
K, P, Pd), applied per element to ``g`` before assembly: ``K_r = sum k (T^T g)(T^T g)^T``.
The virtual element's ``T^T g`` is the pin constraint itself, hence exactly zero, so
the virtual stiffness never enters the result (:mod:`express.assembly.pins`).

Rail modules add their own terms through :class:`AddedTerms` (full coordinates,
before elimination); the generator treats them like everything else.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Any

import sympy as sp

from express.assembly.algebra import ExactDomain, inverted_symbols
from express.assembly.equations import (
    STROKE,
    ClearanceTerm,
    ElementTerm,
    EquationsOfMotion,
    GenerationResult,
    Matrices,
    derivation_steps,
)
from express.assembly.friction_loads import load_values, static_loads
from express.assembly.gravity import gravity_terms, static_model, static_preloads
from express.assembly.kinematics import end_motion, generalized_coordinates
from express.assembly.lines import line_problems, line_vector, scale, unit_term
from express.assembly.pins import NeedsFractionsError, pin_elements, reduced_coordinates
from express.base.diagnostics import ModelError, Problem
from express.model.characteristics import characteristic_values
from express.model.checks import check_model
from express.model.modal_body import modal_expressions, modal_terms
from express.model.parameters import display_unit
from express.model.records import DOF_NAMES, Model

__all__ = [
    "SPARSE_BELOW",
    "AddedTerms",
    "GenerationResult",
    "element_deflections",
    "equation_values",
    "generate",
    "symbolic_matrix",
]


@dataclass(frozen=True)
class AddedTerms:
    """Terms added by the rail modules, in full coordinates (before pin elimination).

    Attributes
    ----------
    inputs : tuple of str
        Input names, in order, appended after the ground inputs.
    point_inputs : dict
        ``(cp_id, axis) -> {input: coefficient}``: extra motion of a CP driven by an
        input (the curvature terms of ``rail.md``); enters every element on the CP.
        ``axis`` 0-2 are its displacements, 3-5 its rotations about x, y, z.
    stiffness, damping : list of (str, str, sympy.Expr)
        ``(row DOF, column DOF, value)`` added to K or C (need not be symmetric).
    forces, rate_forces : list of (str, str, sympy.Expr)
        ``(DOF, input, coefficient)`` added to P or Pd.
    loads : dict of str to sympy.Expr
        The static force of each element a friction limit follows (:mod:`express.assembly.friction_loads`).
    """

    inputs: tuple[str, ...] = ()
    point_inputs: dict[tuple[str, int], dict[str, sp.Expr]] = field(default_factory=dict)
    stiffness: list[tuple[str, str, sp.Expr]] = field(default_factory=list)
    damping: list[tuple[str, str, sp.Expr]] = field(default_factory=list)
    forces: list[tuple[str, str, sp.Expr]] = field(default_factory=list)
    rate_forces: list[tuple[str, str, sp.Expr]] = field(default_factory=list)
    loads: dict[str, sp.Expr] = field(default_factory=dict)

    def expressions(self):
        """Every coefficient, for collecting the parameter symbols."""
        for terms in self.point_inputs.values():
            yield from terms.values()
        for group in (self.stiffness, self.damping, self.forces, self.rate_forces):
            for *_, value in group:
                yield value


def _model_expressions(model: Model, added: AddedTerms):
    for body in model.bodies:
        yield body.mass
        yield from body.inertia
    for point in model.points:
        yield from point.offset
    for element in model.elements:
        yield element.stiffness
        yield element.damping
        if element.vector is not None:  # a line element: k v v^T / (v . v) (express.assembly.lines)
            yield scale(model, element)
    yield from modal_expressions(model)
    yield from added.expressions()


def generate(
    model: Model, *, keep_virtual: bool = False, added: AddedTerms | None = None, readable: bool = True
) -> GenerationResult:
    """Generate the exact symbolic equations of motion of ``model``.

    Parameters
    ----------
    model : Model
        The model (validated again here).
    keep_virtual : bool
        Keep the virtual DOFs and the virtual elements (the paper's eq. 6).
    added : AddedTerms, optional
        Terms from the rail modules. Without them the equations of a model with rail data
        have no wheel/rail or curve terms (no creep forces, no gravitational stiffness of
        the contact: ``K[W1.rz, W1.y] = 0``) and the result says so
        (:attr:`GenerationResult.omitted`); :func:`express.rail.build.generate_vehicle`
        (``express.generate_vehicle``, what ``express generate`` runs) adds them.
    readable : bool
        Factor every entry for people to read (``b**2*(kLL + kLU)``); ``False`` gives
        the same values expanded (``b**2*kLL + b**2*kLU``), which is all a numerical
        command needs and saves the factoring (about half of the generation of a
        3-D car).

    Returns
    -------
    GenerationResult

    Raises
    ------
    ModelError
        For an invalid model or a singular set of pin constraints.

    Examples
    --------
    >>> from express.io.classic import read_classic
    >>> eom = generate(read_classic("examples/lever.exp")).equations
    >>> eom.dofs, eom.eliminated
    (('B1.rz', 'B2.ry'), ('B2.x',))
    >>> eom.K[0, 0]
    b**2*(kLL + kLU)
    """
    problems = check_model(model)
    problems = problems or line_problems(model)  # once the ends are known CPs
    if problems:
        raise ModelError(problems)
    omitted = (RAIL_OMITTED,) if added is None and getattr(model, "rail", None) is not None else ()
    result = _generate_with(model, keep_virtual, added or AddedTerms(), readable)
    return replace(result, omitted=omitted) if omitted else result


#: What :func:`generate` says it left out of a model with rail data given no ``added`` terms.
RAIL_OMITTED = "the wheel/rail and curve terms (the model has rail data; express.generate_vehicle adds them)"


def _generate_with(model: Model, keep_virtual: bool, added: AddedTerms, readable: bool) -> GenerationResult:
    """:func:`generate` of a checked model with its ``added`` terms."""
    if model.gravity is not None or any(e.preload != 0 for e in model.elements):  # preloads' geometric stiffness
        # the 3-D static model has no gravity (and no given preloads)
        static_equations = generate(static_model(model)) if model.gravity is not None else None
        preloads = static_preloads(model, static_equations) if static_equations is not None else {}
        stiffness, forces = gravity_terms(model, static_equations, added.point_inputs, preloads=preloads)
        added = replace(added, stiffness=list(added.stiffness) + stiffness, forces=list(added.forces) + forces,
                        loads=static_loads(model, preloads))
    domain, fallback = _domains(model, added)
    try:
        return _generate(model, keep_virtual, added, domain, readable)
    except NeedsFractionsError:
        return _generate(model, keep_virtual, added, fallback, readable)


def _domains(model: Model, added: AddedTerms) -> tuple[ExactDomain, ExactDomain]:
    """The arithmetic domain of ``model``'s expressions, and the one with fractions that a
    singular set of pins without them needs (:class:`NeedsFractionsError`)."""
    expressions = list(_model_expressions(model, added))
    symbols = set().union(*(sp.sympify(e).free_symbols for e in expressions)) if expressions else set()
    inverses = inverted_symbols(expressions)
    shapes = {value for flexible in getattr(model, "flexible", ()) for mode in flexible.modes
              for _, value in mode.shapes if isinstance(value, sp.Symbol)}  # factored apart (algebra.ExactDomain)
    return ExactDomain(symbols, inverses is None, inverses or (), shapes), ExactDomain(symbols, True)


def element_deflections(model: Model, added: AddedTerms | None = None) -> tuple[ElementTerm, ...]:
    """Every element's true deflection ``delta = gradient . q + inputs . u`` [m; rad] over
    the reduced coordinates, as :func:`generate` assembles it (a line element's along
    its unit vector, a series element's spring ``delta - s``), with its ``stiffness``
    and ``damping`` values; the pins' joining elements (whose force is a reaction) are
    left out.  What :mod:`express.export.element_forces` makes the elements' forces of.

    Parameters
    ----------
    model : Model
        A checked model (:func:`generate` has accepted it).
    added : AddedTerms, optional
        The rail modules' terms; only their ``point_inputs`` move the elements' ends.
    """
    added = added or AddedTerms()
    domain, fallback = _domains(model, added)
    try:
        return _element_deflections(model, added, domain)
    except NeedsFractionsError:
        return _element_deflections(model, added, fallback)


def _element_deflections(model: Model, added: AddedTerms, domain: ExactDomain) -> tuple[ElementTerm, ...]:
    full_dofs = generalized_coordinates(model) + [f"{e.id}.{STROKE}" for e in model.elements if e.series]
    pin_element_ids = {element.id for _, element in pin_elements(model)}
    deflections = _deflections(model, added, domain, pin_element_ids)
    reduced, _, t_rows = reduced_coordinates(model, domain, full_dofs, deflections.gradients, False)
    r_index = {dof: i for i, dof in enumerate(reduced)}
    in_index = {name: i for i, name in enumerate(deflections.inputs)}
    terms = []
    for element in model.elements:
        if element.id in pin_element_ids:
            continue
        g: dict[int, Any] = {}
        for dof, value in deflections.gradients[element.id].items():
            for j, t in t_rows[dof].items():
                g[j] = g.get(j, domain.zero) + value * t
        if element.series:
            stroke = r_index[f"{element.id}.{STROKE}"]
            g[stroke] = g.get(stroke, domain.zero) - domain.one
        h = {in_index[u]: v for u, v in deflections.input_gradients[element.id].items()}
        values = {"stiffness": element.stiffness, "damping": element.damping}
        terms.append(unit_term(model, element, _element_term(element, {j: v for j, v in g.items() if v}, h, reduced,
                                                             deflections.inputs, domain.to_expr, values)))
    return tuple(terms)


def _add_outer(target, left, right, scale) -> None:
    for i, a in left.items():
        factor = a * scale
        for j, b in right.items():
            target[(i, j)] = target.get((i, j), 0) + factor * b


@dataclass
class _Deflections:
    """Every element's deflection as linear forms: ``gradients[element][dof]`` and
    ``input_gradients[element][input]`` (exact domain values), and the input order."""

    gradients: dict[str, dict[str, Any]]
    input_gradients: dict[str, dict[str, Any]]
    inputs: list[str]


def _deflections(model: Model, added: AddedTerms, domain: ExactDomain, pin_element_ids: set[str]) -> _Deflections:
    conv = domain.from_expr
    ground_inputs: list[str] = []
    gradients: dict[str, dict[str, Any]] = {}
    input_gradients: dict[str, dict[str, Any]] = {}
    motion_cache: dict[tuple[str, int, bool], tuple[dict, dict]] = {}

    def motion(point_id: str, axis: int, rotational: bool = False):
        key = (point_id, axis, rotational)
        if key not in motion_cache:
            dofs, inputs = end_motion(model, point_id, axis, rotational)
            inputs = dict(inputs)
            for name, value in added.point_inputs.get((point_id, axis + 3 * rotational), {}).items():
                inputs[name] = inputs.get(name, 0) + value
            motion_cache[key] = (
                {d: conv(v) for d, v in dofs.items()},
                {u: conv(v) for u, v in inputs.items()},
            )
        return motion_cache[key]

    for element in model.elements:
        parts: list[tuple[Any, int]]
        if element.vector is None:
            parts = [(domain.one, int(element.direction))]
        else:  # a line element: v . (u_S - u_T), unnormalised (express.assembly.lines)
            parts = [(conv(c), axis) for axis, c in enumerate(line_vector(model, element)) if c != 0]
        g: dict[str, Any] = {}
        h: dict[str, Any] = {}
        for weight, axis in parts:
            for end, sign in ((element.s_end, weight), (element.t_end, -weight)):
                dofs, inputs = motion(end, axis, element.rotational)
                for dof, value in dofs.items():
                    g[dof] = g.get(dof, domain.zero) + sign * value
                for name, value in inputs.items():
                    h[name] = h.get(name, domain.zero) + sign * value
        gradients[element.id] = {d: v for d, v in g.items() if v}
        if element.id in pin_element_ids:
            h = {}  # a pin to a ground holds the virtual DOF to a static ground
        input_gradients[element.id] = {u: v for u, v in h.items() if v}
        for name in input_gradients[element.id]:
            if name not in ground_inputs and name not in added.inputs:
                ground_inputs.append(name)

    ground_order = {f"{g.id}.{axis}": (i, a) for i, g in enumerate(model.grounds) for a, axis in enumerate(DOF_NAMES)}
    ground_inputs.sort(key=lambda name: ground_order[name])
    inputs = ground_inputs + [name for name in added.inputs if name not in ground_inputs]
    return _Deflections(gradients, input_gradients, inputs)


@dataclass
class _Assembly:
    """Entries of the reduced matrices keyed by (row, column), and the clearances."""

    stiffness: dict[tuple[int, int], Any] = field(default_factory=dict)
    damping: dict[tuple[int, int], Any] = field(default_factory=dict)
    forcing: dict[tuple[int, int], Any] = field(default_factory=dict)
    forcing_rate: dict[tuple[int, int], Any] = field(default_factory=dict)
    mass: dict[tuple[int, int], Any] = field(default_factory=dict)
    clearances: list = field(default_factory=list)
    element_terms: list = field(default_factory=list)


def _assemble(model: Model, added: AddedTerms, domain: ExactDomain, deflections: _Deflections, reduced: list[str],
              t_rows: dict[str, dict[int, Any]], skip: set[str]) -> _Assembly:
    """Element, inertia and rail terms in the reduced coordinates (elements in ``skip``,
    the pins' joining elements, contribute nothing after elimination)."""
    conv = domain.from_expr
    r_index = {dof: i for i, dof in enumerate(reduced)}
    in_index = {name: i for i, name in enumerate(deflections.inputs)}

    def reduce(vector: dict[str, Any]) -> dict[int, Any]:
        result: dict[int, Any] = {}
        for dof, value in vector.items():
            for j, t in t_rows[dof].items():
                result[j] = result.get(j, domain.zero) + value * t
        return {j: v for j, v in result.items() if v}

    parts = _Assembly()
    for element in model.elements:
        if element.id in skip:
            continue  # its reduced gradient is the pin constraint: exactly zero
        g = reduce(deflections.gradients[element.id])
        h = {in_index[u]: v for u, v in deflections.input_gradients[element.id].items()}
        k, c = conv(element.stiffness), conv(element.damping)
        if element.vector is not None:  # over v . du: k v v^T / (v . v) = k n n^T
            factor = conv(scale(model, element))
            k, c = k * factor, c * factor
        if element.clearance:
            parts.clearances.append(unit_term(model, element, _clearance(element, g, h, reduced, deflections.inputs,
                                                                      domain.readable)))
            continue
        if element.sliding:  # in the matrices stuck (its pre-slip spring), below; slips in the time domain
            parts.element_terms.append(unit_term(model, element, _element_term(
                element, g, h, reduced, deflections.inputs, domain.readable,
                {"stiffness": element.stiffness, "friction": element.friction,
                 **_load_values(model, element, added, deflections, reduce, reduced, domain.readable)})))
        if element.characteristic is not None:  # in the matrices its tangent (stiffness or damping), below
            parts.element_terms.append(unit_term(model, element, _element_term(
                element, g, h, reduced, deflections.inputs, domain.readable,
                characteristic_values(element.characteristic))))
        if element.series:
            # spring deflection delta - s, damper stroke s (docs/model-format.md)
            stroke = r_index[f"{element.id}.{STROKE}"]
            g[stroke] = g.get(stroke, domain.zero) - domain.one
            _add_outer(parts.stiffness, g, g, k)
            _add_outer(parts.forcing, g, h, -k)
            _add_outer(parts.damping, {stroke: domain.one}, {stroke: domain.one}, c)
            continue
        if not g:
            continue
        if k:
            _add_outer(parts.stiffness, g, g, k)
            _add_outer(parts.forcing, g, h, -k)
        if c:
            _add_outer(parts.damping, g, g, c)
            _add_outer(parts.forcing_rate, g, h, -c)
    for body in model.bodies:
        for dof in body.dofs:
            inertia = conv(body.dof_inertia(dof))
            if inertia:
                row = t_rows[f"{body.id}.{dof}"]
                _add_outer(parts.mass, row, row, inertia)
    for dof, mass, damping, stiffness in modal_terms(model):  # mass-normalised modes
        row = t_rows[dof]
        for target, value in ((parts.mass, mass), (parts.damping, damping), (parts.stiffness, stiffness)):
            if value != 0:
                _add_outer(target, row, row, conv(value))
    for target, terms in ((parts.stiffness, added.stiffness), (parts.damping, added.damping)):
        for row_dof, column_dof, value in terms:
            _add_outer(target, t_rows[row_dof], t_rows[column_dof], conv(value))
    for target, terms in ((parts.forcing, added.forces), (parts.forcing_rate, added.rate_forces)):
        for dof, name, value in terms:
            _add_outer(target, t_rows[dof], {in_index[name]: domain.one}, conv(value))
    return parts


def _generation_warnings(model: Model, reduced: list[str], mass_matrix, clearances) -> list[Problem]:
    """One warning for the clearances left out of the linear matrices, one per massless DOF."""
    warnings = []
    by_id = {body.id: body for body in model.bodies}
    if clearances:
        names = ", ".join(term.element for term in clearances)
        first = next(e for e in model.elements if e.clearance)
        warnings.append(
            Problem(
                model.source,
                first.line,
                f"TSD {names}",
                "clearance elements (bump stops) are left out of the linear matrices "
                "(eigenvalues, critical speed, FRF); only the simulation uses them",
            )
        )
    for i, dof in enumerate(reduced):
        if mass_matrix[i, i] == 0 and dof.split(".")[0] in by_id:
            body = by_id[dof.split(".")[0]]
            warnings.append(
                Problem(
                    model.source,
                    body.line,
                    f"body {body.id}",
                    f"DOF {dof} has zero mass or inertia: M is singular and must not be inverted",
                )
            )
    return warnings


def _generate(model: Model, keep_virtual: bool, added: AddedTerms, domain: ExactDomain, readable: bool) -> GenerationResult:
    # series elements add their damper stroke, a massless first-order coordinate
    full_dofs = generalized_coordinates(model) + [f"{e.id}.{STROKE}" for e in model.elements if e.series]
    pin_element_ids = {element.id for _, element in pin_elements(model)}
    deflections = _deflections(model, added, domain, pin_element_ids)
    inputs = deflections.inputs
    reduced, virtual, t_rows = reduced_coordinates(model, domain, full_dofs, deflections.gradients, keep_virtual)
    parts = _assemble(model, added, domain, deflections, reduced, t_rows, set() if keep_virtual else pin_element_ids)
    n, m = len(reduced), len(inputs)
    form = domain.readable if readable else domain.to_expr

    def build(entries: dict[tuple[int, int], Any], columns: int) -> sp.MatrixBase:
        return symbolic_matrix(n, columns, {key: form(value) for key, value in entries.items() if value})

    matrices = {"M": build(parts.mass, n), "C": build(parts.damping, n), "K": build(parts.stiffness, n)}
    if inputs:
        matrices["P"] = build(parts.forcing, m)
        matrices["Pd"] = build(parts.forcing_rate, m)
    symbols = set()
    for matrix in matrices.values():
        symbols |= matrix.free_symbols
    parameters = tuple(sorted(s.name for s in symbols))
    values, units = equation_values(model, parameters)
    equations = EquationsOfMotion(
        name=model.name,
        dofs=tuple(reduced),
        eliminated=tuple(virtual),
        inputs=tuple(inputs),
        matrices=Matrices.of(matrices),
        parameters=parameters,
        values=values,
        units=units,
        clearances=tuple(parts.clearances),
        element_terms=tuple(parts.element_terms),
        derivation=derivation_steps(model),
    )
    warnings = _generation_warnings(model, reduced, matrices["M"], parts.clearances)
    t_matrix = symbolic_matrix(
        len(full_dofs),
        n,
        {(i, j): form(value) for i, dof in enumerate(full_dofs) for j, value in t_rows[dof].items() if value},
    )
    return GenerationResult(equations, tuple(warnings), t_matrix, tuple(full_dofs))


def equation_values(model: Model, parameters: tuple[str, ...]) -> tuple[dict[str, float], dict[str, str]]:
    """``(values, units)`` of :class:`EquationsOfMotion`: every parameter's SI value and
    the unit it was written in (or the SI unit of a derived parameter's dimension),
    without the parameters only the virtual elements use (they vanish from the result)."""
    pin_element_ids = {element.id for _, element in pin_elements(model)}
    virtual_only = {
        symbol.name
        for element in model.elements
        if element.id in pin_element_ids
        for symbol in (sp.sympify(element.stiffness).free_symbols | sp.sympify(element.damping).free_symbols)
    } - set(parameters)
    values = {name: p.value for name, p in sorted(model.parameters.items()) if name not in virtual_only}
    units = {
        name: display_unit(p) for name, p in sorted(model.parameters.items()) if display_unit(p) and name not in virtual_only
    }
    return values, units


#: A matrix with fewer non-zeros than this share of its entries is built sparse.
SPARSE_BELOW = 1 / 16


def symbolic_matrix(rows: int, columns: int, entries: dict[tuple[int, int], sp.Expr]) -> sp.MatrixBase:
    """An immutable SymPy matrix of the non-zero ``entries``, built at the cost of the
    smaller of its two forms: sparse (``ImmutableSparseMatrix``, about 80 us per
    non-zero: SymPy sorts them) when fewer than :data:`SPARSE_BELOW` of the entries
    are non-zero, as in a train's matrices (> 99 % zeros), dense (about 5 us per entry)
    otherwise, as in a single car's.  Both print, compare and index alike."""
    if len(entries) < SPARSE_BELOW * rows * columns:
        return sp.ImmutableSparseMatrix(rows, columns, dict(sorted(entries.items())))
    flat = [sp.S.Zero] * (rows * columns)
    for (i, j), value in entries.items():
        flat[i * columns + j] = value
    return sp.ImmutableMatrix(rows, columns, flat)


def _clearance(element, gradient: dict, inputs_gradient: dict, dofs: list[str], inputs: list[str], form) -> ClearanceTerm:
    """The record of a clearance element, its deflection in reduced coordinates
    (``form``: the domain's ``readable``; a clearance has a few short entries)."""
    return ClearanceTerm(
        element=element.id,
        gradient={dofs[i]: form(v) for i, v in sorted(gradient.items())},
        inputs={inputs[j]: form(v) for j, v in sorted(inputs_gradient.items())},
        gap=sp.sympify(element.gap),
        stiffness=sp.sympify(element.stiffness),
        progressive=sp.sympify(element.progressive),
    )


def _load_values(model: Model, element, added: AddedTerms, deflections: _Deflections, reduce, reduced: list[str],
                 form) -> dict:
    """The ``load_*`` values of a friction element whose limit follows another element's load."""
    if not element.friction_of:
        return {}
    gradient = {reduced[j]: v for j, v in reduce(deflections.gradients[element.friction_of]).items()}
    loads = added.loads or static_loads(model, {})  # no [gravity]: the given preloads alone
    return load_values(model, element, gradient, deflections.input_gradients[element.friction_of], loads, form)


def _element_term(element, gradient: dict, inputs_gradient: dict, dofs: list[str], inputs: list[str], form,
                  values: dict) -> ElementTerm:
    """The record of a nonlinear element for the time domain (:class:`ElementTerm`)."""
    return ElementTerm(
        element=element.id,
        kind=element.kind.value,
        gradient={dofs[i]: form(v) for i, v in sorted(gradient.items())},
        inputs={inputs[j]: form(v) for j, v in sorted(inputs_gradient.items())},
        values={name: sp.sympify(value) for name, value in values.items()},
    )

