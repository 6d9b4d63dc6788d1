"""The results of a study: the checkpoint written as points arrive, and the final file.

**Checkpoint.** Beside the output, ``RESULTS.checkpoint.jsonl``: a header line naming
the study (a hash of the model, the outputs, the options and the points), then one JSON
line per evaluated point, appended and flushed to disk (``fsync``) as chunks finish.
A line cut short by a crash is ignored. ``--resume`` reads it and evaluates only the
points it lacks; a checkpoint of another study is refused. It is removed once the
final file is written.

**Final file**, by suffix, written whole (:mod:`express.io.output`), rows in point
order, so that it is the same whatever the order in which the points finished:

``.csv``
    a header of names with their SI units (``kx1_N_m``, ``critical_speed_m_s``), then one
    row per point: the varied parameters (SI), each output (SI) and ``error`` (empty, or
    the point's message). Numbers are written with the shortest text that reads back as
    the same double (Python's ``repr``), so that nothing is lost; ``nan`` for none.
``.parquet``
    the same columns (pyarrow), the units and the study file in the schema metadata.
``.nc``
    netCDF (xarray, netCDF-3 through SciPy): for a grid, the outputs on the grid's axes
    (one dimension per parameter, the values as coordinates); otherwise a ``point``
    dimension. Every variable carries its ``units``; the study file is the global
    attribute ``study``.
"""

from __future__ import annotations

import csv
import io
import json
import math
import os
from collections.abc import Iterable, Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any, TextIO

import numpy as np

from express.analysis.study.outputs import OUTPUTS
from express.base.data import DataRecord
from express.base.diagnostics import UsageError

__all__ = ["FORMATS", "Checkpoint", "MemoryCheckpoint", "ResultTable", "checkpoint_path", "result_bytes", "study_dataset_of"]

FORMATS = (".csv", ".parquet", ".nc")
_HEADER = "express-study-checkpoint"


def checkpoint_path(output: str | Path) -> Path:
    """``RESULTS.checkpoint.jsonl`` beside ``output``."""
    output = Path(output)
    return output.with_name(output.name + ".checkpoint.jsonl")


class Checkpoint:
    """Append-only JSON-lines record of the evaluated points (module docstring).

    Parameters
    ----------
    path : Path
    identity : dict
        What the study is (JSON-serialisable); the header line.
    """

    def __init__(self, path: Path, identity: dict):
        self.path = path
        self.identity = {"format": _HEADER, **identity}
        self._stream: TextIO | None = None

    def open(self, resume: bool) -> None:
        """Start (or, with ``resume``, continue) the checkpoint.

        Raises
        ------
        UsageError
            A checkpoint exists without ``resume`` (or belongs to another study).
        """
        exists = self.path.exists()
        if exists and not resume:
            raise UsageError(
                f"{self.path}: a checkpoint of an unfinished run exists; continue it with --resume "
                "or delete it to start again"
            )
        header = self._header() if exists else None
        if header == "torn":  # cut short while it was being created: nothing in it yet
            exists = False
        if exists:
            if not isinstance(header, dict) or header.get("format") != _HEADER:
                raise UsageError(
                    f"{self.path}: not a checkpoint of an EXPRESS study (its first line is not a checkpoint "
                    "header); delete it or write the results elsewhere"
                )
            if header != self.identity:
                raise UsageError(
                    f"{self.path}: the checkpoint belongs to another study (or the study, its model "
                    "or its options changed); delete it to start again"
                )
            self._truncate_torn_line()
            self._stream = open(self.path, "a", encoding="utf-8")  # noqa: SIM115 - kept open: appended to until the study ends
        else:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            self._stream = open(self.path, "w", encoding="utf-8")  # noqa: SIM115 - kept open: appended to until the study ends
            self._write([self.identity])

    def _header(self) -> dict | str | None:
        """The header line; ``"torn"`` for a file cut short before its header was whole,
        None for one that is not a checkpoint (binary, another format)."""
        try:
            with open(self.path, "rb") as stream:
                first = stream.readline(1 << 20)
        except OSError as error:
            raise UsageError(f"{self.path}: cannot read the checkpoint ({error.strerror or error})") from None
        if not first.endswith(b"\n"):  # torn: a part of this study's header (or nothing)?
            return "torn" if self._header_bytes().startswith(first) else None
        try:
            header = json.loads(first.decode("utf-8"))
        except (UnicodeDecodeError, json.JSONDecodeError, RecursionError):  # nested beyond the parser: not ours
            return None
        return header if isinstance(header, dict) else None

    def _header_bytes(self) -> bytes:
        return (json.dumps(self.identity, allow_nan=False) + "\n").encode("utf-8")

    def _truncate_torn_line(self) -> None:
        """Drop a last line cut short by a crash, so that appends start on a new line."""
        with open(self.path, "rb+") as stream:
            data = stream.read()
            if data and not data.endswith(b"\n"):
                stream.truncate(data.rfind(b"\n") + 1)

    def _write(self, items: Iterable[dict]) -> None:
        assert self._stream is not None
        self._stream.write("".join(json.dumps(item, allow_nan=False) + "\n" for item in items))
        self._stream.flush()
        os.fsync(self._stream.fileno())

    def append(self, records: Sequence[dict]) -> None:
        """Write records now (flushed and synced to disk)."""
        self._write(records)

    def records(self) -> Iterator[dict]:
        """Every complete record in the file (a torn last line is skipped)."""
        if not self.path.exists():
            return
        with open(self.path, encoding="utf-8", errors="replace") as stream:  # a damaged line is skipped
            stream.readline()
            for line in stream:
                if not line.endswith("\n"):
                    break
                try:
                    record = json.loads(line)
                except (json.JSONDecodeError, RecursionError):
                    continue
                if isinstance(record, dict) and isinstance(record.get("point"), int):
                    yield record

    def close(self) -> None:
        if self._stream is not None:
            self._stream.close()
            self._stream = None

    def remove(self) -> None:
        self.close()
        self.path.unlink(missing_ok=True)

    def exists(self) -> bool:
        """Whether the checkpoint is stored (its file exists)."""
        return self.path.exists()


class MemoryCheckpoint(Checkpoint):
    """A checkpoint kept in memory (:func:`express.analysis.study.run.study`): the same
    records as the file's, nothing written; it cannot be resumed.

    Parameters
    ----------
    identity : dict
        What the study is (as :class:`Checkpoint`).
    """

    def __init__(self, identity: dict):
        super().__init__(Path("(in memory)"), identity)
        self._records: list[dict] = []

    def open(self, resume: bool) -> None:
        self._records = []

    def append(self, records: Sequence[dict]) -> None:
        # the file's JSON round trip keeps every double exactly (shortest repr): a copy is the same record
        self._records.extend(dict(record) for record in records)

    def records(self) -> Iterator[dict]:
        yield from self._records

    def close(self) -> None:
        pass

    def remove(self) -> None:
        self._records = []

    def exists(self) -> bool:
        return False


@dataclass(repr=False)
class ResultTable(DataRecord):
    """The results in point order.

    Attributes
    ----------
    names : tuple of str
        Varied parameters.
    units : dict of str to str
        SI unit of every parameter and output (``""`` for pure numbers).
    values : numpy.ndarray, shape (N, D)
    outputs : tuple of str
    results : numpy.ndarray, shape (N, O)
        Output values (SI), nan where none.
    errors : dict of int to str
        Messages of the points that have one.
    """

    names: tuple[str, ...]
    units: dict[str, str]
    values: np.ndarray
    outputs: tuple[str, ...]
    results: np.ndarray
    errors: dict[int, str]

    @classmethod
    def empty(cls, names, units, outputs, count: int) -> ResultTable:
        return cls(tuple(names), dict(units), np.full((count, len(names)), np.nan), tuple(outputs),
                   np.full((count, len(outputs)), np.nan), {})

    def add(self, record: dict) -> None:
        """Store one checkpoint record."""
        i = record["point"]
        self.values[i] = record["values"]
        self.results[i] = [math.nan if x is None else x for x in record["outputs"]]
        if record.get("error"):
            self.errors[i] = record["error"]
        else:
            self.errors.pop(i, None)

    def column(self, name: str) -> np.ndarray:
        """A parameter's or an output's column."""
        if name in self.names:
            return self.values[:, self.names.index(name)]
        return self.results[:, self.outputs.index(name)]

    def error_column(self) -> list[str]:
        return [self.errors.get(i, "") for i in range(len(self.values))]

    def to_xarray(self):
        """The table as an :class:`xarray.Dataset` over ``point``: each parameter and
        output with its unit, ``error`` ('' for none)."""
        from express.analysis.result_data import study_dataset

        columns: dict[str, Any] = {name: self.column(name) for name in (*self.names, *self.outputs)}
        columns["error"] = self.error_column()
        return study_dataset(columns, self.units)

    def _summary(self) -> list[str]:
        return [f"{len(self.values)} points of {', '.join(self.names) or 'no parameters'}"[:120],
                f"outputs {', '.join(self.outputs)}; {len(self.errors)} with a message"[:120]]


def _number(value: float) -> str:
    return repr(float(value)) if math.isfinite(value) else "nan"


def csv_bytes(table: ResultTable) -> bytes:
    """The CSV file (module docstring)."""
    from express.io.text_formats import column_name

    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow([column_name(n, table.units.get(n)) for n in (*table.names, *table.outputs)] + ["error"])
    errors = table.error_column()
    for i in range(len(table.values)):
        writer.writerow([_number(x) for x in table.values[i]] + [_number(x) for x in table.results[i]] + [errors[i]])
    return buffer.getvalue().encode("utf-8")


def parquet_bytes(table: ResultTable, metadata: dict[str, str]) -> bytes:
    """The Parquet file: one column per parameter and output, and ``error``."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    columns = {name: pa.array(table.column(name), type=pa.float64()) for name in (*table.names, *table.outputs)}
    columns["error"] = pa.array(table.error_column(), type=pa.string())
    meta = {f"express.{k}": v for k, v in metadata.items()}
    meta["express.units"] = json.dumps({n: table.units.get(n, "") for n in (*table.names, *table.outputs)})
    arrow = pa.table(columns).replace_schema_metadata(meta)
    sink = io.BytesIO()
    pq.write_table(arrow, sink)
    return sink.getvalue()


def study_dataset_of(table: ResultTable, metadata: dict[str, str], grid: Sequence[Sequence[float]] | None = None) -> Any:
    """The results as the :class:`xarray.Dataset` the ``.nc`` file holds (module docstring):
    for a grid (``grid``: each parameter's values) the outputs on the grid's axes, else a
    ``point`` dimension; every variable with its SI ``units``; ``metadata`` as attributes."""
    import xarray as xr

    errors = np.array(table.error_column(), dtype=object)
    data: dict[str, Any]
    if grid is not None:
        shape = tuple(len(axis) for axis in grid)
        dims = table.names
        coords = {name: (name, np.asarray(axis, dtype=float), {"units": table.units.get(name, "")})
                  for name, axis in zip(table.names, grid, strict=True)}
        data = {name: (dims, table.column(name).reshape(shape), {"units": OUTPUTS[name][0]}) for name in table.outputs}
        data["error"] = (dims, errors.reshape(shape), {})
        dataset = xr.Dataset(data, coords=coords)
    else:
        data = {name: ("point", table.column(name), {"units": table.units.get(name, "")})
                for name in (*table.names, *table.outputs)}
        data["error"] = ("point", errors, {})
        dataset = xr.Dataset(data, coords={"point": ("point", np.arange(len(table.values), dtype=np.int32))})
    dataset.attrs.update(metadata)
    return dataset


def netcdf_bytes(table: ResultTable, metadata: dict[str, str], grid: Sequence[Sequence[float]] | None) -> bytes:
    """The netCDF file (:func:`study_dataset_of`); ``grid`` holds each parameter's values for a grid study."""
    return bytes(study_dataset_of(table, metadata, grid).to_netcdf(engine="scipy"))


def result_bytes(path: str | Path, table: ResultTable, metadata: dict[str, str], grid=None) -> bytes:
    """The final file's bytes for ``path``'s suffix (:data:`FORMATS`)."""
    suffix = Path(path).suffix.lower()
    if suffix == ".csv":
        return csv_bytes(table)
    if suffix == ".parquet":
        return parquet_bytes(table, metadata)
    if suffix == ".nc":
        return netcdf_bytes(table, metadata, grid)
    raise UsageError(f"-o {path}: unknown results format; use {', '.join(FORMATS)}")


def read_table(path: str | Path) -> dict[str, np.ndarray]:
    """Columns of a results file by name (units stripped from CSV headers), for figures.

    Numerical columns as float arrays; ``error`` as a list of strings.
    """
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix == ".parquet":
        import pyarrow.parquet as pq

        arrow = pq.read_table(path)
        return {name: (np.asarray(arrow[name]) if name != "error" else arrow[name].to_pylist())
                for name in arrow.column_names}
    if suffix == ".nc":
        import xarray as xr

        with xr.open_dataset(path, engine="scipy") as dataset:
            return {name: np.asarray(dataset[name].values).ravel() for name in dataset.data_vars}
    with open(path, encoding="utf-8", newline="") as stream:
        rows = list(csv.reader(stream))
    header, body = rows[0], rows[1:]
    columns: dict[str, np.ndarray] = {}
    for k, title in enumerate(header):
        name = _bare_name(title)
        cells = [row[k] for row in body]
        columns[name] = cells if name == "error" else np.array([float(c) for c in cells])  # type: ignore[assignment]
    return columns


def _bare_name(title: str) -> str:
    """``critical_speed_m_s`` -> ``critical_speed`` (the unit suffixes of :func:`column_name`)."""
    for name in OUTPUTS:
        if title.startswith(name + "_") or title == name:
            return name
    return title
