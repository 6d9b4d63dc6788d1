"""Model records: bodies, grounds, connection points, elements, pinned joints.

These are what every reader produces and every later stage consumes.  Values are
exact SymPy expressions of parameter names; the parameters themselves (a value with
a unit, an expression of other parameters, or the output of a :class:`Derivation`)
travel alongside in :attr:`Model.parameters`, kept consistent by
:mod:`express.model.parameters` (the parameter graph).  :func:`express.model.checks.check_model` validates
the cross references and reports every problem at once.

Axes and names follow ``conventions.md``: x forward, y left, z up; DOFs
``x, y, z, rx, ry, rz``; a generalized coordinate is ``<body>.<dof>``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from enum import Enum, IntEnum

import sympy as sp

from express.base.units import Dimension
from express.model.characteristics import Characteristic
from express.model.derivation import Derivation
from express.model.modal_body import FlexibleBody

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
