"""Results as data: the shared parts of every result record's ``to_xarray()``,
``to_pandas()``, short ``repr`` and notebook (HTML) display (issue 35, item 2).

A result record derives from :class:`DataRecord` and defines ``to_xarray()`` (an
:class:`xarray.Dataset` with labelled dimensions and CF-style ``units`` and
``long_name`` attributes on every variable) and ``_summary()`` (a few lines of text);
``to_pandas()`` defaults to the dataset as a table (:func:`frame`), with each column's
unit in its name (``"speed [m/s]"``, as :meth:`express.analysis.modes.modes.EigenResult.to_pandas`)
and the units also in ``frame.attrs["units"]``.  xarray and pandas are imported only
when asked.
"""

from __future__ import annotations

import html
from typing import Any

__all__ = ["DataRecord", "columns_frame", "frame", "one_row", "variable", "xarray"]

#: Longest text repr [characters] of a record (a few lines).
REPR_LIMIT = 600


def xarray() -> Any:
    """The :mod:`xarray` module (imported on first use)."""
    import xarray as xr

    return xr


def variable(values: Any, dims: tuple[str, ...] | str, units: str, long_name: str, **attrs: Any) -> tuple:
    """``(dims, values, attrs)`` for an :class:`xarray.Dataset` variable with CF-style
    ``units`` (``"1"`` for a dimensionless number, as CF) and ``long_name``."""
    if isinstance(dims, str):
        dims = (dims,)
    return (dims, values, {"units": units, "long_name": long_name, **attrs})


def _label(name: Any, units: str | None) -> str:
    return f"{name} [{units}]" if units else str(name)


def frame(dataset: Any) -> Any:
    """An :class:`xarray.Dataset` as a :class:`pandas.DataFrame` indexed by its dimensions,
    each column named with its unit, the units also in ``attrs["units"]`` and the dataset's
    attributes in ``attrs``."""
    table = dataset.to_dataframe() if dataset.sizes else dataset.expand_dims("row").to_dataframe()
    units = {str(name): str(dataset[name].attrs.get("units", "")) for name in table.columns}
    table = table.rename(columns={name: _label(name, units[str(name)]) for name in table.columns})
    table.attrs = {**dataset.attrs, "units": units}
    return table


def columns_frame(columns: dict[str, Any], units: dict[str, str], index: str | None = None) -> Any:
    """Named columns (equal lengths, or scalars: one row) as a :class:`pandas.DataFrame`,
    each named with its unit (``units``; ``""`` for none); ``index`` a column made the index."""
    import pandas as pd

    scalar = all(getattr(value, "ndim", 0) == 0 and not isinstance(value, (list, tuple)) for value in columns.values())
    table = pd.DataFrame({_label(name, units.get(name)): ([value] if scalar else value)
                          for name, value in columns.items()})
    if index is not None:
        table = table.set_index(_label(index, units.get(index)))
    table.attrs = {"units": {name: units.get(name, "") for name in columns}}
    return table


def one_row(dataset: Any) -> Any:
    """A dataset of scalars as a one-row :class:`pandas.DataFrame` (:func:`frame`)."""
    table = frame(dataset)
    return table.reset_index(drop=True)


class DataRecord:
    """Mix-in of a result record: ``to_pandas``, a short ``repr`` and ``_repr_html_``
    from the record's ``to_xarray()`` and ``_summary()``.  A dataclass that uses it is
    declared with ``repr=False`` (so that this ``__repr__`` is kept)."""

    def to_xarray(self) -> Any:
        """The record as an :class:`xarray.Dataset` (each record defines its own)."""
        return xarray().Dataset()

    def to_pandas(self) -> Any:
        """The record as a :class:`pandas.DataFrame` (:func:`express.base.data.frame` of
        :meth:`to_xarray`): one row per point of its dimensions, units in the column names."""
        return frame(self.to_xarray())

    def _summary(self) -> list[str]:
        return []

    def __repr__(self) -> str:
        lines = [f"<{type(self).__name__}>", *(f"  {line}" for line in self._summary())]
        text = "\n".join(lines)
        return text if len(text) <= REPR_LIMIT else text[: REPR_LIMIT - 4] + " ..."

    def _repr_html_(self) -> str:
        """The summary and the dataset (xarray's display) in a notebook."""
        head = "<br>".join(html.escape(line) for line in self._summary())
        return f"<p><b>{type(self).__name__}</b><br>{head}</p>" + self.to_xarray()._repr_html_()
