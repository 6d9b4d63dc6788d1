"""Flexible (modal) bodies: free-free modes carried beside a body's rigid motion.

A flexible body keeps its rigid DOFs and adds one coordinate per mode, ``<body>.<mode>``
(``CB.vb1``).  Modes are **mass-normalised** (modal mass 1): mode ``i`` adds ``1`` to
``M``, ``omega_i**2`` to ``K`` and ``2*zeta_i*omega_i`` to ``C`` on its own coordinate
(``omega_i`` [rad/s] and ``zeta_i`` [-] are parameters, so a sensitivity to a bending
frequency is exact like any other).  A point ``P`` of the body (a CP or an output point)
moves with the rigid motion plus ``sum_i phi_i(P) q_i``:

* a **vertical** bending mode moves it along z by ``phi_i(P)`` [1/sqrt(kg)] per unit
  ``q_i`` [sqrt(kg) m];
* a **lateral** bending mode along y by ``phi_i(P)``;
* a **torsion** mode turns the section at ``P`` about x by ``psi_i(P)``
  [rad/(sqrt(kg) m)]: ``u_y = -psi lz``, ``u_z = psi ly`` (``ly``, ``lz`` the point's
  offset from the body centre, the torsion axis), and a rotational element about x at
  ``P`` sees ``psi_i(P) q_i``.

Left out (``docs/model-format.md``, "Flexible bodies"): the slopes of the bending modes
(a point off the neutral axis does not move along x with the bending, a rotational
element about y or z on a bending body is refused), the modes' gravity stiffness, and
any coupling of the modes with the rigid motion through the mass (free-free modes are
orthogonal to the rigid ones: ``tests/test_modal_body.py``).

This module holds the records and everything the assembly asks of them; the sources of
modes are :mod:`express.model.beam_modes` (an analytic beam) and the readers
(:mod:`express.io.toml_modal`).
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from dataclasses import dataclass
from enum import Enum
from typing import TYPE_CHECKING

from express.base.diagnostics import Problem

if TYPE_CHECKING:  # SymPy is imported where expressions are made: the warm analyses use
    import sympy as sp  # the mode names without it (docs/cache.md)

__all__ = [
    "MODAL_UNIT",
    "FlexibleBody",
    "FlexibleMode",
    "ModeKind",
    "check_flexible",
    "coordinate_unit",
    "flexible_body",
    "modal_coordinates",
    "modal_expressions",
    "modal_motion",
    "modal_rotation",
    "modal_terms",
    "mode_words",
]


class ModeKind(Enum):
    """What a mode does to the body: bending in z (vertical) or y (lateral), or torsion."""

    VERTICAL = "vertical"
    LATERAL = "lateral"
    TORSION = "torsion"

    @property
    def words(self) -> str:
        """``"vertical bending"``, ``"lateral bending"``, ``"torsion"``."""
        return "torsion" if self is ModeKind.TORSION else f"{self.value} bending"


@dataclass(frozen=True)
class FlexibleMode:
    """One mass-normalised free-free mode of a body.

    Attributes
    ----------
    name : str
        The mode's coordinate suffix (``vb1``); the DOF is ``<body>.<name>``.
    kind : ModeKind
        Vertical or lateral bending, or torsion.
    omega : sympy.Expr
        Natural angular frequency [rad/s] (a parameter).
    zeta : sympy.Expr
        Modal damping ratio [-] (a parameter or a number).
    shapes : tuple of (str, sympy.Expr)
        Mass-normalised shape value at each point (CP id or output name): a displacement
        [1/sqrt(kg)] for bending, a rotation [rad/(sqrt(kg) m)] for torsion.
    order : int
        1 for the first mode of its kind, 2 for the second... (for the mode names).
    line : int or None
        Line in the source file.
    source : str or None
        The file that gives the mode (a modal data file), None for the model file.
    """

    name: str
    kind: ModeKind
    omega: sp.Expr
    zeta: sp.Expr
    shapes: tuple[tuple[str, sp.Expr], ...]
    order: int = 1
    line: int | None = None
    source: str | None = None  # the file that gives it, when not the model file

    def shape(self, point: str) -> sp.Expr | None:
        """The shape value at ``point`` (None if the mode does not give one)."""
        for name, value in self.shapes:
            if name == point:
                return value
        return None


@dataclass(frozen=True)
class FlexibleBody:
    """The modes of a body (``body`` names a :class:`~express.model.records.Body`).

    ``source`` says where the modes come from (``"modes"``, ``"beam"``, a data file name).
    """

    body: str
    modes: tuple[FlexibleMode, ...]
    source: str = "modes"
    line: int | None = None

    def coordinates(self) -> list[str]:
        """The modal coordinates ``<body>.<mode>``, in mode order."""
        return [f"{self.body}.{mode.name}" for mode in self.modes]


#: SI unit of a mass-normalised modal coordinate: ``q'^2 / 2`` is a kinetic energy [J], so
#: ``q`` is in sqrt(kg) m (tables and CSV columns).
MODAL_UNIT = "kg^0.5*m"
_RIGID_UNITS = {"x": "m", "y": "m", "z": "m", "rx": "rad", "ry": "rad", "rz": "rad", "stroke": "m"}


def coordinate_unit(dof: str) -> str:
    """SI unit of a coordinate ``<body>.<direction>``: ``m`` for a translation and a series
    element's stroke, ``rad`` for a rotation, :data:`MODAL_UNIT` for a flexible body's mode.

    >>> coordinate_unit("CB.y"), coordinate_unit("CB.rz"), coordinate_unit("CB.vb1")
    ('m', 'rad', 'kg^0.5*m')
    """
    return _RIGID_UNITS.get(dof.rsplit(".", 1)[-1], MODAL_UNIT)


_ORDINALS = ("first", "second", "third", "fourth", "fifth", "sixth", "seventh", "eighth", "ninth", "tenth")
_PREFIXES = {"vb": ModeKind.VERTICAL, "lb": ModeKind.LATERAL, "to": ModeKind.TORSION}


def mode_words(name: str) -> str:
    """Words for a mode named by the convention ``vb<n>``, ``lb<n>``, ``to<n>`` (vertical,
    lateral bending, torsion; the beam's names), else the name itself.

    >>> mode_words("vb1"), mode_words("to2"), mode_words("lb12"), mode_words("m7")
    ('first vertical bending', 'second torsion', 'lateral bending 12', 'm7')
    """
    kind = _PREFIXES.get(name[:2])
    if kind is None or not name[2:].isdigit() or int(name[2:]) < 1:
        return name
    order = int(name[2:])
    return f"{_ORDINALS[order - 1]} {kind.words}" if order <= len(_ORDINALS) else f"{kind.words} {order}"


def flexible_body(model, body_id: str) -> FlexibleBody | None:
    """The :class:`FlexibleBody` of ``body_id`` in ``model`` (None for a rigid body)."""
    for flexible in getattr(model, "flexible", ()):
        if flexible.body == body_id:
            return flexible
    return None


def modal_coordinates(model, body_id: str) -> list[str]:
    """The modal coordinates of ``body_id`` (empty for a rigid body)."""
    flexible = flexible_body(model, body_id)
    return flexible.coordinates() if flexible is not None else []


def modal_motion(model, body_id: str, point: str, offset, axis: int) -> dict[str, sp.Expr]:
    """Displacement along ``axis`` (0, 1, 2) of ``point`` (offset ``(lx, ly, lz)`` [m])
    due to the modes of ``body_id``: ``{modal coordinate: coefficient}``.

    Examples
    --------
    >>> import sympy as sp
    >>> from types import SimpleNamespace
    >>> mode = FlexibleMode("t1", ModeKind.TORSION, sp.Symbol("w"), 0, (("C1", sp.Symbol("p")),))
    >>> model = SimpleNamespace(flexible=(FlexibleBody("CB", (mode,)),))
    >>> modal_motion(model, "CB", "C1", (0, 1, 2), 1), modal_motion(model, "CB", "C1", (0, 1, 2), 2)
    ({'CB.t1': -2*p}, {'CB.t1': p})
    """
    flexible = flexible_body(model, body_id)
    terms: dict[str, sp.Expr] = {}
    if flexible is None or axis == 0:
        return terms
    for mode in flexible.modes:
        value = mode.shape(point)
        if value is None:
            continue  # check_flexible reports a used point without a shape
        if mode.kind is ModeKind.TORSION:
            coefficient = -value * offset[2] if axis == 1 else value * offset[1]
        elif (mode.kind is ModeKind.VERTICAL) == (axis == 2):
            coefficient = value
        else:
            continue
        if coefficient != 0:
            terms[f"{body_id}.{mode.name}"] = coefficient
    return terms


def modal_rotation(model, body_id: str, point: str, axis: int) -> dict[str, sp.Expr]:
    """Rotation about ``axis`` of the section at ``point`` due to the torsion modes (the
    bending slopes are left out: :func:`check_flexible` refuses what would need them)."""
    flexible = flexible_body(model, body_id)
    if flexible is None or axis != 0:
        return {}
    terms = {}
    for mode in flexible.modes:
        value = mode.shape(point)
        if mode.kind is ModeKind.TORSION and value is not None and value != 0:
            terms[f"{body_id}.{mode.name}"] = value
    return terms


def modal_terms(model) -> Iterator[tuple[str, sp.Expr, sp.Expr, sp.Expr]]:
    """``(coordinate, mass, damping, stiffness)`` of every mode: ``1``, ``2 zeta omega``,
    ``omega**2`` (mass-normalised modes)."""
    import sympy as sp

    for flexible in getattr(model, "flexible", ()):
        for mode in flexible.modes:
            omega, zeta = sp.sympify(mode.omega), sp.sympify(mode.zeta)
            yield f"{flexible.body}.{mode.name}", sp.S.One, sp.expand(2 * zeta * omega), omega**2


def modal_expressions(model) -> Iterator[sp.Expr]:
    """Every expression of the modes (for collecting the parameter symbols)."""
    import sympy as sp

    for flexible in getattr(model, "flexible", ()):
        for mode in flexible.modes:
            yield sp.sympify(mode.omega)
            yield sp.sympify(mode.zeta)
            for _, value in mode.shapes:
                yield sp.sympify(value)


def _value(expression, model) -> float | None:
    from express.base.expressions import expression_value

    try:
        value = expression_value(expression, {name: p.value for name, p in model.parameters.items()})
    except (KeyError, ValueError):
        return None
    return value if math.isfinite(value) else None


def check_flexible(model) -> list[Problem]:
    """Every problem of the flexible bodies of ``model``.

    A flexible body must be a body of the model; mode names are identifiers, unique,
    and not rigid DOF names; ``omega > 0`` and ``zeta >= 0``; every CP of the body that
    an element uses and every output point on it has a shape in every mode (the reader
    refuses a shape at a point that is neither); no rotational element about y (z) sits on a body with
    vertical (lateral) bending modes (their slopes are not modelled).
    """
    problems: list[Problem] = []
    source = model.source
    bodies = {body.id: body for body in model.bodies}
    used = {end for element in model.elements for end in (element.s_end, element.t_end)}
    seen: set[str] = set()
    for flexible in getattr(model, "flexible", ()):
        item = f"flexible {flexible.body}"
        if flexible.body not in bodies:
            problems.append(Problem(source, flexible.line, item, f'unknown body "{flexible.body}"'))
            continue
        if flexible.body in seen:
            problems.append(Problem(source, flexible.line, item, "given twice"))
        seen.add(flexible.body)
        body = bodies[flexible.body]
        points = [p.id for p in model.points if p.host == body.id]
        needed = [p for p in points if p in used]
        outputs = [o.name for o in model.rail.outputs if o.body == body.id] if model.rail is not None else []
        names: set[str] = set()
        for mode in flexible.modes:
            where = f"{item} mode {mode.name}"
            origin = mode.source or source
            if mode.name in names or mode.name in ("x", "y", "z", "rx", "ry", "rz", "stroke"):
                problems.append(Problem(origin, mode.line, where, "mode name repeated or a rigid DOF's name"))
            names.add(mode.name)
            omega, zeta = _value(mode.omega, model), _value(mode.zeta, model)
            if omega is not None and not omega > 0:
                problems.append(Problem(origin, mode.line, where,
                                        f"frequency must be positive, got {omega / (2 * math.pi):g} Hz"))
            if zeta is not None and not zeta >= 0:
                problems.append(Problem(origin, mode.line, where, f"damping ratio must be >= 0, got {zeta:g}"))
            given = {name for name, _ in mode.shapes}
            missing = [p for p in needed + outputs if p not in given]
            if missing:
                problems.append(Problem(origin, mode.line, where,
                                        f"no mode shape at {', '.join(missing)} (used by the model)"))
        # a vertical bending mode turns the sections about y, a lateral one about z
        turning = {1: ModeKind.VERTICAL, 2: ModeKind.LATERAL}
        kinds = {mode.kind for mode in flexible.modes}
        for element in model.elements:
            if element.rotational and turning.get(int(element.direction)) in kinds and (
                    element.s_end in points or element.t_end in points):
                problems.append(Problem(
                    source, element.line, f"TSD {element.id}",
                    f"a rotational element about {element.axis_name} on body {body.id}, whose "
                    f"{turning[int(element.direction)].words} modes turn it: the bending slopes are not "
                    "modelled (use translational elements, or leave those modes out)",
                ))
    return problems
