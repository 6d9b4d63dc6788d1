"""One small cache for values computed from objects that are compared by identity (a
model, its equations, contact tables): bounded, and safe against a recycled ``id()``."""

from __future__ import annotations

from collections.abc import Callable, Hashable
from typing import Generic, TypeVar

__all__ = ["IdentityCache"]

_V = TypeVar("_V")


class IdentityCache(Generic[_V]):
    """Values keyed by the identity of some objects (and by plain hashable values).

    An entry keeps its objects alive and is found only when the very same objects (``is``)
    are asked for again, so a new object that happens to get a freed ``id()`` never meets
    a stale value.  At most ``size`` entries; the oldest goes first.

    Examples
    --------
    >>> cache = IdentityCache(2)
    >>> model = object()
    >>> cache.get_or_make((model,), lambda: "derived", values=(1.0,))
    'derived'
    >>> cache.get_or_make((model,), lambda: "again", values=(1.0,))
    'derived'
    >>> cache.get_or_make((object(),), lambda: "other", values=(1.0,))
    'other'
    """

    def __init__(self, size: int):
        self.size = size
        self._entries: dict[tuple, tuple[tuple[object, ...], _V]] = {}

    def get_or_make(self, objects: tuple[object, ...], make: Callable[[], _V], values: Hashable = ()) -> _V:
        """The value stored for ``objects`` and ``values``, else ``make()`` (stored).

        Parameters
        ----------
        objects : tuple of object
            Compared by identity.
        make : callable
            Computes the value when it is not stored.
        values : hashable
            Compared by value (speeds, loads, names).

        Returns
        -------
        object
            The stored or new value.
        """
        key = (tuple(id(item) for item in objects), values)
        found = self._entries.get(key)
        if found is not None and all(a is b for a, b in zip(found[0], objects, strict=True)):
            return found[1]
        value = make()
        if key not in self._entries and len(self._entries) >= self.size:
            self._entries.pop(next(iter(self._entries)))
        self._entries[key] = (tuple(objects), value)
        return value

    def clear(self) -> None:
        """Forget every entry."""
        self._entries.clear()
