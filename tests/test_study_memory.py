"""``express.study(spec)``: a study run in memory (issue 35 item 3), the same numbers as
the file ``run_study`` writes, bit for bit, and nothing written."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import express
from express.analysis.study.results import read_table
from express.analysis.study.run import run_study, study
from express.analysis.study.spec import read_study
from express.base.diagnostics import ArgumentError
from express.io.text_formats import column_name

ROOT = Path(__file__).resolve().parents[1]
MODEL = ROOT / "examples" / "forced-steering.toml"

GRID = """kind = "grid"
outputs = ["critical_speed", "critical_frequency", "least_damping_ratio"]
[study.parameters]
Gamma = { values = [0.03, 0.1, 0.3] }
kx1 = { from = "1 MN/m", to = "4 MN/m", count = 2 }
[study.set]
cyaw = "200 kN*s/m"
"""

SAMPLED = """kind = "lhs"
samples = 4
seed = 3
outputs = ["critical_speed", "least_damping_ratio"]
[study.parameters]
kx1 = { from = "1 MN/m", to = "4 MN/m" }
Rrail = { from = -0.1, to = 0.3 }
"""


def _study(folder: Path, body: str) -> Path:
    path = folder / "study.toml"
    path.write_text(f'[study]\nmodel = "{MODEL}"\n' + body)
    return path


def _bits(values) -> np.ndarray:
    """The doubles' bit patterns (nan compared as its bits, so ``==`` is bit for bit)."""
    return np.ascontiguousarray(np.asarray(values, dtype=np.float64)).view(np.int64)


def test_a_grid_study_in_memory_is_the_files_bit_for_bit(tmp_path: Path) -> None:
    """A 3 x 2 grid: the dataset from ``express.study`` equals the netCDF file ``run_study``
    writes (read back: every variable, coordinate, unit and attribute identical) and the
    CSV's numbers bit for bit; a point that hunts at every speed carries the same message."""
    import xarray as xr

    path = _study(tmp_path, GRID)
    run_study(read_study(path), tmp_path / "r.nc", workers=1)
    run_study(read_study(path), tmp_path / "r.csv", workers=1)
    before = sorted(p.name for p in tmp_path.iterdir())
    data = express.study(path, workers=1)  # a path is read here
    assert sorted(p.name for p in tmp_path.iterdir()) == before  # nothing written
    assert data["critical_speed"].dims == ("Gamma", "kx1") and data.sizes == {"Gamma": 3, "kx1": 2}
    assert data["critical_speed"].attrs["units"] == "m/s" and data["kx1"].attrs["units"] == "N/m"
    assert data.attrs["kind"] == "grid" and data.attrs["study"] == path.read_text()
    with xr.open_dataset(tmp_path / "r.nc", engine="scipy") as file:
        xr.testing.assert_identical(data, file.load())
    csv = read_table(tmp_path / "r.csv")
    for name in ("critical_speed", "critical_frequency", "least_damping_ratio"):
        assert np.array_equal(_bits(data[name].values.ravel()), _bits(csv[name]))
    assert list(data["error"].values.ravel()) == csv["error"]
    assert data["error"].values[0, 0]  # Gamma = 0.03 with the soft kx1 hunts at any speed


def test_a_sampled_study_in_memory_is_the_files_bit_for_bit(tmp_path: Path) -> None:
    """Four Latin-hypercube points (one with a negative rail radius fails): the ``point``
    dataset from a :class:`StudySpec` equals the netCDF file, and the CSV bit for bit,
    messages included."""
    import xarray as xr

    spec = read_study(_study(tmp_path, SAMPLED))
    run_study(spec, tmp_path / "s.nc", workers=1)
    run_study(spec, tmp_path / "s.csv", workers=1)
    data = study(spec, workers=1)
    assert data["critical_speed"].dims == ("point",) and data.sizes == {"point": 4}
    with xr.open_dataset(tmp_path / "s.nc", engine="scipy") as file:
        xr.testing.assert_identical(data, file.load())
    csv = read_table(tmp_path / "s.csv")
    for name in ("kx1", "Rrail", "critical_speed", "least_damping_ratio"):
        column = csv[column_name(name, data[name].attrs["units"])] if name in spec.names else csv[name]
        assert np.array_equal(_bits(data[name].values), _bits(column))
    assert list(data["error"].values) == csv["error"]


def test_sobol_indices_in_memory_are_the_files(tmp_path: Path) -> None:
    """A sobol-indices study: the indices as JSON in the ``indices`` attribute, the same
    numbers as the ``.indices.csv`` file ``run_study`` writes beside its output."""
    body = ('kind = "sobol-indices"\nsamples = 8\nseed = 1\noutputs = ["least_damping_ratio"]\n'
            '[study.parameters]\nkx1 = { from = "1 MN/m", to = "4 MN/m" }\nky1 = { from = "1 MN/m", to = "4 MN/m" }\n'
            '[study.options]\nspeed = "200 km/h"\n')
    spec = read_study(_study(tmp_path, body))
    run_study(spec, tmp_path / "i.csv", workers=1)
    data = study(spec, workers=1)
    indices = json.loads(data.attrs["indices"])["least_damping_ratio"]
    rows = (tmp_path / "i.csv.indices.csv").read_text().splitlines()[1:]
    for k, row in enumerate(rows):
        cells = row.split(",")
        assert cells[1] == indices["parameters"][k]
        assert [float(c) for c in cells[2:]] == [indices[key][k] for key in ("S1", "S1_conf", "ST", "ST_conf")]
    csv = read_table(tmp_path / "i.csv")
    assert np.array_equal(_bits(data["least_damping_ratio"].values), _bits(csv["least_damping_ratio"]))


def test_study_refuses_what_is_not_a_study() -> None:
    with pytest.raises(ArgumentError, match="spec must be a StudySpec"):
        study({"model": "x"})  # type: ignore[arg-type]
    assert "study" in express.__all__ and express.study is study


def test_an_optimisation_in_memory_is_the_files(tmp_path: Path) -> None:
    """An optimisation (differential evolution, population 3, 2 iterations): the history in
    memory equals the netCDF file ``run_study`` writes, and the ``best`` attribute (JSON)
    is the summary's best point."""
    import xarray as xr

    from test_study_optimise import OPTIMISE

    path = tmp_path / "opt.toml"
    path.write_text(OPTIMISE)
    spec = read_study(path)
    summary = run_study(spec, tmp_path / "o.nc", workers=1)
    data = study(spec, workers=1)
    best = json.loads(data.attrs.pop("best"))  # the file's summary says it; the dataset carries it
    with xr.open_dataset(tmp_path / "o.nc", engine="scipy") as file:
        xr.testing.assert_identical(data, file.load())
    assert best == summary.extra["best"] and best["point"] < data.sizes["point"]
