"""Writer of the classic model file (the paper's Fig. 5 layout).

The classic format numbers everything (``B1``, ``C1``, ``T1``, ``P1``, ``G1``), so
named items are renumbered in order; comment lines at the top give the renaming.
Positions and rail data have no place in the classic format and are left out.
"""

from __future__ import annotations

from typing import Any

from express.io.toml_writer import value_text
from express.model.records import DOF_NAMES, ElementKind, Model

__all__ = ["model_to_classic"]


def model_to_classic(model: Model) -> tuple[str, dict[str, str]]:
    """Classic-format text of ``model`` and the renaming of its bodies and grounds
    ``{old id: classic id}`` (CPs, elements and pins are renumbered too; see the header)."""
    special = [e.id for e in model.elements
               if e.rotational or e.kind is not ElementKind.PARALLEL or e.vector is not None or e.preload != 0]
    if special or model.gravity is not None:
        raise ValueError(
            f"{model.source}: the classic format has no rotational, series, clearance or line elements "
            f"and no gravity ({', '.join(special) or '[gravity]'}): keep the model in TOML"
        )
    kinds: tuple[tuple[str, tuple[Any, ...]], ...] = (
        ("B", model.bodies), ("G", model.grounds), ("C", model.points), ("T", model.elements), ("P", model.pins),
    )
    names = {prefix: {item.id: f"{prefix}{n}" for n, item in enumerate(items, start=1)} for prefix, items in kinds}
    hosts = {**names["B"], **names["G"]}
    lines = [f"# EXPRESS classic model: {model.name}", "# renaming of the named model:"]
    for prefix, _ in kinds:
        for old, new in names[prefix].items():
            if old != new:
                lines.append(f"#   {new} = {old}")
    renaming = dict(hosts)
    lines += ["", "(1) Body", "Number, Mass, Ix, Iy, Iz, tx, ty, tz, rx, ry, rz,"]
    for body in model.bodies:
        flags = ["1" if dof in body.dofs else "0" for dof in DOF_NAMES]
        fields = [names["B"][body.id], value_text(body.mass), *(value_text(v) for v in body.inertia), *flags]
        lines.append(",\t".join(fields) + ",")
    lines += ["", "(2) Ground", "Number,"]
    for ground in model.grounds:
        lines.append(f"{names['G'][ground.id]},")
    lines += ["", "(3) CP", "Number, on Body, x, y, z,"]
    for point in model.points:
        host = hosts.get(point.host, point.host)
        lines.append(",\t".join([names["C"][point.id], host, *(value_text(v) for v in point.offset)]) + ",")
    lines += ["", "(4) TSD", "Number, Stiffness, Damping, S_End, T_End, Direction,"]
    for element in model.elements:
        fields = [
            names["T"][element.id],
            value_text(element.stiffness),
            value_text(element.damping),
            names["C"][element.s_end],
            names["C"][element.t_end],
            str(element.direction + 1),
        ]
        lines.append(",\t".join(fields) + ",")
    lines += ["", "(5) Pinned Joint", "Number, Virtual, Non-Virtual,"]
    for pin in model.pins:
        lines.append(f"{names['P'][pin.id]},\t{names['C'][pin.virtual]},\t{names['C'][pin.non_virtual]},")
    return "\n".join(lines) + "\n", renaming
