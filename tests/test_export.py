"""Tests of the exporters (``express.export``) on hand-built records.

The records (:func:`lever_eom`, :func:`inputs_eom`, :func:`chain_eom`,
:func:`keyword_eom`) are importable by other test modules.
"""

from __future__ import annotations

import hashlib
import importlib.util
import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

from express.assembly.equations import EquationsOfMotion
from express.export import FORMATS, SUFFIXES, default_suffix
from express.export.json_export import dense_rows, matrix_entries, matrix_items, to_json
from express.export.latex import MAX_MATRIX_ROWS, latex_dof_name, latex_symbol_name, to_latex
from express.export.matlab import is_matlab_identifier, matlab_local_names, to_matlab
from express.export.python_module import to_python
from express.export.text import to_text
from octave_runner import assert_matrices_close, evaluate_matrices

SRC = Path(__file__).resolve().parents[1] / "src"
TESTS = Path(__file__).resolve().parent


# --------------------------------------------------------------------------- records


def lever_eom() -> EquationsOfMotion:
    """The paper's two-DOF lever after elimination of the pin (conventions.md)."""
    J1, J2, b, c, kLL, kLU, lLL, lLU, m = sp.symbols("J1 J2 b c kLL kLU lLL lLU m")
    k12 = b * (kLU * lLU - kLL * lLL)
    return EquationsOfMotion(
        name="lever",
        dofs=("B1.rz", "B2.ry"),
        eliminated=("B2.x",),
        inputs=(),
        matrices={
            "M": sp.ImmutableMatrix([[J1 + b**2 * m, 0], [0, J2]]),
            "C": sp.ImmutableMatrix([[b**2 * c, 0], [0, 0]]),
            "K": sp.ImmutableMatrix(
                [[b**2 * (kLL + kLU), k12], [k12, kLL * lLL**2 + kLU * lLU**2]]
            ),
        },
        parameters=("J1", "J2", "b", "c", "kLL", "kLU", "lLL", "lLU", "m"),
        values={"J1": 12.5, "J2": 3.25, "b": 0.35, "c": 1.5e3, "kLL": 2.0e5,
                "kLU": 3.1e5, "lLL": 0.42, "lLU": 0.61, "m": 17.0},
        units={"J1": "kg m^2", "J2": "kg m^2", "b": "m", "c": "N s/m", "kLL": "N/m",
               "kLU": "N/m", "lLL": "m", "lLU": "m", "m": "kg"},
    )


def inputs_eom() -> EquationsOfMotion:
    """Inputs, P/Pd, a further matrix, awkward parameter names and assumptions."""
    names = ("E", "Gamma", "M", "c1", "end", "k_y", "p", "p_M", "rho_B1", "zeros")
    E, Gamma, M, c1, end, k_y, p, p_M, rho_B1, zeros = sp.symbols(names, positive=True)
    half = sp.Rational(1, 2)
    return EquationsOfMotion(
        name="with_inputs",
        dofs=("B1.y", "B1.rz", "W1.y"),
        eliminated=(),
        inputs=("G1.y", "yR1"),
        matrices={
            "M": sp.ImmutableMatrix(
                [[M, 0, 0], [0, sp.Rational(1, 12) * M * p_M**2 + end, 0], [0, 0, zeros]]
            ),
            "C": sp.ImmutableMatrix(
                [[2 * c1, -c1 * p, 0], [-c1 * p, c1 * p**2, 0], [0, 0, c1 * half]]
            ),
            "K": sp.ImmutableMatrix(
                [[k_y, 0, -k_y], [0, E * sp.sqrt(k_y), Gamma], [-k_y, 0, k_y + rho_B1]]
            ),
            "P": sp.ImmutableMatrix([[k_y, 0], [0, Gamma * p], [0, sp.Float(0.25) * rho_B1]]),
            "Pd": sp.ImmutableMatrix([[c1, 0], [0, 0], [0, 0]]),
            "G": sp.ImmutableMatrix([[1, 0, 0], [0, 0, 0], [0, 0, sp.Rational(3, 2) * E]]),
        },
        parameters=names,
        values={"E": 2.1e11, "Gamma": 0.15, "M": 1200.0, "c1": 4.0e3, "end": 7.5,
                "k_y": 1.0e6, "p": 1.25, "p_M": 0.8, "rho_B1": 1.0 / 3.0, "zeros": 900.0},
        units={"E": "N/m^2", "M": "kg", "zeros": "kg"},
    )


def chain_eom(n: int = 25) -> EquationsOfMotion:
    """A sparse chain of ``n`` bodies joined by springs (wide matrices)."""
    m, k, c = sp.symbols("m k c")
    K = sp.zeros(n, n)
    for i in range(n):
        K[i, i] = 2 * k
        if i + 1 < n:
            K[i, i + 1] = K[i + 1, i] = -k
    return EquationsOfMotion(
        name="chain",
        dofs=tuple(f"B{i + 1}.y" for i in range(n)),
        eliminated=(),
        inputs=(),
        matrices={
            "M": sp.ImmutableMatrix(sp.eye(n) * m),
            "C": sp.ImmutableMatrix(sp.eye(n) * c),
            "K": sp.ImmutableMatrix(K),
        },
        parameters=("c", "k", "m"),
        values={"c": 10.0, "k": 1.0e4, "m": 2.0},
    )


def keyword_eom() -> EquationsOfMotion:
    """Parameter names that are Python keywords or builtins used by the module."""
    names = ("abs", "class", "float", "lambda", "numpy")
    a, cl, fl, lam, npy = sp.symbols(names)
    return EquationsOfMotion(
        name="keywords",
        dofs=("B1.x",),
        eliminated=(),
        inputs=(),
        matrices={
            "M": sp.ImmutableMatrix([[a + cl]]),
            "C": sp.ImmutableMatrix([[fl * lam]]),
            "K": sp.ImmutableMatrix([[npy**2]]),
        },
        parameters=names,
        values={"abs": 1.0, "class": 2.0, "float": 3.0, "lambda": 4.0, "numpy": 5.0},
    )


RECORDS = {"lever": lever_eom, "inputs": inputs_eom, "chain": chain_eom}


def _parse(text: str, parameters) -> sp.Expr:
    local = {name: sp.Symbol(name) for name in parameters}
    return sp.parse_expr(text, local_dict=local)


def _plain(expr: sp.Expr) -> sp.Expr:
    """Replace symbols by assumption-free symbols of the same name."""
    return sp.sympify(expr).xreplace({s: sp.Symbol(s.name) for s in sp.sympify(expr).free_symbols})


def _load_module(path: Path, name: str):
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


# --------------------------------------------------------------------------- registry


def test_formats_and_suffixes():
    assert list(FORMATS) == ["json", "matlab", "python", "latex", "text"]
    assert SUFFIXES == {"json": ".json", "matlab": ".m", "python": ".py", "latex": ".tex",
                        "text": ".txt"}
    assert default_suffix("matlab") == ".m"
    with pytest.raises(ValueError, match="unknown export format"):
        default_suffix("xml")


# --------------------------------------------------------------------------- all formats


@pytest.mark.parametrize("record", sorted(RECORDS))
@pytest.mark.parametrize("fmt", list(FORMATS))
def test_deterministic(fmt, record):
    first = FORMATS[fmt](RECORDS[record]())
    second = FORMATS[fmt](RECORDS[record]())
    assert isinstance(first, str) and first.endswith("\n")
    assert first.encode() == second.encode()


def test_same_bytes_across_hash_seeds():
    code = (
        "import hashlib, test_export\n"
        "from express.export import FORMATS\n"
        "for r in sorted(test_export.RECORDS):\n"
        "    for f, fn in FORMATS.items():\n"
        "        out = fn(test_export.RECORDS[r]())\n"
        "        print(r, f, hashlib.sha256(out.encode()).hexdigest())\n"
    )
    outputs = []
    for seed in ("1", "12345"):
        env = dict(os.environ, PYTHONHASHSEED=seed,
                   PYTHONPATH=os.pathsep.join([str(SRC), str(TESTS)]))
        proc = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True,
                              text=True, check=True, timeout=600)
        outputs.append(proc.stdout)
    assert outputs[0] == outputs[1]
    here = "".join(
        f"{r} {f} {hashlib.sha256(fn(RECORDS[r]()).encode()).hexdigest()}\n"
        for r in sorted(RECORDS) for f, fn in FORMATS.items()
    )
    assert outputs[0] == here


@pytest.mark.parametrize("fmt", list(FORMATS))
def test_bad_shapes_rejected(fmt):
    eom = lever_eom()
    bad = dict(eom.matrices, C=sp.ImmutableMatrix([[1, 2, 3]]))
    with pytest.raises(ValueError, match="matrix C has shape"):
        FORMATS[fmt](EquationsOfMotion(eom.name, eom.dofs, eom.eliminated, eom.inputs, bad,
                                       eom.parameters, eom.values, eom.units))
    with pytest.raises(ValueError, match="not listed in parameters"):
        FORMATS[fmt](EquationsOfMotion(eom.name, eom.dofs, eom.eliminated, eom.inputs,
                                       eom.matrices, eom.parameters[1:], eom.values))


def test_matrix_items_order_and_shapes():
    assert [k for k, _ in matrix_items(inputs_eom())] == ["M", "C", "K", "P", "Pd", "G"]
    eom = inputs_eom()
    with pytest.raises(ValueError, match="matrix P has shape"):
        matrix_items(EquationsOfMotion(eom.name, eom.dofs, eom.eliminated, ("G1.y",),
                                       eom.matrices, eom.parameters))
    lever = lever_eom()
    empty = dict(lever.matrices, P=sp.ImmutableMatrix(2, 0, []), Pd=sp.ImmutableMatrix(2, 0, []))
    record = EquationsOfMotion(lever.name, lever.dofs, lever.eliminated, (), empty,
                               lever.parameters)
    assert [k for k, _ in matrix_items(record)] == ["M", "C", "K"]


# --------------------------------------------------------------------------- JSON


#: The lever's matrices as JSON version 1 wrote them (dense rows), for the readers.
LEVER_V1 = {
    "M": [["J1 + b**2*m", "0"], ["0", "J2"]],
    "C": [["b**2*c", "0"], ["0", "0"]],
    "K": [["b**2*(kLL + kLU)", "b*(-kLL*lLL + kLU*lLU)"],
          ["b*(-kLL*lLL + kLU*lLU)", "kLL*lLL**2 + kLU*lLU**2"]],
}


def test_json_lever_contract():
    """Version 2 (format change, conventions.md): the keys in order, matrices as their
    non-zero entries [i, j, text], 0-based and row-major, one entry per line."""
    text = to_json(lever_eom())
    doc = json.loads(text)
    assert list(doc) == ["format", "version", "dofs", "eliminated", "parameters", "M", "C", "K",
                         "values", "units", "given", "derivation"]
    assert doc["format"] == "express-equations" and doc["version"] == 2
    assert doc["dofs"] == ["B1.rz", "B2.ry"]
    assert doc["eliminated"] == ["B2.x"]
    assert doc["parameters"] == ["J1", "J2", "b", "c", "kLL", "kLU", "lLL", "lLU", "m"]
    assert doc["M"] == {"shape": [2, 2], "entries": [[0, 0, "J1 + b**2*m"], [1, 1, "J2"]]}
    assert doc["C"] == {"shape": [2, 2], "entries": [[0, 0, "b**2*c"]]}
    assert doc["values"]["kLU"] == 3.1e5 and doc["units"]["J1"] == "kg m^2"
    assert doc["given"] == doc["parameters"] and doc["derivation"] == []
    lines = text.splitlines()
    assert '      [0, 0, "J1 + b**2*m"],' in lines and '      [1, 1, "J2"]' in lines
    assert text.endswith("}\n") and '"0"' not in text


@pytest.mark.parametrize("key", ["M", "C", "K"])
def test_json_dense_rows_read_both_versions(key):
    """The dense form stays readable: ``dense_rows`` gives the version 1 rows from a
    version 2 document and passes version 1 rows through."""
    doc = json.loads(to_json(lever_eom()))
    assert dense_rows(doc[key]) == LEVER_V1[key]
    assert dense_rows(LEVER_V1[key]) == LEVER_V1[key]


@pytest.mark.parametrize("bad", [{"shape": [2, 2]}, {"entries": []}, "K",
                                 {"shape": [1, 1], "entries": [[1, 0, "a"]]}])
def test_json_dense_rows_rejects_other_forms(bad):
    with pytest.raises(ValueError):
        dense_rows(bad)


def test_json_writes_only_non_zero_entries():
    """A 60-body chain: K has 60 + 2*59 entries in the file, no zeros; the size
    follows the non-zero entries (a 120-body chain is about twice as large)."""
    doc = json.loads(to_json(chain_eom(60)))
    assert doc["K"]["shape"] == [60, 60] and len(doc["K"]["entries"]) == 60 + 2 * 59
    assert len(doc["M"]["entries"]) == 60
    assert all(text != "0" for _, _, text in doc["K"]["entries"])
    assert [e[:2] for e in doc["K"]["entries"]] == sorted(e[:2] for e in doc["K"]["entries"])
    small, large = len(to_json(chain_eom(60))), len(to_json(chain_eom(120)))
    assert 1.8 < large / small < 2.2


def test_json_inputs_key_order():
    doc = json.loads(to_json(inputs_eom()))
    assert list(doc) == ["format", "version", "dofs", "eliminated", "parameters", "M", "C", "K",
                         "inputs", "P", "Pd", "G", "values", "units", "given", "derivation"]
    assert doc["inputs"] == ["G1.y", "yR1"]
    assert doc["P"]["shape"] == [3, 2]
    assert len(dense_rows(doc["P"])) == 3 and all(len(row) == 2 for row in dense_rows(doc["P"]))
    assert list(doc["values"]) == sorted(doc["values"])


def test_json_inputs_without_input_matrices():
    lever = lever_eom()
    record = EquationsOfMotion(lever.name, lever.dofs, lever.eliminated, ("G1.x",),
                               lever.matrices, lever.parameters)
    doc = json.loads(to_json(record))
    assert list(doc) == ["format", "version", "dofs", "eliminated", "parameters", "M", "C", "K",
                         "inputs", "values", "units", "given", "derivation"]


def test_json_refuses_a_matrix_named_like_a_key():
    lever = lever_eom()
    record = EquationsOfMotion(lever.name, lever.dofs, lever.eliminated, (),
                               dict(lever.matrices, values=sp.ImmutableMatrix([[1, 0], [0, 1]])),
                               lever.parameters)
    with pytest.raises(ValueError, match="'values' is a key of the JSON document"):
        to_json(record)


@pytest.mark.parametrize("record", sorted(RECORDS))
def test_json_round_trip(record):
    eom = RECORDS[record]()
    doc = json.loads(to_json(eom))
    for key, mat in eom.matrices.items():
        rows = dense_rows(doc[key])
        assert len(rows) == mat.rows and all(len(row) == mat.cols for row in rows)
        for i in range(mat.rows):
            for j in range(mat.cols):
                back = _parse(rows[i][j], doc["parameters"])
                assert sp.simplify(back - _plain(mat[i, j])) == 0, (key, i, j, rows[i][j])


@pytest.mark.parametrize("record", [*sorted(RECORDS), "keywords", "units"])
@pytest.mark.parametrize("fmt", list(FORMATS))
def test_sparse_matrices_give_the_same_bytes(fmt, record):
    """Records holding SymPy sparse matrices (entries keyed by DOF pair) export to the
    very same text as with dense ones."""
    eom = {"keywords": keyword_eom, "units": units_eom, **RECORDS}[record]()
    sparse = {key: sp.ImmutableSparseMatrix(mat) for key, mat in eom.matrices.items()}
    record_sparse = EquationsOfMotion(eom.name, eom.dofs, eom.eliminated, eom.inputs, sparse,
                                      eom.parameters, eom.values, eom.units)
    assert FORMATS[fmt](record_sparse) == FORMATS[fmt](eom)


def test_matrix_entries_row_major_non_zeros():
    K = sp.ImmutableSparseMatrix(3, 3, {(2, 0): sp.Symbol("a"), (0, 2): 2, (1, 1): sp.Symbol("b")})
    assert matrix_entries(K) == [(0, 2, 2), (1, 1, sp.Symbol("b")), (2, 0, sp.Symbol("a"))]
    assert matrix_entries(sp.ImmutableMatrix(sp.zeros(4, 4))) == []


def test_json_rejects_non_finite_value():
    eom = lever_eom()
    values = dict(eom.values, m=float("nan"))
    with pytest.raises(ValueError, match="non-finite"):
        to_json(EquationsOfMotion(eom.name, eom.dofs, eom.eliminated, eom.inputs,
                                  eom.matrices, eom.parameters, values))


# --------------------------------------------------------------------------- Python


@pytest.mark.parametrize("record", [*sorted(RECORDS), "keywords"])
def test_python_module_matches_sympy(tmp_path, record):
    eom = keyword_eom() if record == "keywords" else RECORDS[record]()
    source = to_python(eom)
    assert "sympy" not in source and "eval(" not in source and "exec(" not in source
    imports = [ln for ln in source.splitlines() if ln.startswith(("import ", "from "))]
    assert imports == ["import numpy"]
    path = tmp_path / f"eom_{record}.py"
    path.write_text(source, encoding="utf-8")
    module = _load_module(path, f"eom_{record}")
    assert eom.dofs == module.DOFS
    assert eom.inputs == module.INPUTS
    assert eom.parameters == module.PARAMETERS
    assert eom.values == module.VALUES
    assert tuple(k for k, _ in matrix_items(eom)) == module.MATRICES
    expected = evaluate_matrices(eom)
    got = module.matrices()
    assert all(isinstance(a, np.ndarray) and a.dtype == float for a in got.values())
    assert_matrices_close(got, expected)
    other = {name: 1.0 + 0.1 * k for k, name in enumerate(eom.parameters)}
    assert_matrices_close(module.matrices(other), evaluate_matrices(eom, other))


def test_python_module_missing_values(tmp_path):
    eom = lever_eom()
    values = {k: v for k, v in eom.values.items() if k not in ("b", "m")}
    record = EquationsOfMotion(eom.name, eom.dofs, eom.eliminated, eom.inputs, eom.matrices,
                               eom.parameters, values)
    path = tmp_path / "partial.py"
    path.write_text(to_python(record), encoding="utf-8")
    module = _load_module(path, "partial")
    with pytest.raises(KeyError, match="no default value for parameter\\(s\\) b, m"):
        module.matrices()
    with pytest.raises(KeyError, match="missing parameter\\(s\\) b, m"):
        module.matrices(values)
    got = module.matrices({**values, "b": 0.5, "m": 2.0})
    assert got["M"][0, 0] == pytest.approx(values["J1"] + 0.25 * 2.0, rel=1e-15)


def test_python_renames_unsafe_parameters():
    source = to_python(keyword_eom())
    assert "p_lambda = float(p['lambda'])" in source
    assert "p_class = float(p['class'])" in source
    assert "p_float = float(p['float'])" in source
    assert "p_numpy = float(p['numpy'])" in source
    source = to_python(inputs_eom())
    assert "p_M_ = float(p['M'])" in source and "p_M = float(p['p_M'])" in source


# --------------------------------------------------------------------------- MATLAB


@pytest.mark.parametrize("name", ["1abc", "a-b", "end", "_x", "x" * 64, "", "café", "a b"])
def test_matlab_rejects_bad_names(name):
    assert not is_matlab_identifier(name)
    with pytest.raises(ValueError, match="not a valid MATLAB function name"):
        to_matlab(lever_eom(), name)


def test_matlab_name_default_and_explicit():
    assert to_matlab(lever_eom()).startswith("function [M, C, K] = lever(p)\n")
    long = "a" + "b" * 62
    assert to_matlab(lever_eom(), long).startswith(f"function [M, C, K] = {long}(p)\n")
    eom = lever_eom()
    bad = EquationsOfMotion("my-model", eom.dofs, eom.eliminated, eom.inputs, eom.matrices,
                            eom.parameters)
    with pytest.raises(ValueError):
        to_matlab(bad)
    assert to_matlab(bad, "my_model").startswith("function [M, C, K] = my_model(p)")


def test_matlab_lever_layout():
    text = to_matlab(lever_eom())
    lines = text.splitlines()
    assert "Generated by EXPRESS" in text
    assert "B1.rz" in text and "B2.ry" in text and "kg m^2" in text
    assert "kLU = p.kLU;" in lines
    assert "K = zeros(2, 2);" in lines
    assert "K(2, 1) = K(1, 2);" in lines
    assert "C(1, 1) = b.^2.*c;" in lines
    assert not any(ln.startswith("C(2, 2)") for ln in lines)  # zero entries are skipped
    assert text.count("\nfunction") == 0  # a single function, no subfunctions


def test_matlab_inputs_and_safe_names():
    text = to_matlab(inputs_eom())
    lines = text.splitlines()
    assert lines[0] == "function [M, C, K, P, Pd, G] = with_inputs(p)"
    assert "G1.y" in text and "yR1" in text
    assert "p_M_ = p.M;" in lines
    assert "p_M = p.p_M;" in lines
    assert "p_end = p.('end');" in lines
    assert "p_p = p.p;" in lines
    assert "p_zeros = p.zeros;" in lines
    assert "M(1, 1) = p_M_;" in lines
    assert "P(3, 3)" not in text
    assert "P(3, 2) = 0.25*rho_B1;" in lines
    assert "K(3, 1) = K(1, 3);" in lines and "K(3, 2)" not in text  # K is not symmetric


def test_matlab_local_names_deterministic():
    names = ("M", "end", "p", "p_M", "sqrt", "x", "Pd")
    first = matlab_local_names(names, ["M", "C", "K", "P", "Pd"])
    assert first == {"M": "p_M_", "end": "p_end", "p": "p_p", "p_M": "p_M",
                     "sqrt": "p_sqrt", "x": "x", "Pd": "p_Pd"}
    assert matlab_local_names(names, ["M", "C", "K", "P", "Pd"]) == first
    long = "a" * 62 + "M"
    got = matlab_local_names(["end", long, "p_" + long[:61]], [])
    assert all(len(v) <= 63 for v in got.values()) and len(set(got.values())) == 3


def test_matlab_sparse_lines():
    text = to_matlab(chain_eom(40))
    lines = text.splitlines()
    assert "K = zeros(40, 40);" in lines
    k_lines = [ln for ln in lines if ln.startswith("K(")]
    assert len(k_lines) == 40 + 2 * 39
    assert "K(40, 39) = K(39, 40);" in lines


# --------------------------------------------------------------------------- LaTeX


@pytest.mark.parametrize(
    "name, tex",
    [("kLU", "k_{LU}"), ("lLL", "l_{LL}"), ("J1", "J_{1}"), ("f11", "f_{11}"),
     ("Gamma", r"\Gamma"), ("Icz", "I_{cz}"), ("m", "m"), ("alpha", r"\alpha"),
     ("rho_B1", r"\rho_{B1}"), ("rhoB1", r"\rho_{B1}"), ("theta2", r"\theta_{2}"),
     ("S_B1", "S_{B1}"), ("pitch", "p_{itch}"), ("k_a_b", "k_{a,b}")],
)
def test_latex_symbol_names(name, tex):
    assert latex_symbol_name(name) == tex


def test_latex_dof_names():
    assert latex_dof_name("B1.rz") == r"\mathrm{B1}.r_{z}"
    assert latex_dof_name("W1.y") == r"\mathrm{W1}.y"
    assert latex_dof_name("G_1.x") == r"\mathrm{G\_1}.x"


def test_latex_lever():
    text = to_latex(lever_eom())
    assert r"\documentclass" not in text and r"\begin{document}" not in text
    assert "k_{LU}" in text and "l_{LL}" in text and "J_{1}" in text
    assert r"\begin{bmatrix}" in text and r"\begin{equation*}" in text
    assert r"\mathrm{B1}.r_{z} & \mathrm{B2}.r_{y}" in text
    assert text.count(r"\begin{bmatrix}") == text.count(r"\end{bmatrix}") == 4
    assert text.count(r"\begin{equation*}") == text.count(r"\end{equation*}")


def test_latex_inputs():
    text = to_latex(inputs_eom())
    assert r"P_{d} =" in text and r"\Gamma" in text and "u =" in text
    assert r"\dot{u}" in text


def test_latex_wide_matrices_are_split():
    text = to_latex(chain_eom(45))
    assert "columns 1-20 of 45" in text and "columns 41-45 of 45" in text
    rows = [ln for ln in text.splitlines() if ln.startswith("  ") and "&" in ln]
    assert rows and max(ln.count("&") for ln in rows) == 19
    assert r"\setcounter{MaxMatrixCols}{20}" in text


# --------------------------------------------------------------------------- text


def test_text_lever():
    text = to_text(lever_eom())
    assert "B1.rz" in text and "B2.ry" in text and "B2.x" in text
    assert "K[B1.rz, B2.ry] = b*(-kLL*lLL + kLU*lLU)" in text
    assert "K[B2.ry, B1.rz]" not in text
    assert "K (2 x 2), symmetric: upper triangle shown" in text
    assert "C[B2.ry, B2.ry]" not in text


def test_text_inputs():
    text = to_text(inputs_eom())
    assert "P[B1.y, G1.y] = k_y" in text
    assert "Pd[B1.y, G1.y] = c1" in text
    assert "K[W1.y, B1.y] = -k_y" in text  # K is not symmetric: full listing
    assert "K (3 x 3)\n" in text
    assert "G[B1.y, B1.y] = 1" in text


# ---------------------------------------------------------- values shown in the unit written


def units_eom() -> EquationsOfMotion:
    """Values in SI with the units a model file used (issue 10: ``cx1 = 15 kN*s/m``)."""
    cx1, mc, v, Gamma = sp.symbols("cx1 mc v Gamma")
    return EquationsOfMotion(
        name="units",
        dofs=("B1.x",),
        eliminated=(),
        inputs=(),
        matrices={
            "M": sp.ImmutableMatrix([[mc]]),
            "C": sp.ImmutableMatrix([[cx1 + Gamma / v]]),
            "K": sp.ImmutableMatrix([[0]]),
        },
        parameters=("Gamma", "cx1", "mc", "v"),
        values={"Gamma": 0.1, "cx1": 15000.0, "mc": 30000.0, "v": 100 / 3.6},
        units={"Gamma": "1", "cx1": "kN*s/m", "mc": "t", "v": "km/h"},
    )


@pytest.mark.parametrize(
    ("exporter", "template"),
    [
        (to_text, "  {name} = {shown}"),
        (to_matlab, "%     {name} = {shown}"),
        (to_latex, "%   {name} = {shown}"),
        (to_python, "    {name} = {shown}"),
    ],
)
def test_headers_show_values_in_the_unit_written(exporter, template):
    """Every header shows ``cx1 = 15 kN*s/m``, never the SI number beside the unit."""
    text = exporter(units_eom())
    lines = text.splitlines()
    for name, shown in (("cx1", "15 kN*s/m"), ("mc", "30 t"), ("v", "100 km/h"), ("Gamma", "0.1")):
        expected = template.format(name=name.ljust(5) if exporter in (to_text, to_matlab) else name, shown=shown)
        assert expected in lines, (name, expected)
    assert "15000" not in "\n".join(line for line in lines if "cx1 =" in line and ("%" in line or "  cx1" in line))


def test_python_and_matlab_defaults_stay_si(tmp_path):
    """The code keeps SI values (the headers only display them in the file's unit)."""
    eom = units_eom()
    assert "    p.cx1 = 15000.0;" in to_matlab(eom)
    module = tmp_path / "units_module.py"
    module.write_text(to_python(eom), encoding="utf-8")
    namespace: dict = {}
    exec(compile(module.read_text(encoding="utf-8"), str(module), "exec"), namespace)
    assert namespace["VALUES"]["cx1"] == 15000.0 and namespace["UNITS"]["cx1"] == "kN*s/m"
    assert namespace["matrices"]()["C"][0, 0] == pytest.approx(15000.0 + 0.1 * 3.6 / 100)


def test_json_stays_si_with_a_units_map():
    doc = json.loads(to_json(units_eom()))
    assert doc["values"]["cx1"] == 15000.0 and doc["values"]["mc"] == 30000.0
    assert doc["units"] == {"Gamma": "1", "cx1": "kN*s/m", "mc": "t", "v": "km/h"}


def test_unreadable_unit_is_shown_as_si():
    eom = units_eom()
    eom.units["cx1"] = "widgets"
    assert "  cx1   = 15000.0 SI" in to_text(eom).splitlines()


def test_latex_tall_matrices_are_listed_entry_by_entry():
    """More than MAX_MATRIX_ROWS rows: the non-zero entries, one per line, labelled by
    DOF names; the cost follows them (no bmatrix of zeros)."""
    n = MAX_MATRIX_ROWS + 20
    text = to_latex(chain_eom(n))
    assert r"\begin{bmatrix}" in text  # the DOF vector q is still typeset
    assert f"% K ({n} x {n}): {n + 2 * (n - 1)} non-zero entries, listed" in text
    assert r"  K_{\mathrm{B1}.y,\,\mathrm{B2}.y} &= - k \\" in text
    assert text.count(r"\begin{align*}") == text.count(r"\end{align*}}") + 1
    rows = [ln for ln in text.splitlines() if ln.startswith("  K_{")]
    assert len(rows) == n + 2 * (n - 1)
    assert to_latex(chain_eom(MAX_MATRIX_ROWS)).count(r"\begin{bmatrix}") > 3
