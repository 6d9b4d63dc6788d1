"""Exports keep the derivation (issue 10 item 5): the MATLAB/Octave and Python exports take
the given parameters and compute the derived ones (closed forms as code, Kalker's creep
coefficients through the shipped ``kalker_creep``), so that changing ``mc`` there moves
P0, f1 and f2 exactly as ``--set mc=...`` does.

The Octave checks are skipped when Octave is missing, except in CI (``octave_runner``).
"""

from __future__ import annotations

import importlib.util
import itertools
import json
import math
import subprocess
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

from express.assembly.equations import DerivationCall, DerivedParameter, EquationsOfMotion
from express.cli import main
from express.export import FORMATS
from express.export.derivation import derivation_plan, step_outputs
from express.export.kalker_code import python_kalker
from express.export.matlab import to_matlab
from express.export.python_module import to_python
from express.io import load_model
from express.model.parameters import with_values
from express.numeric.statespace import load_vehicle
from express.rail.build import generate_vehicle
from express.rail.contact import creep_coefficients
from octave_runner import assert_matrices_close, evaluate_matrices, require_octave, run_octave

ROOT = Path(__file__).resolve().parents[1]
STEERED = ROOT / "examples" / "forced-steering.toml"
CREEP = ("wheel_load", "wheel_radius", "rail_head_radius", "youngs_modulus", "poisson")
HEAVY = 60000.0  # kg: the car body of 30 t doubled


# --------------------------------------------------------------------------- records


def _given_values() -> dict[str, float]:
    return {"m": 1400.0, "J": 600.0, "g": 9.81, "v": 30.0, "b": 0.56, "r0": 0.43,
            "Rrail": 0.3, "Emod": 206e9, "nu": 0.3, "k": 4.0e6, "unused": 7.0}


def _reference(given: dict[str, float]) -> dict[str, float]:
    """The derived values by the library: P0 = m g / 2, f1, f2 from creep_coefficients."""
    values = dict(given)
    values.setdefault("P0", given["m"] * given["g"] / 2)
    creep = creep_coefficients(values["P0"], given["r0"], given["Rrail"], given["Emod"], given["nu"])
    values.setdefault("f1", creep.f11)
    values.setdefault("f2", creep.f22)
    return values


def derived_eom(steps=None) -> EquationsOfMotion:
    """A wheelset's lateral and yaw motion whose wheel load and creep coefficients are
    derived: P0 = m g / 2 and f1, f2 = Kalker(P0, r0, Rrail, Emod, nu); an unused
    derived parameter (``spare = unused*2``) too."""
    m, J, v, b, k, f1, f2, P0, g, r0, Rr, E, nu, unused = sp.symbols(
        "m J v b k f1 f2 P0 g r0 Rrail Emod nu unused")
    if steps is None:
        steps = (
            DerivedParameter("spare", 2 * unused),
            DerivedParameter("P0", m * g / 2),
            DerivationCall("kalker", "rail.creep",
                           tuple(zip(CREEP, (P0, r0, Rr, E, nu), strict=True)), (("f11", "f1"), ("f22", "f2"))),
        )
    values = _reference(_given_values())
    values["spare"] = 14.0
    return EquationsOfMotion(
        name="wheelset",
        dofs=("W1.y", "W1.rz"),
        eliminated=(),
        inputs=(),
        matrices={
            "M": sp.ImmutableMatrix([[m, 0], [0, J]]),
            "C": sp.ImmutableMatrix([[2 * f2 / v, 0], [0, 2 * b**2 * f1 / v]]),
            "K": sp.ImmutableMatrix([[k + P0 / b / 10, -2 * f2], [0, k * b**2]]),
        },
        parameters=("J", "P0", "b", "f1", "f2", "k", "m", "v"),
        values=values,
        units={"m": "kg", "P0": "N", "f1": "N", "f2": "N", "Emod": "GPa"},
        derivation=steps,
    )


def _load(path: Path, name: str):
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _module(tmp_path, eom, name="derived_module"):
    path = tmp_path / f"{name}.py"
    path.write_text(to_python(eom), encoding="utf-8")
    return _load(path, name)


# --------------------------------------------------------------------------- the plan


def test_plan_takes_the_given_parameters_and_leaves_unused_steps_out():
    plan = derivation_plan(derived_eom())
    assert plan.derived == ("P0", "f1", "f2")
    assert plan.given == ("Emod", "J", "Rrail", "b", "g", "k", "m", "nu", "r0", "v")
    assert [type(step).__name__ for step in plan.steps] == ["DerivedParameter", "DerivationCall"]


@pytest.mark.parametrize("fmt", ["json", "matlab", "python"])
def test_a_derivation_without_code_exports_its_results_as_given(fmt):
    """A kind the exports cannot write (e.g. the profiles' conicity) is left out: its
    results become given parameters with their values; a known kind called with other
    arguments is refused."""
    eom = derived_eom()
    call = eom.derivation[-1]
    odd = DerivationCall("table_lookup", "rail.creep", call.inputs, call.outputs)
    plan = derivation_plan(derived_eom(steps=(*eom.derivation[:-1], odd)))
    assert set(step_outputs(call)) & set(plan.given) and not set(step_outputs(call)) & set(plan.derived)
    assert FORMATS[fmt](derived_eom(steps=(*eom.derivation[:-1], odd)))
    short = DerivationCall("kalker", "rail.creep", call.inputs[:3], call.outputs)
    with pytest.raises(ValueError, match="takes the arguments"):
        FORMATS[fmt](derived_eom(steps=(*eom.derivation[:-1], short)))


def test_json_records_the_given_parameters_and_the_steps():
    doc = json.loads(FORMATS["json"](derived_eom()))
    assert doc["given"] == ["Emod", "J", "Rrail", "b", "g", "k", "m", "nu", "r0", "v"]
    assert doc["derivation"] == [
        {"parameter": "P0", "expression": "g*m/2"},
        {"function": "kalker", "item": "rail.creep",
         "arguments": {"wheel_load": "P0", "wheel_radius": "r0", "rail_head_radius": "Rrail",
                       "youngs_modulus": "Emod", "poisson": "nu"},
         "results": {"f11": "f1", "f22": "f2"}},
    ]


@pytest.mark.parametrize("fmt", list(FORMATS))
def test_exports_are_deterministic_with_a_derivation(fmt):
    assert FORMATS[fmt](derived_eom()).encode() == FORMATS[fmt](derived_eom()).encode()


# --------------------------------------------------------------------------- Python


def test_python_module_computes_the_derived_parameters(tmp_path):
    eom = derived_eom()
    module = _module(tmp_path, eom)
    source = to_python(eom)
    assert [ln for ln in source.splitlines() if ln.startswith(("import ", "from "))] == ["import numpy"]
    assert "sympy" not in source and "eval(" not in source
    assert derivation_plan(eom).given == module.PARAMETERS
    assert module.DERIVED == ("P0", "f1", "f2")
    assert set(module.VALUES) == set(module.PARAMETERS)  # no derived value to shadow a change
    values = module.parameter_values()
    for name, expected in _reference(module.VALUES).items():
        if name in values:
            assert values[name] == pytest.approx(expected, rel=1e-13), name
    assert_matrices_close(module.matrices(), evaluate_matrices(eom), rtol=1e-12)


@pytest.mark.parametrize("change", [{"m": 2800.0}, {"g": 9.0, "nu": 0.27}, {"Rrail": 0.6, "r0": 0.46}])
def test_python_module_follows_a_changed_given_value(tmp_path, change):
    eom = derived_eom()
    module = _module(tmp_path, eom)
    given = {**module.VALUES, **change}
    expected = _reference(given)
    values = module.parameter_values(given)
    assert values["P0"] == pytest.approx(given["m"] * given["g"] / 2, rel=1e-15)  # closed form
    for name in ("f1", "f2"):
        assert values[name] == pytest.approx(expected[name], rel=1e-12)
    assert_matrices_close(module.matrices(given), evaluate_matrices(eom, expected), rtol=1e-12)


@pytest.mark.parametrize("explicit", [{"f1": 5.0e6}, {"P0": 40e3}, {"P0": 40e3, "f1": 1e6, "f2": 2e6}])
def test_python_module_uses_a_derived_value_given_explicitly(tmp_path, explicit):
    eom = derived_eom()
    module = _module(tmp_path, eom)
    given = {**module.VALUES, **explicit}
    expected = _reference(given)  # a given P0 feeds Kalker; a given f1 stays
    values = module.parameter_values(given)
    for name in ("P0", "f1", "f2"):
        assert values[name] == pytest.approx(expected[name], rel=1e-12), name
    assert_matrices_close(module.matrices(given), evaluate_matrices(eom, expected), rtol=1e-12)


def test_python_module_missing_given_value(tmp_path):
    module = _module(tmp_path, derived_eom())
    partial = {k: v for k, v in module.VALUES.items() if k != "Emod"}
    with pytest.raises(KeyError, match="missing parameter\\(s\\) Emod"):
        module.matrices(partial)


# --------------------------------------------------------------------------- Kalker


def _kalker_inputs():
    """Wheel loads, radii, moduli and Poisson's ratios over the usual range and beyond:
    round contacts, slender ellipses on both sides (Kalker's asymptotes), nu at and
    between the table's nodes."""
    loads = (2e3, 50e3, 150e3)
    radii = ((0.43, 0.3), (0.46, 0.08), (0.5, 0.5), (0.3, 10.0), (0.4, 400.0), (8.0, 0.01), (0.45, 0.2999))
    materials = ((206e9, 0.3), (210e9, 0.0), (70e9, 0.25), (206e9, 0.5), (110e9, 0.07))
    return [(n, r, R, E, nu) for n, (r, R), (E, nu) in itertools.product(loads, radii, materials)]


def test_shipped_kalker_function_agrees_with_the_library():
    namespace = {"numpy": np}
    exec(compile(python_kalker(), "kalker_creep", "exec"), namespace)  # the module's own code
    kalker = namespace["kalker_creep"]
    for arguments in _kalker_inputs():
        f11, f22 = kalker(*arguments)
        reference = creep_coefficients(*arguments)
        assert f11 == pytest.approx(reference.f11, rel=1e-12), arguments
        assert f22 == pytest.approx(reference.f22, rel=1e-12), arguments


@pytest.mark.parametrize(
    "arguments, message",
    [((0.0, 0.43, 0.3, 206e9, 0.3), "wheel_load"), ((5e4, -0.43, 0.3, 206e9, 0.3), "wheel_radius"),
     ((5e4, 0.43, 0.3, math.inf, 0.3), "youngs_modulus"), ((5e4, 0.43, 0.3, 206e9, 0.6), "poisson"),
     ((5e4, 0.43, 1e30, 206e9, 0.3), "too small")],
)
def test_shipped_kalker_function_refuses_bad_input(arguments, message):
    namespace = {"numpy": np}
    exec(compile(python_kalker(), "kalker_creep", "exec"), namespace)
    with pytest.raises(ValueError, match=message):
        namespace["kalker_creep"](*arguments)
    with pytest.raises(ValueError):
        creep_coefficients(*arguments)  # the library refuses the same input


# --------------------------------------------------------------------------- the bundled car


@pytest.fixture(scope="module")
def steered_equations():
    return generate_vehicle(load_model(STEERED)).equations


@pytest.fixture(scope="module")
def heavy_vehicle():
    return load_vehicle(STEERED, {"mc": HEAVY})


def test_python_export_of_the_car_follows_mc_like_load_vehicle(tmp_path, steered_equations, heavy_vehicle):
    """``matrices({**VALUES, "mc": 60e3})`` gives the matrices of
    ``load_vehicle(..., {"mc": 60000})`` and its P0, f1, f2, to 1e-9 relative."""
    module = _module(tmp_path, steered_equations, "steered_module")
    assert {"P0", "f1", "f2"} <= set(module.DERIVED) and "mc" in module.PARAMETERS
    given = {**module.VALUES, "mc": HEAVY}
    values = module.parameter_values(given)
    for name in ("P0", "f1", "f2"):
        assert values[name] == pytest.approx(heavy_vehicle.values[name], rel=1e-9), name
    mc, mt, mw, g = (given[k] for k in ("mc", "mt", "mw", "g"))
    assert values["P0"] == pytest.approx((mc + 2 * mt + 4 * mw) * g / 8, rel=1e-15)
    light = module.parameter_values()
    assert values["f1"] == pytest.approx(light["f1"] * (values["P0"] / light["P0"]) ** (2 / 3), rel=1e-6)
    got = module.matrices(given)
    v = given["v"]
    expected = {"M": heavy_vehicle.mass, "K": heavy_vehicle.stiffness, "C": heavy_vehicle.damping(v),
                "P": heavy_vehicle.forcing(v), "Pd": heavy_vehicle.forcing_rate(v)}
    assert_matrices_close(got, expected, rtol=1e-9)


def test_a_wheel_load_given_on_the_command_line_is_a_given_parameter(tmp_path, capsys):
    """``--set P0=...`` makes P0 given: the module takes it and derives only f1, f2."""
    target = tmp_path / "fixed_load.py"
    assert main(["generate", str(STEERED), "--set", "P0=40 kN", "--format", "python", "-o", str(target)]) == 0
    module = _load(target, "fixed_load")
    assert "P0" in module.PARAMETERS and module.DERIVED == ("f1", "f2")
    assert module.VALUES["P0"] == 40e3
    values = module.parameter_values({**module.VALUES, "mc": HEAVY})
    assert values["f1"] == pytest.approx(creep_coefficients(40e3, 0.43, 0.3, 206e9, 0.3).f11, rel=1e-12)


# --------------------------------------------------------------------------- Octave


@pytest.fixture(scope="module")
def octave():
    return require_octave()


def test_octave_export_of_the_car_follows_mc_like_generate_set(tmp_path, octave, capsys):
    """The ``.m`` file of ``express generate``, run in Octave with mc = 60 t, gives the
    P0, f1, f2 and matrices of ``express generate --set mc=60000`` to 1e-9."""
    mfile = tmp_path / "forced_steering.m"
    assert main(["generate", str(STEERED), "--format", "matlab", "-o", str(mfile)]) == 0
    heavy_json = tmp_path / "heavy.json"
    assert main(["generate", str(STEERED), "--set", f"mc={HEAVY}", "--format", "json", "-o", str(heavy_json)]) == 0
    heavy = json.loads(heavy_json.read_text(encoding="utf-8"))
    light_equations = generate_vehicle(load_model(STEERED)).equations
    given = {name: light_equations.values[name] for name in derivation_plan(light_equations).given}
    got = run_octave(mfile, {**given, "mc": HEAVY}, octave=octave)
    for name in ("P0", "f1", "f2", "mc"):
        assert got[f"values.{name}"][0, 0] == pytest.approx(heavy["values"][name], rel=1e-9), name
    heavy_equations = generate_vehicle(with_values(load_model(STEERED), {"mc": HEAVY})).equations
    matrices = {key: value for key, value in got.items() if not key.startswith("values.")}
    assert_matrices_close(matrices, evaluate_matrices(heavy_equations), rtol=1e-9)
    text = mfile.read_text(encoding="utf-8")
    assert "p.P0 =" not in text and "p.f1 =" not in text  # derived: not in the defaults
    assert "function [f11, f22] = kalker_creep(" in text


def test_octave_export_uses_a_derived_value_given_explicitly(tmp_path, octave):
    eom = derived_eom()
    mfile = tmp_path / "wheelset.m"
    mfile.write_text(to_matlab(eom), encoding="utf-8")
    given = {name: eom.values[name] for name in derivation_plan(eom).given}
    for explicit in ({}, {"f1": 5.0e6}, {"P0": 40e3}, {"m": 2000.0, "nu": 0.27}):
        expected = _reference({**given, **explicit})
        got = run_octave(mfile, {**given, **explicit}, octave=octave)
        for name in ("P0", "f1", "f2"):
            assert got[f"values.{name}"][0, 0] == pytest.approx(expected[name], rel=1e-12), (explicit, name)
        matrices = {key: value for key, value in got.items() if not key.startswith("values.")}
        assert_matrices_close(matrices, evaluate_matrices(eom, expected), rtol=1e-12)


def _kalker_probe() -> EquationsOfMotion:
    """A record whose matrices are f1 and f2 themselves, all Kalker inputs given."""
    f1, f2, P0, r0, Rr, E, nu = sp.symbols("f1 f2 P0 r0 Rrail Emod nu")
    call = DerivationCall("kalker", "rail.creep", tuple(zip(CREEP, (P0, r0, Rr, E, nu), strict=True)),
                          (("f11", "f1"), ("f22", "f2")))
    return EquationsOfMotion(
        name="kalker_probe", dofs=("B1.y",), eliminated=(), inputs=(),
        matrices={"M": sp.ImmutableMatrix([[f1]]), "C": sp.ImmutableMatrix([[f2]]),
                  "K": sp.ImmutableMatrix([[1]])},
        parameters=("f1", "f2"), derivation=(call,),
    )


def test_octave_kalker_function_agrees_with_the_library(tmp_path, octave):
    """Every input of the grid in one Octave session: f11, f22 to 1e-12 relative."""
    mfile = tmp_path / "kalker_probe.m"
    mfile.write_text(to_matlab(_kalker_probe()), encoding="utf-8")
    grid = _kalker_inputs()
    lines = [f"addpath('{tmp_path}');"]
    for n, r, R, E, nu in grid:
        lines.append(f"[M, C] = kalker_probe(struct('P0', {n!r}, 'r0', {r!r}, 'Rrail', {R!r}, "
                     f"'Emod', {E!r}, 'nu', {nu!r})); fprintf('%.17g %.17g\\n', M, C);")
    driver = tmp_path / "driver.m"
    driver.write_text("\n".join(lines) + "\n", encoding="utf-8")
    proc = subprocess.run([octave, "--no-gui", "--norc", "--quiet", "--no-window-system",
                           "--eval", f"source('{driver}')"], capture_output=True, text=True,
                          timeout=300, cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    rows = [tuple(float(x) for x in line.split()) for line in proc.stdout.split("\n") if line.strip()]
    assert len(rows) == len(grid)
    for arguments, (f11, f22) in zip(grid, rows, strict=True):
        reference = creep_coefficients(*arguments)
        assert f11 == pytest.approx(reference.f11, rel=1e-12), arguments
        assert f22 == pytest.approx(reference.f22, rel=1e-12), arguments


def test_octave_kalker_function_refuses_bad_input(tmp_path, octave):
    mfile = tmp_path / "kalker_probe.m"
    mfile.write_text(to_matlab(_kalker_probe()), encoding="utf-8")
    values = {"P0": 5e4, "r0": 0.43, "Rrail": 0.3, "Emod": 206e9, "nu": 0.7}
    with pytest.raises(RuntimeError, match="poisson must lie in"):
        run_octave(mfile, values, octave=octave)
