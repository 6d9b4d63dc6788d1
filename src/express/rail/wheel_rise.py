"""How each wheel sits on its rail along the contact tables: the look-ups the compiled
force kernel shares (the yaw node, the contact's place on the rail) and the wheels' rise
on their rails, which presses the vertical contact springs of a 3-D model
(:func:`contact_rise`; ``docs/contact.md``, "Dynamic wheel loads").
"""

from __future__ import annotations

import math

import numpy as np

from express.base.kernels import kernel
from express.rail.contact_tables import ANGLE, ARM, RADIUS, ROLL, YAW_STEP, ContactTables

__all__ = ["contact_rise", "rail_position", "rise_tables", "yaw_node"]


@kernel
def yaw_node(psi, count):
    """Yaw node ``k`` below ``|psi|`` and the weight ``t`` of node ``k + 1``, linear in
    ``psi^2`` (constant beyond the last of ``count`` nodes)."""
    if count < 2:
        return 0, 0.0
    k = min(int(abs(psi) / YAW_STEP), count - 2)
    low, high = (k * YAW_STEP) ** 2, ((k + 1) * YAW_STEP) ** 2
    return k, min((psi * psi - low) / (high - low), 1.0)


@kernel
def rail_position(maps, j, start, step, count, node, weight, y, side):
    """``u`` of ``side`` of wheelset ``j`` at ``y`` from the rail maps ``maps``
    (:attr:`~express.rail.contact_forces.ContactSet.rail_maps`; clamped; yaw nodes
    ``node``, ``node + 1`` with ``weight``) and the overshoot."""
    last = start + step * (count - 1)
    clamped = min(max(y, start), last)
    f = (clamped - start) / step
    k = min(max(math.floor(f), 0), count - 2)
    t = f - k
    u = (1.0 - t) * maps[j, node, side, k] + t * maps[j, node, side, k + 1]
    if weight > 0.0:
        u += weight * ((1.0 - t) * maps[j, node + 1, side, k] + t * maps[j, node + 1, side, k + 1] - u)
    return u, y - clamped


def rise_tables(tables: np.ndarray, sources: list[ContactTables]) -> tuple[np.ndarray, np.ndarray]:
    """The ``rise`` and ``lever`` of a :class:`~express.rail.contact_forces.ContactSet` for each
    wheelset, yaw node and side of the kernel layout ``tables`` (n, yaw nodes, 2, rows,
    fields) of the wheelsets' ``sources``.

    Along the tables the wheelset sits on both rails at its geometric roll ``phi_g(u)``
    (field ``roll``); its centre rises by ``dz_g = sigma (tan(delta) du - lever dphi_g)``
    on either side, ``lever = l - d tan(delta)`` with ``d = r - sigma l phi_g`` the
    contact's depth below the centre in the track plane (sums of trapezoids; in each step
    the side whose contact angle changes less, so that a contact jump on one side is
    stepped over on the other).  The rise of a side is ``z_g + sigma lever phi_g``, from
    the centred wheelset: the interpenetration of the wheel on the path is then constant,
    and off it changes by ``-(z - z_g) - sigma lever (phi - phi_g)`` (:func:`contact_rise`).
    """
    sigma = np.array([1.0, -1.0])[None, :, None]
    slope = np.tan(tables[..., ANGLE])
    lever = tables[..., ARM] - (tables[..., RADIUS] - sigma[None] * tables[..., ARM] * tables[..., ROLL]) * slope
    rise = np.zeros(tables.shape[:4])
    for j, source in enumerate(sources):
        rows, step = source.data.shape[2], source.step
        tangent, roll, arm = slope[j, :, :, :rows], tables[j, :, :, :rows, ROLL], lever[j, :, :, :rows]
        climb = sigma * (0.5 * step * (tangent[..., 1:] + tangent[..., :-1])
                         - 0.5 * (arm[..., 1:] + arm[..., :-1]) * np.diff(roll))
        smooth = np.argmin(np.abs(np.diff(tangent)), axis=1)[:, None, :]
        steps = np.take_along_axis(climb, smooth, axis=1)[:, 0, :]
        centre = np.concatenate([np.zeros(steps.shape[:1] + (1,)), np.cumsum(steps, axis=-1)], axis=-1)
        side = centre[:, None, :] + sigma * arm * roll
        grid = source.start + step * np.arange(rows)
        for node in range(side.shape[0]):
            for s in range(2):
                side[node, s] -= np.interp(0.0, grid, side[node, s])
        rise[j, :, :, :rows] = side
    return rise, np.ascontiguousarray(lever)


@kernel
def _along(field, j, node, weight, side, k, t):
    value = field[j, node, side, k] + t * (field[j, node, side, k + 1] - field[j, node, side, k])
    if weight > 0.0:
        value += weight * (field[j, node + 1, side, k] + t * (field[j, node + 1, side, k + 1] - field[j, node + 1, side, k])
                           - value)
    return value


@kernel
def contact_rise(contacts, j, y, psi, out):
    """How wheelset ``j``'s wheels at displacement ``y`` [m] from the track and yaw
    ``psi`` [rad] sit on their rails, into ``out`` (2, 2): per side (left, right) the
    rise ``h = z_g + sigma lever phi_g`` [m] of :func:`_rise_tables` and the lever
    ``l - d tan(delta)`` [m] of the wheel's load about the wheelset centre (where the
    contact normal meets the axle, ``d`` the contact's depth below the centre).

    A wheel moved across its rail by ``du`` must rise by ``sigma tan(delta) du`` (the slope
    of the common tangent plane in the track plane); rolled by ``dphi`` its contact point
    moves across by ``r dphi`` and up by ``sigma l dphi``.  So a wheelset at ``z``,
    ``phi`` presses its wheel into the rail by ``z_g - z - sigma lever (phi - phi_g)``
    more than on the geometric path (``z_g``, ``phi_g``), to first order in the distance
    from it: ``h - z - sigma lever phi``.  With ``Q`` proportional to it, the rails'
    lateral force ``-sigma Q tan(delta)``, vertical force ``Q`` and roll moment
    ``sigma lever Q`` are its gradient, up to terms in ``phi - phi_g``: the contact's
    normal forces are conservative.  Interpolated at the contact's place ``u`` on the
    rail (the rail maps), constant beyond the tables.
    """
    node, weight = yaw_node(psi, contacts.yaw_count[j])
    start, step, count = contacts.table_start[j], contacts.table_step[j], contacts.table_count[j]
    last = start + step * (count - 1)
    for side in range(2):
        u, _ = rail_position(contacts.rail_maps, j, contacts.map_start[j], contacts.map_step[j], contacts.map_count[j],
                             node, weight, y, side)
        f = (min(max(u, start), last) - start) / step
        k = min(max(math.floor(f), 0), count - 2)
        t = f - k
        out[side, 0] = _along(contacts.rise, j, node, weight, side, k, t)
        out[side, 1] = _along(contacts.lever, j, node, weight, side, k, t)


