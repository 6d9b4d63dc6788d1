"""FE modal data from a universal file (``express.io.uff_modes``, ``[flexible.<body>.fe]``):
a real NX export read for what it states, an FE beam written in the test and read back
against the analytic beam, the unit conversions, and bad input."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
import pyuff
import scipy.linalg as sl

from cli_support import assert_input_error
from express.base.diagnostics import Problem
from express.io.uff_modes import PURITY, FEModeChoice, read_uff_modes
from express.model.modal_body import ModeKind
from test_modal_body import BEAM, LENGTH, beam_model, frequencies, hermite_matrices

NX = Path(__file__).parent / "data" / "fe_modes" / "nx_simulation_output_10_modes.uff"
#: The NX file's first frequencies [Hz] as its datasets state them (record 12, field 2).
NX_FREQUENCIES = [23383.2, 23384.1, 37317.1, 54308.9, 54313.4, 60860.4, 74629.1, 89949.6, 89961.3, 111941.0]


def nx_sets():
    return pyuff.UFF(str(NX)).read_sets()


# ------------------------------------------------------------------ a real FE program's file


def test_the_nx_export_is_read_for_what_it_states():
    """Every mode's frequency as stated; shapes at three named nodes equal pyuff's raw
    values (the file's units are mm and mN, so its mass unit is the kg and a translation
    keeps its value); each mode's kind from its dominant translation, FE y taken as body z
    (``axes = ["z", "x", "y"]``: the nodes lie along FE z)."""
    nodes = {"A": 3992, "B": 9581, "C": 9592}
    problems: list[Problem] = []
    modes = read_uff_modes(NX, nodes, ("z", "x", "y"), None, 0.5, problems)
    raw = [s for s in nx_sets() if s["type"] == 2414]
    assert [round(m.omega / (2 * math.pi), 1) for m in modes] == sorted(
        f for f, s in zip(NX_FREQUENCIES, raw, strict=True) if _dominant(s, nodes) in (0, 1))
    by_frequency = {round(s["record12_field2"], 1): s for s in raw}
    for mode in modes:
        data = by_frequency[round(mode.omega / (2 * math.pi), 1)]
        values = dict(zip(data["node_nums"], data["data_at_node"], strict=True))
        column = 2 if mode.kind is ModeKind.VERTICAL else 0  # FE y (re part at 2), FE x (at 0)
        for point, node in nodes.items():
            assert mode.shapes[point] == pytest.approx(values[node][column], rel=1e-12)
    assert modes[0].kind is ModeKind.VERTICAL and modes[0].name == "vb1"
    refused = [p for p in problems if "not a vertical or lateral mode" in p.message]
    assert len(modes) + len(refused) == len(NX_FREQUENCIES)


def _dominant(data, nodes):
    """The NX mode's dominant FE axis at the nodes (0 x, 1 y, 2 z) if it is pure, else -1."""
    values = dict(zip(data["node_nums"], data["data_at_node"], strict=True))
    squares = [sum(values[n][2 * k] ** 2 for n in nodes.values()) for k in range(3)]
    k = int(np.argmax(squares))
    return k if squares[k] >= PURITY * sum(squares) else -1


def test_torsion_from_a_file_without_rotations_is_refused():
    problems: list[Problem] = []
    modes = read_uff_modes(NX, {"A": 3992}, ("z", "x", "y"), [FEModeChoice("to1", 1, ModeKind.TORSION)], 0.5, problems)
    assert not modes
    assert "torsion needs rotations" in problems[0].message and problems[0].line is not None


# ------------------------------------------------------------------ an FE beam, read back


def free_free_fe_beam(elements: int):
    """The test's uniform car body as a free-free FE beam (Hermite elements, consistent
    mass): node positions [m] from the left end, frequencies [Hz] and the vertical
    translations of the mass-normalised modes [1/sqrt(kg)], shape (nodes, modes)."""
    stiffness, mass = hermite_matrices(elements)
    values, vectors = sl.eigh(stiffness, mass)  # eigh normalises to vectors.T M vectors = 1
    return np.arange(elements + 1) * (LENGTH / elements), np.sqrt(np.abs(values)) / (2 * math.pi), vectors[0::2]


def write_beam_uff(path: Path, length_factor: float, force_factor: float, kept: int = 6, units: bool = True):
    """The FE beam's first ``kept`` modes (rigid ones included) as datasets 164, 2411 and
    55 (normal modes, three translations), in the unit system of the factors."""
    x, f, shapes = free_free_fe_beam(48)
    mass_factor = force_factor / length_factor  # file mass per kg
    sets = []
    if units:
        sets.append(pyuff.prepare_164(units_code=1, units_description="test units", temp_mode=1,
                                      length=length_factor, force=force_factor, temp=1.0, temp_offset=273.15))
    nodes = np.arange(1, x.size + 1)
    zeros = np.zeros(x.size, dtype=int)
    sets.append(pyuff.prepare_2411(node_nums=nodes, def_cs=zeros, disp_cs=zeros, color=zeros + 1,
                                   x=x * length_factor, y=0.0 * x, z=0.0 * x))
    for k in range(kept):
        phi = shapes[:, k] / math.sqrt(mass_factor)  # a translation's value in the file's units
        sets.append(pyuff.prepare_55(model_type=1, analysis_type=2, data_ch=2, spec_data_type=8, data_type=2,
                                     n_data_per_node=3, r1=0 * phi, r2=0 * phi, r3=phi, mode_n=k + 1,
                                     freq=f[k], modal_m=1.0, modal_damp_vis=0.0, modal_damp_his=0.0,
                                     node_nums=nodes, load_case=1))
    writer = pyuff.UFF(str(path))
    writer.write_sets(sets, mode="overwrite")
    return x


def fe_model(tmp_path: Path, length_factor: float = 1.0, force_factor: float = 1.0, extra: str = "") -> str:
    """The test's beam model with its car body's modes from the FE beam's file."""
    x = write_beam_uff(tmp_path / "beam.unv", length_factor, force_factor)
    node = {p: int(np.argmin(np.abs(x - (LENGTH / 2 + offset)))) + 1 for p, offset in (("P1", 8.0), ("P2", -8.0))}
    return BEAM + f"""
[flexible.CB]
damping = 0.0
[flexible.CB.fe]
file = "beam.unv"
nodes = {{ P1 = {node["P1"]}, P2 = {node["P2"]} }}
{extra}
"""


@pytest.mark.parametrize("length_factor, force_factor, units", [
    (1.0, 1.0, "m, N, kg"),
    (1000.0, 1.0, "mm, N, t"),
    (1000.0, 1000.0, "mm, mN, kg"),
])
def test_an_fe_beam_read_back_gives_the_analytic_beams_frequencies(tmp_path, length_factor, force_factor, units):
    """The free-free FE beam (48 Hermite elements) in three unit systems, its two rigid
    modes left out (below 0.5 Hz), the first two bending modes kept (``modes``) and the
    car body on its two springs: the coupled frequencies equal those of the analytic
    free-free beam with two modes (``[flexible.CB.beam]``).  Achieved in every unit
    system: bounce and pitch 5e-9 and 3e-9 relative (asserted 2e-8), the two bending
    modes 4.6e-7 and 1.4e-6 (asserted 3e-6: the universal file's E13.5 fields carry six
    digits, and the 48-element beam).  A mass unit taken wrongly (kg for t) would scale
    the shapes by 31.6 and move the bounce by percents."""
    text = fe_model(tmp_path, length_factor, force_factor, 'modes = { vb1 = 3, vb2 = 4 }')
    path = tmp_path / "fe.toml"
    path.write_text(text, encoding="utf-8")
    found = frequencies(str(path))
    analytic = frequencies(beam_model(2))
    assert found.size == analytic.size == 4
    errors = np.abs(found - analytic) / analytic
    assert np.all(errors <= [2e-8, 2e-8, 3e-6, 3e-6]), errors


def test_without_modes_every_elastic_mode_is_kept_and_named(tmp_path):
    """No ``modes``: the four elastic modes of the six in the file, rigid ones dropped
    below ``rigid_below``, named vb1..vb4 in order of frequency."""
    path = tmp_path / "fe.toml"
    path.write_text(fe_model(tmp_path), encoding="utf-8")
    from express.io.toml_model import read_toml_model

    model = read_toml_model(path)
    names = [mode.name for mode in model.flexible[0].modes]
    assert names == ["vb1", "vb2", "vb3", "vb4"]


# ------------------------------------------------------------------ bad input


@pytest.mark.parametrize("extra, mentions", [
    ('modes = { vb1 = 99 }', "not in the file"),
    ('modes = { vb1 = { mode = 3, kind = "sideways" } }', "a mode is its FE mode number"),
    ('axes = ["x", "x", "z"]', "axes must name"),
    ('modes = { to1 = { mode = 3, kind = "torsion" } }', "torsion needs rotations"),
    ('rigid_below = "0.5 m"', "rigid_below"),
])
def test_bad_fe_modes_exit_2_and_write_nothing(tmp_path, capsys, extra, mentions):
    path = tmp_path / "fe.toml"
    path.write_text(fe_model(tmp_path, extra=extra), encoding="utf-8")
    target = tmp_path / "out.json"
    assert_input_error(capsys, "generate", path, "--format", "json", "-o", target, "--no-cache", mentions=mentions)
    assert not target.exists()


def test_a_node_missing_from_the_file_is_named_with_the_modes_line(tmp_path, capsys):
    path = tmp_path / "fe.toml"
    text = fe_model(tmp_path).replace("P2 = ", "P2 = 9000 + 0 * ")
    path.write_text(text.replace("P2 = 9000 + 0 * ", "P2 = 9000, Q = "), encoding="utf-8")
    err = assert_input_error(capsys, "eigen", path, "--no-cache", mentions="no shape at the node of P2 (node 9000)")
    assert f"{tmp_path / 'beam.unv'}:" in err


def test_a_file_without_units_or_modes_is_refused(tmp_path):
    write_beam_uff(tmp_path / "beam.unv", 1.0, 1.0, units=False)
    problems: list[Problem] = []
    assert read_uff_modes(tmp_path / "beam.unv", {"P1": 1}, ("x", "y", "z"), None, 0.5, problems) == []
    assert "no units dataset (164)" in problems[0].message
    (tmp_path / "junk.unv").write_text("not a universal file\n", encoding="utf-8")
    problems = []
    assert read_uff_modes(tmp_path / "junk.unv", {"P1": 1}, ("x", "y", "z"), None, 0.5, problems) == []
    assert problems and problems[0].file == str(tmp_path / "junk.unv")
