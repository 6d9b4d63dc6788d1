"""Gravity: static preloads from the 3-D static equilibrium and their geometric stiffness.

With ``[gravity] acceleration = "g"`` every body carries its weight ``m g`` (down, -z).
Three steps (``docs/model-format.md``, section Gravity):

1. **Static equilibrium of the full 3-D model.** Every body gets all six DOFs, whatever
   the dynamic model keeps; series elements (their dampers relax) and clearance
   elements (within their gaps) carry no static load; pins stay constraints; in a rail
   vehicle the rails carry each wheelset (its ``z`` and ``rx`` are held).  The static
   displacement solves ``K_s q_s = F`` exactly (SymPy, on the coordinates that move:
   found numerically at the model's values and at perturbed values, the result then
   checked on the whole system); a weight no element carries is refused.
2. **Preloads.** Each element's static force ``N = k delta_s`` (``delta_s`` its static
   deflection, S end relative to T end along its axis: negative in compression).
3. **Geometric stiffness.** The element's potential ``k/2 (delta_s + delta)^2`` with
   ``delta`` to second order gives ``K += N d2(delta)/dq2``:

   * a CP at offset ``r`` on a rotating body moves by ``theta x r + 1/2 theta x (theta
     x r)``: along axis ``a`` the second-order term has the Hessian
     ``H_ij = 1/2 (d_ia r_j + d_ja r_i) - r_a d_ij`` over the rotations (a body on
     springs below its centre: ``K_rx,rx = 2 k b^2 - m g h``);
   * an element whose ends are a distance ``L`` apart along its axis (from the bodies'
     positions plus the offsets) is a link whose line follows its ends: ``delta`` gains
     ``|du_perp|^2 / (2 L)`` (a pendulum of length ``L``: lateral stiffness ``m g / L``);
   * an element whose two ends coincide, between two bodies, acts along the axis of the
     body that carries it (its **support**, the lower of the two: an air spring along
     the bogie's, a primary spring along the wheelset's), which turns by ``theta_B``:
     ``delta`` gains ``(theta_B x e) . du`` (``e`` the axis, ``du`` the ends' relative
     motion, curvature inputs included).  The element's force then has one line of
     action on both bodies, as an internal force must: a car body shifted by ``d`` on
     its air springs puts the couple ``N d`` of its weight on the bogie and the wheels.
     An axis fixed in the track frame left that couple to the track, and a canted
     curve's wheel loads missed it (``docs/curving.md``, "Statics of a canted curve").

   Rotational elements, pins and the wheel/rail contact add no geometric stiffness here
   (the contact's gravitational stiffness belongs to the wheel/rail model).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import replace

import numpy as np
import sympy as sp

from express.assembly.equations import GenerationResult
from express.assembly.kinematics import point_motion
from express.assembly.lines import end_position, exact_norm, line_vector, squared_length
from express.base.diagnostics import ModelError, Problem
from express.model.records import AXES, DOF_NAMES, ElementKind, Model

__all__ = ["element_length", "gravity_stiffness", "gravity_terms", "static_model", "static_preloads"]

#: Relative size of the random perturbation of the parameters used to find which
#: coordinates move in the static equilibrium (structural zeros stay zero).
_PERTURBATION = 0.1


def static_model(model: Model) -> Model:
    """The 3-D static model: all DOFs, no series, clearance or friction elements (the
    characteristics as their tangents at the static state), wheelsets held, flexible
    bodies rigid (their modes' static deflection is left out of the preloads), no gravity
    (its equations, from :func:`express.assembly.generator.generate`, are the
    ``static_equations`` argument of :func:`static_preloads` and :func:`gravity_stiffness`)."""
    held = {w.body for w in model.rail.wheelsets} if model.rail is not None else set()
    bodies = tuple(
        replace(b, dofs=tuple(d for d in DOF_NAMES if not (b.id in held and d in ("z", "rx")))) for b in model.bodies
    )
    # a characteristic carries its static load as the linear analyses see it: its tangent
    elements = tuple(replace(e, kind=ElementKind.PARALLEL, characteristic=None) if e.kind is ElementKind.CHARACTERISTIC
                     else e for e in model.elements if e.kind in (ElementKind.PARALLEL, ElementKind.CHARACTERISTIC))
    # a given preload adds geometric stiffness only: the static solve is linear
    elements = tuple(replace(e, preload=sp.S.Zero) if e.preload != 0 else e for e in elements)
    # flexible bodies statically rigid: the preloads of the rigid bodies (docs/model-format.md)
    return replace(model, bodies=bodies, elements=elements, gravity=None, rail=None, flexible=())


def _number_function(symbols: list[sp.Symbol], expressions):
    return sp.lambdify(symbols, list(expressions), modules="math")


def static_preloads(model: Model, static_equations: GenerationResult) -> dict[str, sp.Expr]:
    """Static force ``N = k delta_s`` [N or N m] of every loaded element under gravity.

    Parameters
    ----------
    model : Model
        The model with its ``[gravity]``.
    static_equations : GenerationResult
        The equations of :func:`static_model` of ``model`` (``generate(static_model(model))``;
        the generator passes them, so that this module does not call it back).

    Returns
    -------
    dict of str to sympy.Expr
        Element id -> exact preload (elements without load omitted).

    Raises
    ------
    ModelError
        When no element carries a body's weight (naming the bodies), or when a value
        is missing.
    """
    gravity = sp.sympify(model.gravity)
    result = static_equations
    static = static_model(model)
    eom, t = result.equations, result.transformation
    full = list(result.full_dofs)
    n = len(eom.dofs)
    load_full = sp.zeros(len(full), 1)
    for body in static.bodies:
        if f"{body.id}.z" in full:  # a held wheelset's weight goes straight to the rails
            load_full[full.index(f"{body.id}.z"), 0] = -body.mass * gravity
    load = (t.T * load_full).applyfunc(sp.expand)
    stiffness = eom.K
    symbols = sorted(stiffness.free_symbols | load.free_symbols, key=lambda s: s.name)
    values = model.values()
    missing = [s.name for s in symbols if s.name not in values]
    if missing:
        raise ModelError([Problem(model.source, None, "gravity", f"no value for {', '.join(missing)}")])
    numbers = _number_function(symbols, list(stiffness) + list(load))
    rng = np.random.default_rng(0)
    points = [np.array([values[s.name] for s in symbols], dtype=float)]
    points.append(points[0] * (1.0 + _PERTURBATION * rng.uniform(-1.0, 1.0, len(symbols))))
    moving: set[int] = set()
    for point in points:
        flat = np.array(numbers(*point), dtype=float)
        k_num, f_num = flat[: n * n].reshape(n, n), flat[n * n :]
        q = _solve_numeric(model, static, eom.dofs, k_num, f_num)
        scale = np.max(np.abs(q)) if q.size else 0.0
        moving |= {i for i in range(n) if abs(q[i]) > 1e-9 * scale}
    active = _independent(sorted(moving), np.array(numbers(*points[0]), dtype=float)[: n * n].reshape(n, n))
    q_static = sp.zeros(n, 1)
    if active:
        k_aa = stiffness.extract(active, active)
        f_a = load.extract(active, [0])
        solution = _exact_solve(k_aa, f_a)
        for index, value in zip(active, solution, strict=True):
            q_static[index, 0] = value
    _check_solution(model, numbers, points, stiffness, load, q_static, symbols, n)
    displacement = (t * q_static).applyfunc(sp.cancel)  # full static coordinates
    by_dof = {dof: displacement[i, 0] for i, dof in enumerate(full) if displacement[i, 0] != 0}
    preloads = {}
    for element in static.elements:
        if element.rotational:
            continue
        weights = [(sp.S.One, element.direction)] if element.vector is None else [
            (sp.sympify(c), axis) for axis, c in enumerate(line_vector(static, element)) if c != 0]
        deflection = sum(
            (weight * sign * value * by_dof[dof]
             for weight, axis in weights
             for end, sign in ((element.s_end, 1), (element.t_end, -1))
             for dof, value in point_motion(static, end, axis)[0].items()
             if dof in by_dof),
            sp.S.Zero,
        )
        if element.vector is None:
            force = sp.factor(sp.cancel(sp.sympify(element.stiffness) * deflection))
        else:  # N = mu |v|, mu = k v.du / (v.v) (express.assembly.lines)
            vector = line_vector(static, element)
            force = sp.factor(sp.cancel(sp.sympify(element.stiffness) * deflection / squared_length(vector)))
            force = force * sp.sqrt(squared_length(vector))
        if force != 0:
            preloads[element.id] = force
    pinned = {frozenset((p.virtual, p.non_virtual)) for p in model.pins}
    return {e: f for e, f in preloads.items() if frozenset(_ends(static, e)) not in pinned}


def _ends(model: Model, element_id: str) -> tuple[str, str]:
    element = next(e for e in model.elements if e.id == element_id)
    return element.s_end, element.t_end


def _solve_numeric(model: Model, static: Model, dofs, k_num: np.ndarray, f_num: np.ndarray) -> np.ndarray:
    """Least-squares static solution; refuses a load in the null space of K."""
    if not f_num.size:
        return np.zeros(0)
    q, *_ = np.linalg.lstsq(k_num, f_num, rcond=None)
    residual = np.linalg.norm(k_num @ q - f_num)
    if residual <= 1e-8 * max(float(np.linalg.norm(f_num)), 1e-300):
        return q
    # which weights are not carried: a body's own load with a part in the null space of K
    _, singular, vt = np.linalg.svd(k_num)
    null = vt[singular <= 1e-10 * singular.max()] if singular.size else vt
    unsupported = sorted({
        dofs[i].split(".")[0] for i in np.flatnonzero(f_num)
        if np.linalg.norm(null[:, i]) > 1e-6  # e_i (this body's weight) is not in the range of K
    })
    lines = {body.id: body.line for body in model.bodies}
    raise ModelError([
        Problem(model.source, lines.get(name), f"body {name}",
                "gravity: no element carries its weight in the full 3-D model (add an element along z, "
                "or leave out [gravity])")
        for name in unsupported or ["?"]
    ])


def _independent(indices: list[int], k_num: np.ndarray) -> list[int]:
    """A subset of ``indices`` whose block of K is invertible (column pivoting)."""
    if not indices:
        return []
    import scipy.linalg

    block = k_num[np.ix_(indices, indices)]
    _, r, pivots = scipy.linalg.qr(block, pivoting=True)
    diagonal = np.abs(np.diag(r))
    rank = int(np.sum(diagonal > 1e-10 * diagonal.max())) if diagonal.size else 0
    return sorted(indices[p] for p in pivots[:rank])


def _exact_solve(matrix: sp.Matrix, rhs: sp.Matrix) -> list[sp.Expr]:
    """Exact solution of a small nonsingular system over the rational functions."""
    from sympy.polys.matrices import DomainMatrix

    a, b = DomainMatrix.from_Matrix(sp.Matrix(matrix)).unify(DomainMatrix.from_Matrix(sp.Matrix(rhs)))
    x = a.to_field().lu_solve(b.to_field())
    return [sp.cancel(value) for value in x.to_Matrix()]


def _check_solution(model, numbers, points, stiffness, load, q_static, symbols, n) -> None:
    """The exact solution must solve the whole static system at both parameter points."""
    function = _number_function(symbols, list(q_static))
    for point in points:
        flat = np.array(numbers(*point), dtype=float)
        k_num, f_num = flat[: n * n].reshape(n, n), flat[n * n :]
        q = np.array(function(*point), dtype=float)
        if np.linalg.norm(k_num @ q - f_num) > 1e-7 * max(float(np.linalg.norm(f_num)), 1e-300):
            raise ModelError([Problem(model.source, None, "gravity",
                                      "the static equilibrium could not be solved exactly (internal check failed)")])


def element_length(model: Model, element) -> sp.Expr:
    """Signed distance ``L = (p_S - p_T)[axis]`` [m] between an element's ends along its
    axis: body position plus CP offset (a ground CP's offset is its position)."""
    bodies = {b.id: b for b in model.bodies}

    def position(point_id: str) -> sp.Expr:
        point = model.point(point_id)
        body = bodies.get(point.host)
        base = body.position[element.direction] if body is not None else 0
        return sp.sympify(base) + sp.sympify(point.offset[element.direction])

    return sp.expand(position(element.s_end) - position(element.t_end))


def _rotation_hessian(model: Model, point_id: str, axis: int) -> list[tuple[str, str, sp.Expr]]:
    """Second derivatives of a CP's displacement along ``axis`` over its body's
    rotations (``1/2 theta x (theta x r)``), as (dof, dof, value) for every pair."""
    point = model.point(point_id)
    try:
        body = model.body(point.host)
    except KeyError:
        return []
    r = [sp.sympify(v) for v in point.offset]
    entries = []
    for i in range(3):
        for j in range(3):
            value = sp.Rational(1, 2) * (int(i == axis) * r[j] + int(j == axis) * r[i]) - r[axis] * int(i == j)
            di, dj = f"r{AXES[i]}", f"r{AXES[j]}"
            if value != 0 and di in body.dofs and dj in body.dofs:
                entries.append((f"{body.id}.{di}", f"{body.id}.{dj}", value))
    return entries


def gravity_stiffness(model: Model, static_equations: GenerationResult) -> list[tuple[str, str, sp.Expr]]:
    """Geometric stiffness of the preloaded elements: ``(row DOF, column DOF, value)``
    in the model's full coordinates (before pin elimination), to be added to K
    (:func:`gravity_terms` without curvature inputs)."""
    return gravity_terms(model, static_equations)[0]


def gravity_terms(model: Model, static_equations: GenerationResult | None,
                  point_inputs: Mapping[tuple[str, int], Mapping[str, sp.Expr]] | None = None,
                  preloads: Mapping[str, sp.Expr] | None = None,
                  ) -> tuple[list[tuple[str, str, sp.Expr]], list[tuple[str, str, sp.Expr]]]:
    """Geometric stiffness of the preloaded elements and its part over the inputs.

    Parameters
    ----------
    model : Model
        The model with its ``[gravity]``.
    static_equations : GenerationResult or None
        The equations of :func:`static_model` of ``model`` (see :func:`static_preloads`);
        None for a model without ``[gravity]`` (its elements' given ``preload`` only).
    point_inputs : mapping, optional
        ``(cp_id, axis) -> {input: coefficient}``, the CPs' motion driven by inputs (the
        curvature terms of :func:`express.rail.curve.curvature_point_inputs`).
    preloads : mapping, optional
        :func:`static_preloads` of the model, when the caller has them.

    Returns
    -------
    stiffness : list of (str, str, sympy.Expr)
        ``(row DOF, column DOF, value)`` in the model's full coordinates (before pin
        elimination), to be added to K [N/m, N, N m/rad].
    forces : list of (str, str, sympy.Expr)
        ``(DOF, input, coefficient)`` to be added to P: the turning axes of coincident
        elements (module docstring) over the inputs' motion of their ends.
    """
    if preloads is None:
        preloads = (static_preloads(model, static_equations)
                    if model.gravity is not None and static_equations is not None else {})
    terms: list[tuple[str, str, sp.Expr]] = []
    forces: list[tuple[str, str, sp.Expr]] = []
    for element in model.elements:
        if element.vector is not None and not element.rotational:
            terms += _line_terms(model, element, preloads.get(element.id))
            continue
        force = preloads.get(element.id)
        if element.preload != 0 and not element.rotational:  # a given tension besides gravity's
            force = sp.sympify(element.preload) + (force if force is not None else 0)
        if force is None:
            continue
        for end, sign in ((element.s_end, 1), (element.t_end, -1)):
            for row, column, value in _rotation_hessian(model, end, element.direction):
                terms.append((row, column, sign * force * value))
        length = element_length(model, element)
        if length != 0:
            for axis in range(3):
                if axis == element.direction:
                    continue
                relative = _relative_motion(model, element, axis, {})[0]
                for row, a in relative.items():
                    for column, b in relative.items():
                        if a != 0 and b != 0:
                            terms.append((row, column, force * a * b / length))
        elif _between_bodies(model, element) and _coincident(model, element):
            stiffness, driven = _turning_axis(model, element, force, point_inputs or {})
            terms += stiffness
            forces += driven
    return terms, forces


def _line_terms(model: Model, element, gravity_force: sp.Expr | None) -> list[tuple[str, str, sp.Expr]]:
    """Geometric stiffness of a line element carrying the tension ``N`` (gravity's and its
    given ``preload``): ``N n . d2(u_S - u_T)/dq2`` over its ends' rotations and
    ``N/L (I - n n^T)`` over their relative motion, ``L = n . (p_S - p_T)``; written with
    ``mu = N/|v|`` (:mod:`express.assembly.lines`). A line whose ends coincide adds the
    rotation terms only."""
    vector = [sp.sympify(c) for c in line_vector(model, element)]
    mu = sp.S.Zero
    if gravity_force is not None:
        mu += sp.cancel(gravity_force / sp.sqrt(squared_length(vector)))
    if element.preload != 0:
        norm = exact_norm(vector, model.values())
        if norm is None:
            raise ModelError([Problem(model.source, element.line, f"TSD {element.id}",
                                      f"the length of its direction {tuple(vector)} is not a rational function of "
                                      "the parameters (a square root): its given preload cannot enter the exact K "
                                      "(give a direction of rational length, e.g. [3, 0, 4])")])
        mu += sp.sympify(element.preload) / norm
    if mu == 0:
        return []
    terms: list[tuple[str, str, sp.Expr]] = []
    pull = [mu * c for c in vector]  # N n
    for end, sign in ((element.s_end, 1), (element.t_end, -1)):
        for row, column, value in _vector_hessian(model, end, pull):
            terms.append((row, column, sign * value))
    start, finish = end_position(model, element.s_end), end_position(model, element.t_end)
    projected = sp.expand(sum((c * (a - b) for c, a, b in zip(vector, start, finish, strict=True)), sp.S.Zero))
    if projected == 0:
        return terms
    squared = squared_length(vector)
    relative = [_relative_motion(model, element, axis, {})[0] for axis in range(3)]
    for b in range(3):
        for c in range(3):
            weight = sp.cancel(mu * (squared * int(b == c) - vector[b] * vector[c]) / projected)
            if weight == 0:
                continue
            for row, x in relative[b].items():
                for column, y in relative[c].items():
                    if x != 0 and y != 0:
                        terms.append((row, column, weight * x * y))
    return terms


def _vector_hessian(model: Model, point_id: str, pull) -> list[tuple[str, str, sp.Expr]]:
    """``w . d2u/dq2`` of a CP over its body's rotations (``u = theta x r + 1/2 theta x
    (theta x r)``): ``1/2 (w_i r_j + w_j r_i) - (w . r) delta_ij``, ``w`` a force [N]."""
    point = model.point(point_id)
    try:
        body = model.body(point.host)
    except KeyError:
        return []
    r = [sp.sympify(v) for v in point.offset]
    along = sum((w * x for w, x in zip(pull, r, strict=True)), sp.S.Zero)
    entries = []
    for i in range(3):
        for j in range(3):
            value = sp.Rational(1, 2) * (pull[i] * r[j] + pull[j] * r[i]) - along * int(i == j)
            di, dj = f"r{AXES[i]}", f"r{AXES[j]}"
            if value != 0 and di in body.dofs and dj in body.dofs:
                entries.append((f"{body.id}.{di}", f"{body.id}.{dj}", value))
    return entries


def _relative_motion(model: Model, element, axis: int,
                     point_inputs: Mapping[tuple[str, int], Mapping[str, sp.Expr]]
                     ) -> tuple[dict[str, sp.Expr], dict[str, sp.Expr]]:
    """First-order motion of the S end relative to the T end along ``axis``: over the
    coordinates and over the inputs (ground inputs and ``point_inputs``)."""
    dofs: dict[str, sp.Expr] = {}
    inputs: dict[str, sp.Expr] = {}
    for end, sign in ((element.s_end, 1), (element.t_end, -1)):
        moved, driven = point_motion(model, end, axis)
        for target, part in ((dofs, moved), (inputs, driven), (inputs, point_inputs.get((end, axis), {}))):
            for name, value in part.items():
                target[name] = target.get(name, 0) + sign * value
    return dofs, inputs


def _between_bodies(model: Model, element) -> bool:
    bodies = {body.id for body in model.bodies}
    return all(model.point(end).host in bodies for end in (element.s_end, element.t_end))


def _coincident(model: Model, element) -> bool:
    """Whether the element's two ends are the same point (body position plus offset)."""
    def position(point_id: str) -> list[sp.Expr]:
        point = model.point(point_id)
        body = model.body(point.host)
        return [sp.sympify(body.position[i]) + sp.sympify(point.offset[i]) for i in range(3)]

    start, end = position(element.s_end), position(element.t_end)
    return all(sp.expand(a - b) == 0 for a, b in zip(start, end, strict=True))


def _support(model: Model, element) -> str:
    """The body that carries a coincident element: the lower of its two bodies (their
    positions' height at the model's values), the T end's on a tie."""
    values = model.values()
    hosts = [model.point(end).host for end in (element.s_end, element.t_end)]
    heights = [float(sp.sympify(model.body(host).position[2]).subs(values)) for host in hosts]
    return hosts[0] if heights[0] < heights[1] else hosts[1]


def _turning_axis(model: Model, element, force: sp.Expr,
                  point_inputs: Mapping[tuple[str, int], Mapping[str, sp.Expr]]
                  ) -> tuple[list[tuple[str, str, sp.Expr]], list[tuple[str, str, sp.Expr]]]:
    """K and P terms of ``N (theta_B x e) . du``: the axis ``e`` of a coincident element
    turning with its support ``B`` (:func:`_support`, module docstring).

    ``(theta_B x e) . du = sum_i theta_B,i eps(i, a, k) du_k`` (``a`` the element's axis,
    ``k`` the third axis); the potential ``N eps theta_B,i du_k`` is bilinear, so K gains
    ``N eps`` on (rotation, relative motion) both ways and P gains ``-N eps`` times the
    inputs' part of ``du_k``.  A rotation the support does not have adds nothing (a
    lateral-only model's wheelsets under their primary springs)."""
    axis = element.direction
    support = model.body(_support(model, element))
    stiffness: list[tuple[str, str, sp.Expr]] = []
    driven: list[tuple[str, str, sp.Expr]] = []
    for i in range(3):
        if i == axis or f"r{AXES[i]}" not in support.dofs:
            continue
        rotation = f"{support.id}.r{AXES[i]}"
        k = 3 - i - axis
        scale = force * (1 if (i, axis, k) in ((0, 1, 2), (1, 2, 0), (2, 0, 1)) else -1)
        moved, inputs = _relative_motion(model, element, k, point_inputs)
        for dof, b in moved.items():
            if b != 0:
                stiffness += [(rotation, dof, scale * b), (dof, rotation, scale * b)]
        driven += [(rotation, name, -scale * b) for name, b in inputs.items() if b != 0]
    return stiffness, driven
