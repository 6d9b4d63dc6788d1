"""The named choices of the rail modules, as types: the creep law, the contact model of a
time march and the kind of a profile (each a ``Literal`` and the tuple of its values)."""

from __future__ import annotations

from typing import Literal, get_args

__all__ = ["CONTACT_MODELS", "CREEP_LAWS", "DEFAULT_CREEP_LAW", "PROFILE_KINDS", "ContactModel", "CreepLaw", "ProfileKind"]

#: The tangential contact law of the nonlinear contact (``rail/creep_law.py``; ``"table"``:
#: the tables of the exact theory, ``rail/creep_table.py``).
CreepLaw = Literal["fastsim", "polach", "table"]
#: Wheel/rail contact of a time march: the profiles' tables or the linear dead band.
ContactModel = Literal["tables", "deadband"]
#: What a profile describes.
ProfileKind = Literal["wheel", "rail"]

CREEP_LAWS: tuple[CreepLaw, ...] = get_args(CreepLaw)
#: The creep law of the contact from profiles unless one is chosen: the tables of the exact
#: theory (``docs/contact.md``: accurate in every regime, spin and flange contact included);
#: FASTSIM and Polach stay selectable.
DEFAULT_CREEP_LAW: CreepLaw = "table"
CONTACT_MODELS: tuple[ContactModel, ...] = get_args(ContactModel)
PROFILE_KINDS: tuple[ProfileKind, ...] = get_args(ProfileKind)
