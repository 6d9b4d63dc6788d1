"""The warm load: a numerical vehicle from the derivation cache without reading the model.

A derivation entry (:mod:`express.numeric.derived`) spares the symbolic work, but to
find it a load must read the model file into its records — SymPy expressions — and
that import and reading cost more than the rest of a numerical command.  So beside it
the cache keeps a *warm entry* of what the numerical vehicle takes from the model:
the parameter values (SI), the speed's name, the wheelsets' coordinates, the rail
layout, the facts of :mod:`express.numeric.facts`, the warnings the reading gave, and
the files the reading read with their digests.  It is keyed by the model file's own
bytes and the options; it is used only while every file it lists still has the
recorded digest, and it names the derivation entry by the same key a full load
computes (:func:`express.io.cache.entry_key` of those files), so the two cannot
disagree.  Reading it imports neither SymPy nor the model readers.

Everything here is data checked when read (:class:`~express.numeric.program.ProgramError`
for anything else: the entry is ignored with one warning and rebuilt).
"""

from __future__ import annotations

import hashlib
import math
import os
import stat
import warnings
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from express.base.diagnostics import ArgumentError, ModelWarning
from express.io.cache import cache_enabled, entry_damaged, entry_key, has_entry, read_entry, write_entry
from express.numeric.compiled import CompiledExpressions, CompiledMatrices
from express.numeric.derived import CompiledVehicle, read_compiled_entry
from express.numeric.facts import VehicleFacts, facts_data, read_facts
from express.numeric.program import ProgramError, checked_list, checked_strings
from express.rail.layout import RailLayout, Station

if TYPE_CHECKING:
    from express.assembly.equations import EquationsOfMotion
    from express.model.records import Model

__all__ = ["VehicleOrigin", "WarmRead", "WarmVehicle", "file_digest", "find_warm", "read_warm_vehicle", "read_warning_items",
           "reemit", "repeat_warnings", "unchanged", "warm_entry", "warning_items", "write_warm_entry"]

#: Warning categories a warm entry may repeat (the reading's warnings, by name).
_CATEGORIES: dict[str, type[Warning]] = {
    c.__name__: c for c in (ModelWarning, UserWarning, RuntimeWarning, DeprecationWarning)
}


class VehicleOrigin:
    """The symbolic equations and model a :class:`VehicleModel` was evaluated from: given,
    or — a vehicle read back from the derivation cache — built on first use by ``twin``
    (the same vehicle through the symbolic model), so that a warm command that never asks
    for them never loads the model file's records nor SymPy.

    Parameters
    ----------
    name, source : str
        The model's name and file.
    dofs, inputs : tuple of str
        The equations' coordinates and inputs.
    equations, model : optional
        Given when evaluated from the symbolic model.
    twin : callable, optional
        Builds the same vehicle from the symbolic model (a vehicle read from the cache).
    facts : VehicleFacts, optional
        The model's facts at the vehicle's values, when read from the cache.
    """

    def __init__(self, name: str, source: str, dofs: tuple[str, ...], inputs: tuple[str, ...], *,
                 equations: EquationsOfMotion | None = None, model: Model | None = None,
                 twin: Callable[[], Any] | None = None, facts: VehicleFacts | None = None):
        self.name, self.source, self.dofs, self.inputs = name, source, dofs, inputs
        self._equations, self._model, self._twin, self.facts = equations, model, twin, facts
        self._built: Any = None  # the VehicleModel (express.numeric.statespace imports this module)

    @property
    def cached(self) -> bool:
        """Whether the vehicle was read from the cache (its symbolic side is built on demand)."""
        return self._twin is not None

    def twin(self) -> Any:
        """The same vehicle evaluated from the symbolic model (built once)."""
        if self._twin is None:
            raise ArgumentError("this vehicle was evaluated from its symbolic model already")
        if self._built is None:
            self._built = self._twin()
        return self._built

    @property
    def equations(self) -> EquationsOfMotion:
        return self._equations if self._equations is not None else self.twin().equations

    @property
    def model(self) -> Model:
        return self._model if self._model is not None else self.twin().model


@dataclass(frozen=True)
class WarmVehicle:
    """What a warm load evaluates (module docstring).

    Attributes
    ----------
    key : str
        The derivation entry's key (the in-process reuse's too).
    name : str
        The model's name.
    dofs, inputs : tuple of str
        The equations' coordinates and inputs.
    values : dict of str to float
        Every parameter's value at the file's values [SI].
    speed_name : str or None
        The speed parameter kept apart.
    compiled : CompiledMatrices
    rail_numbers : CompiledExpressions or None
    wheelsets : tuple of (str, int, int)
        Every wheelset: its body, the indices of its ``y`` and ``rz`` in ``dofs``.
    layout : RailLayout or None
        Station positions as numbers [m].
    facts : VehicleFacts
    """

    key: str
    name: str
    dofs: tuple[str, ...]
    inputs: tuple[str, ...]
    values: dict[str, float]
    speed_name: str | None
    compiled: CompiledMatrices
    rail_numbers: CompiledExpressions | None
    wheelsets: tuple[tuple[str, int, int], ...]
    layout: RailLayout | None
    facts: VehicleFacts


def _model_key(path: str | Path, with_rail: bool) -> str | None:
    """The warm entry's key: the model file's bytes and the options (None: not a regular
    file, or unreadable)."""
    digest = file_digest(os.fspath(path))
    if digest is None:
        return None
    return entry_key("vehicle warm", [(os.path.abspath(path), digest)], {"with_rail": with_rail, "warm_format": 2})


def file_digest(path: str) -> str | None:
    """SHA-256 of a regular file's bytes; None for anything else (a pipe is read once, by
    the model reader: ``express eigen <(cat model.toml)``), an unreadable file, or one
    beyond the input size limit (``EXPRESS_MAX_FILE_MB``: the model reader refuses it
    before reading it whole; it is never hashed whole first)."""
    from express.base.limits import limit

    try:
        status = os.stat(path)
        if not stat.S_ISREG(status.st_mode) or status.st_size > limit("file_mb") * 1024 * 1024:
            return None
        digest = hashlib.sha256()
        with open(path, "rb") as stream:
            for block in iter(lambda: stream.read(1 << 20), b""):
                digest.update(block)
        return digest.hexdigest()
    except OSError:
        return None


@dataclass(frozen=True)
class WarmRead:
    """A warm entry found for a model file whose listed files are all unchanged.

    Attributes
    ----------
    key : str
        The warm entry's key.
    vehicle_key : str
        The derivation entry's key (the in-process reuse's too).
    payload : dict
        The entry's data (checked by :func:`read_warm_vehicle`).
    """

    key: str
    vehicle_key: str
    payload: dict


#: Warm entries read or written in this process, by key: a second load of the same file
#: reads no cache file (the files it lists are still digested).
_READ: dict[str, dict] = {}
_READ_SIZE = 8


def find_warm(path: str | Path, with_rail: bool) -> WarmRead | None:
    """The warm entry of ``path``, or None: the cache off, no entry, a file it lists
    changed since (a full load stores the entry anew), a damaged entry (one warning)."""
    key = _model_key(path, with_rail) if cache_enabled() else None
    if key is None:
        return None
    payload = _READ.get(key)
    if payload is None:
        payload = read_entry(key)
        if payload is None:
            return None
    try:
        reads = _reads(payload)
    except ProgramError:
        entry_damaged(key)
        return None
    if not unchanged(reads):
        return None
    _remember(key, payload)
    return WarmRead(key, entry_key("vehicle", reads, {"with_rail": with_rail}), payload)


def unchanged(reads: Sequence[tuple[str, str]]) -> bool:
    """Whether every file of ``reads`` (path, SHA-256) still has its recorded bytes."""
    return all(file_digest(name) == digest for name, digest in reads)


def _remember(key: str, payload: dict) -> None:
    if len(_READ) >= _READ_SIZE:
        _READ.pop(next(iter(_READ)))
    _READ[key] = payload


def read_warm_vehicle(found: WarmRead) -> WarmVehicle | None:
    """The vehicle of a warm entry and of its derivation entry, or None: no derivation
    entry, or a damaged one (one warning, as for a full load)."""
    vehicle = read_entry(found.vehicle_key)
    if vehicle is None:
        return None
    try:
        part = read_compiled_entry(vehicle)
    except ProgramError:
        entry_damaged(found.vehicle_key)
        return None
    try:
        return _warm_vehicle(found.payload, found.vehicle_key, part)
    except ProgramError:
        _READ.pop(found.key, None)
        entry_damaged(found.key)
        return None


def _warm_vehicle(payload: dict, vehicle_key: str, part: CompiledVehicle) -> WarmVehicle:
    pairs = checked_list(payload.get("values"))  # pairs: the model's order (JSON sorts a mapping)
    if not all(isinstance(p, list) and len(p) == 2 and isinstance(p[0], str) and type(p[1]) is float
               and math.isfinite(p[1]) for p in pairs):
        raise ProgramError("bad values")
    values = dict(pairs)
    _check_bounds(values, payload.get("bounds"))
    speed_name = payload.get("speed_name")
    if not (speed_name is None or isinstance(speed_name, str)):
        raise ProgramError("bad speed")
    if part.compiled.speed != (speed_name if speed_name in part.compiled.parameters else None):
        raise ProgramError("another speed")
    if any(name not in values for name in part.compiled.parameters):
        raise ProgramError("a parameter without a value")
    wheelsets = tuple(_wheelset(item, part.dofs) for item in checked_list(payload.get("wheelsets")))
    layout = _layout(payload.get("layout"))
    if (layout is None) != (part.rail_numbers is None):
        raise ProgramError("rail numbers without a layout")
    name = payload.get("name")
    if not isinstance(name, str):
        raise ProgramError("bad name")
    return WarmVehicle(vehicle_key, name, part.dofs, part.inputs, dict(values), speed_name, part.compiled,
                       part.rail_numbers, wheelsets, layout, read_facts(payload.get("facts")))


def _bound(value: float) -> float | None:
    return float(value) if math.isfinite(value) else None  # JSON has no infinity


def _check_bounds(values: dict[str, float], data: Any) -> None:
    """Every value within the valid range the model's reading gave it (the same ranges a
    model file's values are checked against: a value no file could give is not used)."""
    for item in checked_list(data):
        if not (isinstance(item, list) and len(item) == 4 and isinstance(item[0], str) and item[0] in values
                and all(v is None or type(v) is float for v in item[1:3]) and type(item[3]) is bool):
            raise ProgramError("bad bounds")
        name, low, high, open_low = item
        value = values[name]
        if (low is not None and (value <= low if open_low else value < low)) or (high is not None and value > high):
            raise ProgramError(f"{name} = {value!r} outside its valid range")


def reemit(found: WarmRead, source: str) -> bool:
    """Give again the warnings the reading of the model gave (the file named as in
    ``source``, the path this load was given); False (nothing given) for an entry whose
    warnings do not check (damaged: one warning, the caller loads in full)."""
    try:
        messages = [_warning(item) for item in checked_list(found.payload.get("warnings"))]
        recorded = read_facts(found.payload.get("facts")).source
    except ProgramError:
        _READ.pop(found.key, None)
        entry_damaged(found.key)
        return False
    repeat_warnings(messages, recorded, source)
    return True


def repeat_warnings(messages: Sequence[tuple[str, str]], recorded: str, source: str) -> None:
    """Give the ``(category, message)`` warnings of an entry again, the model file named
    as ``source`` (this load's path) where the cold load named it ``recorded``."""
    for category, message in messages:
        if message.startswith(f"{recorded}:"):  # the file as the cold load was given it
            message = source + message[len(recorded):]
        warnings.warn(message, _CATEGORIES[category], stacklevel=4)


def warning_items(caught: Sequence[warnings.WarningMessage]) -> list[list[str]] | None:
    """The caught warnings as ``[category, message]`` data, or None when one cannot be
    repeated exactly (a category a warm entry does not know)."""
    if any(type(w.message) is not w.category or w.category.__name__ not in _CATEGORIES for w in caught):
        return None
    return [[w.category.__name__, str(w.message)] for w in caught]


def read_warning_items(data: Any) -> list[tuple[str, str]]:
    """``[category, message]`` data back as pairs (ProgramError when it does not check)."""
    return [_warning(item) for item in checked_list(data)]


def warm_entry(
    name: str, reads: Sequence[tuple[str, str]], values: dict[str, float], speed_name: str | None,
    wheelsets: Sequence[tuple[str, int, int]], layout: RailLayout | None, station_positions: Sequence[float],
    facts: VehicleFacts, caught: Sequence[warnings.WarningMessage],
    bounds: dict[str, tuple[float, float, bool]] | None = None,
) -> dict[str, Any] | None:
    """The warm entry's data, or None when it cannot repeat the load exactly (a value
    not finite, a warning of another category).  ``bounds``: the valid range of each
    parameter (:func:`express.model.parameter_ranges.parameter_bounds`), checked again
    when the entry is read."""
    items = warning_items(caught)
    if items is None or not all(math.isfinite(v) for v in values.values()):
        return None
    return {
        "name": name,
        "kind": "vehicle warm",
        "reads": [list(read) for read in reads],
        "values": [[key, float(value)] for key, value in values.items()],
        "bounds": [[key, _bound(low), _bound(high), bool(open_low)]
                   for key, (low, high, open_low) in sorted((bounds or {}).items())],
        "speed_name": speed_name,
        "wheelsets": [list(item) for item in wheelsets],
        "layout": None if layout is None else {
            "wheelsets": list(layout.wheelsets),
            "stations": [[s.name, float(x), list(s.bodies)] for s, x in zip(layout.stations, station_positions, strict=True)],
            "irregularity": list(layout.irregularity), "flange": list(layout.flange),
            "curvature": list(layout.curvature), "cant": list(layout.cant),
        },
        "facts": facts_data(facts),
        "warnings": items,
    }


def write_warm_entry(path: str | Path, with_rail: bool, vehicle_key: str, entry: dict[str, Any] | None) -> None:
    """Store ``entry`` for ``path`` (replacing one that lists a file changed since) when
    its derivation entry was stored (a derivation with a function is not cached: neither
    is its warm entry)."""
    key = _model_key(path, with_rail) if cache_enabled() else None
    if key is not None and entry is not None and has_entry(vehicle_key):
        write_entry(key, entry)
        _remember(key, entry)


def _reads(payload: Any) -> list[tuple[str, str]]:
    if not isinstance(payload, dict) or payload.get("kind") != "vehicle warm":
        raise ProgramError("not a warm entry")
    reads = checked_list(payload.get("reads"))
    if not reads or not all(isinstance(r, list) and len(r) == 2 and all(isinstance(x, str) for x in r) for r in reads):
        raise ProgramError("bad reads")
    return [(r[0], r[1]) for r in reads]


def _wheelset(item: Any, dofs: tuple[str, ...]) -> tuple[str, int, int]:
    if not (isinstance(item, list) and len(item) == 3 and isinstance(item[0], str)
            and all(type(x) is int and 0 <= x < len(dofs) for x in item[1:])):
        raise ProgramError("bad wheelset")
    return item[0], item[1], item[2]


def _layout(data: Any) -> RailLayout | None:
    if data is None:
        return None
    if not isinstance(data, dict):
        raise ProgramError("bad layout")
    stations = []
    for item in checked_list(data.get("stations")):
        if not (isinstance(item, list) and len(item) == 3 and isinstance(item[0], str) and type(item[1]) is float):
            raise ProgramError("bad station")
        stations.append(Station(item[0], item[1], tuple(checked_strings(item[2]))))
    groups = [tuple(checked_strings(data.get(name))) for name in ("wheelsets", "irregularity", "flange", "curvature", "cant")]
    return RailLayout(groups[0], tuple(stations), *groups[1:])


def _warning(item: Any) -> tuple[str, str]:
    if not (isinstance(item, list) and len(item) == 2 and item[0] in _CATEGORIES and isinstance(item[1], str)):
        raise ProgramError("bad warning")
    return item[0], item[1]



