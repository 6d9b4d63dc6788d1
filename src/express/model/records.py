"""Model records: bodies, grounds, connection points, elements, pinned joints.

These are what every reader produces and every later stage consumes.  Values are
exact SymPy expressions of parameter names; the parameters themselves (a value with
a unit, an expression of other parameters, or the output of a :class:`Derivation`)
travel alongside in :attr:`Model.parameters`, kept consistent by
:mod:`express.model.parameters` (the parameter graph).  :func:`check_model` validates the
cross references and reports every problem at once.

Axes and names follow ``conventions.md``: x forward, y left, z up; DOFs
``x, y, z, rx, ry, rz``; a generalized coordinate is ``<body>.<dof>``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from enum import Enum, IntEnum

import sympy as sp

from express.base.diagnostics import Problem
from express.base.expressions import expression_value
from express.base.units import Dimension
from express.model.characteristics import Characteristic
from express.model.derivation import Derivation
from express.model.load_reference import load_reference_problems
from express.model.modal_body import FlexibleBody, check_flexible

__all__ = [
    "AXES",
    "DOF_NAMES",
    "Axis",
    "Body",
    "ConnectionPoint",
    "Derivation",
    "Element",
    "ElementKind",
    "Ground",
    "Model",
    "Motion",
    "OutputPoint",
    "Parameter",
    "PinnedJoint",
    "RailSpec",
    "Wheelset",
    "check_model",
]

AXES = ("x", "y", "z")
DOF_NAMES = ("x", "y", "z", "rx", "ry", "rz")

Vector = tuple[sp.Expr, sp.Expr, sp.Expr]
ZERO3: Vector = (sp.S.Zero, sp.S.Zero, sp.S.Zero)
#: Standard gravity [m/s^2], the rail gravity of a model that names none.
STANDARD_GRAVITY = sp.Float(9.81)


@dataclass(frozen=True)
class Body:
    """A rigid body.

    Attributes
    ----------
    id : str
        Identifier (``B1``, ``car_body``).
    mass : sympy.Expr
        Mass [kg].
    inertia : tuple of 3 sympy.Expr
        Principal moments of inertia about x, y, z through the centre [kg m^2].
    dofs : tuple of str
        The DOFs the body has, a subset of :data:`DOF_NAMES` in that order.
    position : tuple of 3 sympy.Expr
        Centre in the vehicle frame [m]: station along the vehicle (x), lateral, height.
        Used by the rail modules (curvature terms); ignored by the core generator.
    label : str
        Human description.
    line : int or None
        Line in the source file.
    outline : tuple of 3 sympy.Expr or None
        Length, width and height [m] the body is drawn as (``express draw``); None:
        estimated from its mass and inertias (``docs/drawings-and-interfaces.md``).
    """

    id: str
    mass: sp.Expr
    inertia: Vector
    dofs: tuple[str, ...]
    position: Vector = ZERO3
    label: str = ""
    line: int | None = None
    outline: Vector | None = None

    def dof_names(self) -> list[str]:
        """Generalized-coordinate names ``<id>.<dof>`` of this body, in order."""
        return [f"{self.id}.{dof}" for dof in self.dofs]

    def dof_inertia(self, dof: str) -> sp.Expr:
        """Mass (translations) or moment of inertia (rotations) for ``dof``."""
        if dof in AXES:
            return self.mass
        return self.inertia[AXES.index(dof[1])]


@dataclass(frozen=True)
class Ground:
    """A ground: a surface that does not move unless driven as an input."""

    id: str
    label: str = ""
    line: int | None = None


@dataclass(frozen=True)
class ConnectionPoint:
    """A connection point (CP) at ``offset`` [m] from the centre of its host."""

    id: str
    host: str
    offset: Vector
    line: int | None = None


class Axis(IntEnum):
    """A direction of the vehicle's axes (0 = x along the track, 1 = y lateral, 2 = z up)."""

    X = 0
    Y = 1
    Z = 2


class Motion(Enum):
    """What an element's deflection measures: the relative translation of its ends along
    its axis, or the relative rotation of their bodies about it."""

    TRANSLATION = "translation"
    ROTATION = "rotation"


class ElementKind(Enum):
    """How an element's force follows its deflection."""

    #: Spring and damper side by side (Kelvin-Voigt): ``k delta + c delta'``.
    PARALLEL = "parallel"
    #: Spring and damper in series (Maxwell), with the damper stroke as a coordinate.
    SERIES = "series"
    #: A bump stop: ``k e + k3 e^3`` beyond the gap only (the nonlinear simulation).
    CLEARANCE = "clearance"
    #: Coulomb friction: a pre-slip spring in series with a slider that slips at the
    #: friction limit (the slider's position a state of the time march; the linear
    #: analyses see it stuck: the spring alone).
    FRICTION = "friction"
    #: A nonlinear characteristic, force against deflection or velocity (piecewise
    #: linear; the linear analyses see its tangent at the static state).
    CHARACTERISTIC = "characteristic"


@dataclass(frozen=True)
class Element:
    """A spring/damper element (TSD) between CPs ``s_end`` and ``t_end``.

    Its deflection is ``u_S[d] - u_T[d]`` along axis ``direction`` (0 = x, 1 = y, 2 = z);
    with ``motion`` :attr:`Motion.ROTATION` the relative rotation ``theta_S[d] - theta_T[d]``
    of its two ends' bodies about axis ``d`` (stiffness [N m/rad], damping [N m s/rad]).
    ``stiffness`` [N/m] and ``damping`` [N s/m] may be zero (not both, usefully).
    ``kind``: :class:`ElementKind` (``docs/model-format.md``).

    Attributes
    ----------
    id : str
        The element's name.
    stiffness, damping : sympy.Expr
        [N/m], [N s/m] (rotational: [N m/rad], [N m s/rad]).
    s_end, t_end : str
        The connection points at its S and T ends.
    direction : Axis
        The axis of the deflection (an int 0, 1, 2 is taken as the :class:`Axis`).
    label : str
        A free description.
    line : int or None
        Line in the source file.
    motion : Motion
        Translation (default) or rotation.
    kind : ElementKind
        Parallel (default), series or clearance.
    gap : sympy.Expr
        The clearance [m] (clearance elements only).
    progressive : sympy.Expr
        The cubic stiffness ``k3`` [N/m^3] beyond the gap (clearance elements only).
    friction : sympy.Expr
        The friction limit ``mu N`` [N; N m for a rotational one] of a friction element:
        its pre-slip spring (``stiffness``) carries at most this force, beyond it the
        slider slips; with ``friction_of`` (an element's id) the ``mu`` [-] (``mu r`` [m]) of its load.
    checked : tuple of (str, sympy.Expr, Dimension, bool)
        The values an element was derived from (an air spring's pressure, area, volumes:
        ``express.io.toml_air_springs``), each with what it is, its dimension and whether
        it must be positive; checked on reading with the element's line (the dimensions
        of a plain or series element that has any are checked through them, not through
        its derived stiffness and damping).
    characteristic : Characteristic or None
        A nonlinear characteristic (:mod:`express.model.characteristics`); its tangent
        at the static state is the element's ``stiffness`` (force against deflection) or
        ``damping`` (against velocity).
    vector, through_ends : tuple of 3 sympy.Expr or None, bool
        A line element's vector ``v`` [-] (given, or ``p_S - p_T`` [m] with ``through_ends``:
        ``direction = "line"``): deflection ``n . (u_S - u_T)``, ``n = v/|v|``
        (:mod:`express.assembly.lines`; ``direction`` then its first axis, for drawings).
    preload : sympy.Expr
        A given static tension [N] (besides ``[gravity]``'s): geometric stiffness only.
    """

    id: str
    stiffness: sp.Expr
    damping: sp.Expr
    s_end: str
    t_end: str
    direction: Axis
    label: str = ""
    line: int | None = None
    motion: Motion = Motion.TRANSLATION
    kind: ElementKind = ElementKind.PARALLEL
    gap: sp.Expr = sp.S.Zero
    progressive: sp.Expr = sp.S.Zero
    friction: sp.Expr = sp.S.Zero
    friction_of: str = ""
    friction_plane: str = ""  # the partner of a friction pair in a plane (express.forces.friction)
    checked: tuple[tuple[str, sp.Expr, Dimension, bool], ...] = ()
    characteristic: Characteristic | None = None
    vector: Vector | None = None
    through_ends: bool = False
    preload: sp.Expr = sp.S.Zero

    def __post_init__(self) -> None:
        object.__setattr__(self, "direction", Axis(self.direction))

    @property
    def rotational(self) -> bool:
        """The element acts on the relative rotation of its ends' bodies."""
        return self.motion is Motion.ROTATION

    @property
    def series(self) -> bool:
        """A series (Maxwell) element."""
        return self.kind is ElementKind.SERIES

    @property
    def clearance(self) -> bool:
        """A clearance element (bump stop)."""
        return self.kind is ElementKind.CLEARANCE

    @property
    def sliding(self) -> bool:
        """A friction element (a pre-slip spring and a slider)."""
        return self.kind is ElementKind.FRICTION

    @property
    def axis_name(self) -> str:
        """``x``, ``y``, ``z`` or, for a rotational element, ``rx``, ``ry``, ``rz``."""
        return ("r" if self.rotational else "") + AXES[self.direction]


@dataclass(frozen=True)
class PinnedJoint:
    """A pinned joint: the CP ``virtual`` moves with ``non_virtual`` along the joining
    element's direction; the virtual CP's body carries the virtual DOF."""

    id: str
    virtual: str
    non_virtual: str
    line: int | None = None


@dataclass(frozen=True)
class Parameter:
    """A parameter: a number with a unit (primary) or an expression of others (derived).

    Attributes
    ----------
    name : str
    value : float
        Current value in SI units (derived values are kept up to date by
        :mod:`express.model.parameters`; ``nan`` until a new model is evaluated).
    unit : str
        The unit the user wrote (``""`` for a bare SI number or a derived value).
    line : int or None
        Line in the source file.
    expression : sympy.Expr or None
        The definition of a derived parameter (``(mc + 2*mt + 4*mw)*g/8``); None for a
        primary one.
    derived_by : str or None
        The item of the :class:`Derivation` that sets it (``"rail.creep"``), if any.
    dimension : express.base.units.Dimension or None
        Its dimension: from its unit, its expression or where it is used; None if unknown.
    """

    name: str
    value: float
    unit: str = ""
    line: int | None = None
    expression: sp.Expr | None = None
    derived_by: str | None = None
    dimension: Dimension | None = None

    @property
    def is_primary(self) -> bool:
        """Whether the value is given (not an expression, not set by a derivation)."""
        return self.expression is None and self.derived_by is None


@dataclass(frozen=True)
class Wheelset:
    """Wheel/rail data of a body that is a wheelset (``rail.md``).

    All values are expressions of parameters: creep coefficients ``f1``, ``f2`` [N]
    per wheel, ``conicity`` [-], rolling radius ``r0`` [m], contact half distance
    ``b`` [m], ``flange_clearance`` [m], equivalent rail lateral stiffness
    ``rail_stiffness`` [N/m], ``friction`` coefficient [-], static ``wheel_load`` [N].
    """

    body: str
    f1: sp.Expr
    f2: sp.Expr
    conicity: sp.Expr
    r0: sp.Expr
    b: sp.Expr
    flange_clearance: sp.Expr
    rail_stiffness: sp.Expr
    friction: sp.Expr
    wheel_load: sp.Expr
    line: int | None = None


@dataclass(frozen=True)
class OutputPoint:
    """A named point on a body whose motion is reported (e.g. the floor above a bogie)."""

    name: str
    body: str
    offset: Vector
    line: int | None = None


@dataclass(frozen=True)
class RailSpec:
    """What makes a model a rail vehicle: wheelsets, speed, cant base, outputs."""

    wheelsets: tuple[Wheelset, ...]
    speed: sp.Expr
    cant_base: sp.Expr
    gravity: sp.Expr = STANDARD_GRAVITY
    outputs: tuple[OutputPoint, ...] = ()
    line: int | None = None


@dataclass(frozen=True)
class Model:
    """A whole model as read from a file."""

    name: str
    source: str
    bodies: tuple[Body, ...]
    grounds: tuple[Ground, ...]
    points: tuple[ConnectionPoint, ...]
    elements: tuple[Element, ...]
    pins: tuple[PinnedJoint, ...]
    parameters: dict[str, Parameter] = field(default_factory=dict)
    rail: RailSpec | None = None
    title: str = ""
    gravity: sp.Expr | None = None  # [gravity] acceleration: every body's weight (docs/model-format.md)
    derivations: tuple[Derivation, ...] = ()
    #: Flexible (modal) bodies: modes beside the rigid motion (:mod:`express.model.modal_body`).
    flexible: tuple[FlexibleBody, ...] = ()

    def __repr__(self) -> str:
        rail = f", {len(self.rail.wheelsets)} wheelsets" if self.rail is not None else ""
        derived = sum(1 for p in self.parameters.values() if not p.is_primary)
        return (
            f"<Model {self.name!r} from {self.source}: {len(self.bodies)} bodies, "
            f"{len(self.points)} CPs, {len(self.elements)} elements, {len(self.pins)} pins{rail}, "
            f"{len(self.parameters)} parameters ({derived} derived)>"
        )

    def body(self, body_id: str) -> Body:
        """The body with id ``body_id`` (KeyError if none)."""
        return self._by_id("bodies")[body_id]

    def point(self, point_id: str) -> ConnectionPoint:
        """The CP with id ``point_id`` (KeyError if none)."""
        return self._by_id("points")[point_id]

    def _by_id(self, what: str) -> dict:
        """Index of ``bodies`` or ``points`` by id (the first of a repeated id), built
        once: looking items up one by one made a 100-car train's generation quadratic."""
        key = f"_index_{what}"
        index = self.__dict__.get(key)
        if index is None:
            index = {}
            for item in getattr(self, what):
                index.setdefault(item.id, item)
            object.__setattr__(self, key, index)  # a cache, not a field: frozen stays frozen
        return index

    def values(self) -> dict[str, float]:
        """Parameter values in SI, by name."""
        return {name: parameter.value for name, parameter in self.parameters.items()}


def _duplicates(records, kind: str, source: str, problems: list[Problem]) -> None:
    seen: dict[str, int | None] = {}
    for record in records:
        if record.id in seen:
            first = seen[record.id]
            where = f" (first defined on line {first})" if first is not None else ""
            problems.append(Problem(source, record.line, f"{kind} {record.id}", f"duplicate id{where}"))
        else:
            seen[record.id] = record.line


def check_model(model: Model) -> list[Problem]:
    """Every error in the cross references of ``model`` (empty list if none).

    Checks duplicate ids, CPs on unknown bodies or grounds, elements on unknown CPs,
    pins naming unknown CPs or lacking their element, virtual CPs whose body lacks the
    translation along the pin direction, and rail data naming unknown bodies.
    """
    source = model.source
    problems: list[Problem] = []
    _duplicates(model.bodies, "body", source, problems)
    _duplicates(model.grounds, "ground", source, problems)
    _duplicates(model.points, "CP", source, problems)
    _duplicates(model.elements, "TSD", source, problems)
    _duplicates(model.pins, "pin", source, problems)
    body_ids = {body.id for body in model.bodies}
    ground_ids = {ground.id for ground in model.grounds}
    for clash in sorted(body_ids & ground_ids):
        problems.append(Problem(source, None, f"ground {clash}", "id is also used by a body"))
    hosts = {point.id: point.host for point in model.points}
    for point in model.points:
        if point.host not in body_ids and point.host not in ground_ids:
            problems.append(
                Problem(source, point.line, f"CP {point.id}", f'unknown body or ground "{point.host}"')
            )
    for element in model.elements:
        for end_name, end in (("S_End", element.s_end), ("T_End", element.t_end)):
            if end not in hosts:
                problems.append(
                    Problem(source, element.line, f"TSD {element.id}", f'{end_name} "{end}" is not a CP')
                )
        if element.s_end == element.t_end:
            problems.append(
                Problem(source, element.line, f"TSD {element.id}", "S_End and T_End are the same CP")
            )
    bodies = {body.id: body for body in model.bodies}
    _check_element_kinds(model, hosts, bodies, problems)
    _check_pins(model, hosts, bodies, ground_ids, problems)
    _check_rail_references(model, bodies, problems)
    if model.flexible:
        problems.extend(check_flexible(model))
    return problems


def _check_pins(model: Model, hosts: dict[str, str], bodies: dict[str, Body], ground_ids: set[str],
                problems: list[Problem]) -> None:
    """Pins: known CPs, exactly one joining element, a virtual CP on a body with the
    translation along the pin direction."""
    source = model.source
    by_ends: dict[frozenset, list[Element]] = {}
    for element in model.elements:
        by_ends.setdefault(frozenset((element.s_end, element.t_end)), []).append(element)
    for pin in model.pins:
        item = f"pin {pin.id}"
        known = True
        for role, cp in (("virtual", pin.virtual), ("non-virtual", pin.non_virtual)):
            if cp not in hosts:
                problems.append(Problem(source, pin.line, item, f'{role} CP "{cp}" is not a CP'))
                known = False
        if not known:
            continue
        joining = by_ends.get(frozenset((pin.virtual, pin.non_virtual)), [])
        if not joining:
            problems.append(
                Problem(
                    source,
                    pin.line,
                    item,
                    f"no element joins its CPs {pin.virtual} and {pin.non_virtual} "
                    "(the element gives the pin direction)",
                )
            )
            continue
        if len(joining) > 1:
            ids = ", ".join(element.id for element in joining)
            problems.append(Problem(source, pin.line, item, f"several elements join its CPs: {ids}"))
            continue
        virtual_host = hosts[pin.virtual]
        if virtual_host not in bodies and virtual_host not in ground_ids:
            continue  # the CP's unknown host is reported with the CP
        if virtual_host not in bodies:
            problems.append(
                Problem(source, pin.line, item, f"virtual CP {pin.virtual} is on ground {virtual_host}")
            )
            continue
        axis = AXES[joining[0].direction]
        if axis not in bodies[virtual_host].dofs:
            problems.append(
                Problem(
                    source,
                    pin.line,
                    item,
                    f"virtual CP {pin.virtual} is on body {virtual_host}, which has no "
                    f"{axis} translation DOF (the pin direction of element {joining[0].id})",
                )
            )


def _check_rail_references(model: Model, bodies: dict[str, Body], problems: list[Problem]) -> None:
    """Wheelsets and output points name known bodies; a wheelset has the y and rz DOFs
    and is listed once (its weight against its wheel load: :mod:`express.model.parameter_ranges`)."""
    source = model.source
    if model.rail is not None:
        listed: set[str] = set()
        for wheelset in model.rail.wheelsets:
            if wheelset.body in listed:
                problems.append(Problem(source, wheelset.line, f"wheelset {wheelset.body}", "listed twice"))
                continue
            listed.add(wheelset.body)
            if wheelset.body not in bodies:
                problems.append(
                    Problem(source, wheelset.line, f"wheelset {wheelset.body}", "unknown body")
                )
            elif not {"y", "rz"} <= set(bodies[wheelset.body].dofs):
                problems.append(
                    Problem(
                        source,
                        wheelset.line,
                        f"wheelset {wheelset.body}",
                        "a wheelset body needs the y and rz DOFs",
                    )
                )
        for output in model.rail.outputs:
            if output.body not in bodies:
                problems.append(
                    Problem(source, output.line, f"output {output.name}", f'unknown body "{output.body}"')
                )


def _numeric_value(expression, parameters: dict[str, Parameter]) -> float | None:
    """Value of a parameter expression, or None when a name has no value (yet)."""
    try:
        value = expression_value(expression, {name: p.value for name, p in parameters.items()})
    except (KeyError, ValueError):
        return None
    return value if math.isfinite(value) else None


def _check_element_kinds(model: Model, hosts: dict[str, str], bodies: dict[str, Body], problems: list[Problem]) -> None:
    """Rotational, series and clearance elements: ends, values, and no pins on them."""
    pinned = {frozenset((pin.virtual, pin.non_virtual)) for pin in model.pins}
    for element in model.elements:
        item = f"TSD {element.id}"
        if element.rotational:
            axes = [element.axis_name] if element.vector is None else [
                "r" + "xyz"[a] for a, c in enumerate(element.vector) if sp.sympify(c) != 0]
            for end_name, end in (("S_End", element.s_end), ("T_End", element.t_end)):
                body = bodies.get(hosts.get(end, ""))
                if body is None:
                    continue
                for axis in axes:
                    if axis not in body.dofs:
                        problems.append(Problem(
                            model.source, element.line, item,
                            f"rotational element about {axis}: its {end_name} {end} is on body "
                            f"{body.id}, which has no {axis} DOF",
                        ))
        if element.series:
            for what, value in (("stiffness", element.stiffness), ("damping", element.damping)):
                if sp.sympify(value) == 0:
                    problems.append(Problem(
                        model.source, element.line, item,
                        f"a series (Maxwell) element needs a nonzero {what}",
                    ))
        if element.sliding:
            problems += load_reference_problems(model, element)
            for what, value in (("pre-slip stiffness (stiffness)", element.stiffness),
                                ("friction coefficient mu" if element.friction_of else "friction limit", element.friction)):
                number = _numeric_value(value, model.parameters)
                if number is not None and not number > 0:
                    problems.append(Problem(model.source, element.line, item,
                                            f"a friction element needs a positive {what}, got {number:g}"))
        for what, value, _, positive in element.checked:
            number = _numeric_value(value, model.parameters)
            if positive and number is not None and not number > 0:
                problems.append(Problem(model.source, element.line, item, f"{what} must be positive, got {number:g}"))
        if element.clearance:
            gap = _numeric_value(element.gap, model.parameters)
            if gap is not None and not gap >= 0:
                problems.append(Problem(model.source, element.line, item, f"gap must be >= 0, got {gap:g}"))
        elif sp.sympify(element.progressive) != 0:
            problems.append(Problem(
                model.source, element.line, item, "progressive stiffness needs a gap (a clearance element)"
            ))
        if frozenset((element.s_end, element.t_end)) in pinned and (
            element.rotational or element.kind is not ElementKind.PARALLEL or element.vector is not None
        ):
            problems.append(Problem(
                model.source, element.line, item,
                "the element of a pinned joint must be a plain translational element along an axis",
            ))
