"""One wear step's cases: the vehicle on a worn wheel profile, and the depth each case of
the route wears off the profile per metre run (steady curving with the profiles' contact,
:mod:`express.analysis.curving.steady`; ``docs/wear.md``, "Wear prediction").

The wheel profile lives on a uniform lateral grid (:class:`ProfileGrid`, the side frame of
:mod:`express.rail.profiles`); each case's contacts (every wheel of the vehicle) spread
their USFD wear mass over its cells (:func:`express.rail.wear_profile.usfd_profile_wear`,
the patch's lateral semi-axis projected on the profile's lateral coordinate,
``b cos(gamma)``); the depth of a case is the **mean over all wheels**, left and right:
one profile stands for every wheel, and the route's curves count half to the left and half
to the right (the left wheel of a right-hand curve wears as the right wheel of a left-hand one).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from express.base.diagnostics import ArgumentError
from express.numeric.statespace import VehicleModel
from express.rail.contact_tables import ARM
from express.rail.profiles import STANDARD_PROFILES, Profile, standard_profile
from express.rail.wear_profile import usfd_profile_wear

__all__ = ["KIND", "ProfileGrid", "case_depth", "initial_grid", "profile_nodes_of", "profile_text",
           "with_wheel_profile"]

#: Kind of the model's profile derivation (:data:`express.rail.profile_contact.KIND`).
KIND = "profiles"


@dataclass(frozen=True)
class ProfileGrid:
    """A wheel profile on uniform lateral nodes ``y = start + spacing k``, ``k < count`` [m],
    heights ``z`` [m] (side frame); the wear cells are centred on the nodes."""

    start: float
    spacing: float
    z: np.ndarray

    @property
    def y(self) -> np.ndarray:
        return self.start + self.spacing * np.arange(self.z.size)

    @property
    def edges(self) -> np.ndarray:
        """Cell edges [m], shape (count + 1,)."""
        return self.start + self.spacing * (np.arange(self.z.size + 1) - 0.5)

    def worn(self, depth: np.ndarray) -> ProfileGrid:
        """The profile with ``depth`` [m] (per node) removed: ``z + depth`` (the radius
        ``r0 - z`` falls by the depth)."""
        return replace(self, z=self.z + depth)


def profile_nodes_of(vehicle: VehicleModel) -> list:
    """The model's profile derivations; ArgumentError unless there is one wheel profile."""
    nodes = [d for d in vehicle.model.derivations if d.kind == KIND and not dict(d.settings).get("table")]  # not a table file
    if not nodes:
        raise ArgumentError(f"{vehicle.model.source}: the contact does not come from profiles (conicity = "
                            "{ from = \"profiles\", ... } in [rail.wheel_rail]): a wear prediction wears a wheel profile")
    wheels = {dict(d.settings).get("wheel") for d in nodes}
    if len(wheels) > 1:
        raise ArgumentError(f"{vehicle.model.source}: the wheelsets have different wheel profiles "
                            f"({', '.join(sorted(str(w) for w in wheels))}); the prediction wears one profile")
    return nodes


def _wheel_profile(vehicle: VehicleModel) -> Profile:
    from express.rail.profile_formats import read_profile

    settings = dict(profile_nodes_of(vehicle)[0].settings)
    text = settings["wheel"]
    if text.strip().upper().replace(" ", "") in STANDARD_PROFILES:
        return standard_profile(text.strip().upper().replace(" ", ""))
    path = Path(text) if Path(text).is_absolute() else Path(settings.get("base", "") or ".") / text
    return read_profile(path, "wheel", units=settings.get("units") or None)


def initial_grid(vehicle: VehicleModel, spacing: float) -> ProfileGrid:
    """The model's wheel profile resampled on nodes ``spacing`` [m] apart (multiples of it,
    inside the profile; linear between its points)."""
    profile = _wheel_profile(vehicle)
    first, last = math.ceil(profile.y[0] / spacing - 1e-9), math.floor(profile.y[-1] / spacing + 1e-9)
    y = spacing * np.arange(first, last + 1)
    return ProfileGrid(float(y[0]), float(spacing), np.interp(y, profile.y, profile.z))


def profile_text(grid: ProfileGrid, note: str) -> str:
    """The profile as a two-column file in mm (``docs/contact.md``), 12 significant digits."""
    lines = [f"# {note}", "y_mm,z_mm"]
    lines += [f"{y * 1e3:.12g},{z * 1e3:.12g}" for y, z in zip(grid.y, grid.z, strict=True)]
    return "\n".join(lines) + "\n"


def with_wheel_profile(vehicle: VehicleModel, path: str | Path) -> VehicleModel:
    """``vehicle`` with the wheel profile of every profile derivation replaced by the file
    ``path`` (in mm: :func:`profile_text`), its contact and linear terms evaluated anew."""
    from express.model.parameters import resolve

    model = vehicle.model
    derivations = []
    for node in model.derivations:
        if node.kind == KIND:
            settings = {**dict(node.settings), "wheel": str(Path(path).resolve())}
            settings.pop("units", None)  # the file's header names its unit
            node = replace(node, settings=tuple(settings.items()))
        derivations.append(node)
    return vehicle.with_model(resolve(replace(model, derivations=tuple(derivations))))


def case_depth(vehicle: VehicleModel, grid: ProfileGrid, results: list) -> tuple[np.ndarray, dict[str, float]]:
    """The depth worn off ``grid``'s cells per metre run [m/m] by the steady states
    ``results`` (:class:`~express.analysis.curving.steady.SteadyCurving` of one case, or
    none for straight track; where the curve has no equilibrium, the settled time run
    into it, :class:`~express.analysis.curving.settled.SettledCurving`, or a run on a
    random track, :class:`~express.analysis.wear.random_track.RandomTrackRun`: their
    instants each standing for an equal share of the metre), the mean over all wheels,
    and the case's largest Tγ [N] and whether a wheel is in flange contact."""
    from express.rail.profile_contact import wheelset_contacts

    depth = np.zeros(grid.z.size)
    summary = {"Tgamma_max": 0.0, "flanging": 0.0}
    if not results:
        return depth, summary
    tables = wheelset_contacts(vehicle.model, vehicle.values, vehicle.wheelsets)
    count = 0
    for result in results:
        out = result.wheel_rail
        rolled = 1.0 / out.vertical_load.shape[0]  # [m] per instant: a steady state is one instant
        if out.frictional_power is None or out.wheel_position is None or out.patch_semi_b is None:
            raise ArgumentError("the steady state has no contact tables' record (the wear needs the profiles' contact)")
        for j, contact in enumerate(tables):
            assert contact is not None
            table = contact.tables
            for side in range(2):  # the centred contact's place on the profile, then this one's from it
                centre = float(np.interp(0.0, table.y, table.data[ARM, side])) - table.setup.tapeline_half_distance
                semi_b = out.patch_semi_b[:, j, side] * np.cos(out.contact_angle[:, j, side])
                depth += usfd_profile_wear(grid.edges, centre + out.wheel_position[:, j, side], semi_b,
                                           out.frictional_power[:, j, side], out.patch_area[:, j, side], rolled,
                                           radius=vehicle.wheelsets[j].r0)
                count += 1
        summary["Tgamma_max"] = max(summary["Tgamma_max"], float(np.max(out.frictional_power)))
        summary["flanging"] = max(summary["flanging"], float(np.any(out.flange_contact)))
    return depth / count, summary
