"""Flexible (modal) bodies: the free-free beam's closed form, the modal model against an
independent finite-element beam, orthogonality, the rigid limit and bad input
(``express.model.modal_body``, ``express.model.beam_modes``, ``express.io.toml_modal``)."""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.linalg as sl
import sympy as sp
from scipy.integrate import quad
from scipy.optimize import brentq

from cli_support import PROBLEM_LINE, assert_input_error
from express.assembly.generator import generate
from express.io.toml_model import parse_toml_model, read_toml_model
from express.model.beam_modes import bending_shape, free_free_roots, torsion_frequency

#: A uniform 24 m, 40 t car body on two vertical springs 8 m either side of its centre
#: (pitch inertia m L^2 / 12 of the uniform beam), bending stiffness EI.
LENGTH, MASS, EI, SPRING, HALF_BASE = 24.0, 40000.0, 2.0e9, 1.0e6, 8.0

BEAM = """
[model]
name = "beam"

[parameters]
m = "40 t"
Jx = "60 t*m^2"
Jy = "1920 t*m^2"
k = "1 MN/m"
a = "8 m"

[bodies.CB]
mass = "m"
inertia = ["Jx", "Jy", "Jy"]
dofs = ["z", "ry"]

[grounds.G]

[points.P1]
body = "CB"
offset = ["a", 0, 0]
[points.P2]
body = "CB"
offset = ["-a", 0, 0]
[points.G1]
body = "G"
offset = ["a", 0, 0]
[points.G2]
body = "G"
offset = ["-a", 0, 0]

[elements.K1]
from = "P1"
to = "G1"
direction = "z"
stiffness = "k"
[elements.K2]
from = "P2"
to = "G2"
direction = "z"
stiffness = "k"
"""


def beam_model(modes: int, ei: float = EI, damping: float = 0.0) -> str:
    """The model text: rigid for ``modes == 0``, else ``modes`` vertical bending modes."""
    if modes == 0:
        return BEAM
    return BEAM + f"""
[flexible.CB]
damping = {damping}
[flexible.CB.beam]
length = "{LENGTH} m"
vertical_EI = "{ei} N*m^2"
vertical = {modes}
"""


def frequencies(text: str) -> np.ndarray:
    """Undamped natural frequencies [Hz] of a model text (or of a model file ending
    ``.toml``), ascending."""
    model = read_toml_model(text) if text.endswith(".toml") else parse_toml_model(text, "beam.toml")
    equations = generate(model).equations
    values = {sp.Symbol(name): value for name, value in equations.values.items()}
    mass = np.array(equations.M.subs(values), dtype=float)
    stiffness = np.array(equations.K.subs(values), dtype=float)
    return np.sqrt(sl.eigh(stiffness, mass, eigvals_only=True)) / (2 * math.pi)


def hermite_matrices(elements: int) -> tuple[np.ndarray, np.ndarray]:
    """Stiffness and mass matrices of the free-free uniform beam: Euler-Bernoulli
    elements with cubic Hermite shape functions (consistent mass), DOFs (w, w') per node."""
    h, mu = LENGTH / elements, MASS / LENGTH
    ke = EI / h**3 * np.array([[12, 6 * h, -12, 6 * h], [6 * h, 4 * h * h, -6 * h, 2 * h * h],
                               [-12, -6 * h, 12, -6 * h], [6 * h, 2 * h * h, -6 * h, 4 * h * h]])
    me = mu * h / 420 * np.array([[156, 22 * h, 54, -13 * h], [22 * h, 4 * h * h, 13 * h, -3 * h * h],
                                  [54, 13 * h, 156, -22 * h], [-13 * h, -3 * h * h, -22 * h, 4 * h * h]])
    n = 2 * (elements + 1)
    stiffness, mass = np.zeros((n, n)), np.zeros((n, n))
    for e in range(elements):
        block = slice(2 * e, 2 * e + 4)
        stiffness[block, block] += ke
        mass[block, block] += me
    return stiffness, mass


def hermite_beam(elements: int) -> np.ndarray:
    """Natural frequencies [Hz] of the same beam on its two springs by an independent
    finite-element model (:func:`hermite_matrices`), the springs on the nodes at
    ``L/2 -+ a``."""
    h = LENGTH / elements
    stiffness, mass = hermite_matrices(elements)
    for x in (LENGTH / 2 - HALF_BASE, LENGTH / 2 + HALF_BASE):
        node = round(x / h)
        assert abs(node * h - x) < 1e-9
        stiffness[2 * node, 2 * node] += SPRING
    return np.sqrt(sl.eigh(stiffness, mass, eigvals_only=True)) / (2 * math.pi)


# --------------------------------------------------------------------------- closed form


def test_free_free_roots_to_the_published_digits():
    """``cos x cosh x = 1``: the published roots (Blevins, Formulas for natural frequency
    and mode shape, table 8-1) to their 9-10 digits; the residual is at machine precision
    (achieved < 1e-15 relative; asserted 1e-13)."""
    published = [4.730040745, 7.853204624, 10.995607838, 14.137165491, 17.278759657]
    roots = free_free_roots(5)
    assert roots == pytest.approx(published, abs=6e-10)
    for root in roots:
        assert abs(math.cos(root) * math.cosh(root) - 1.0) < 1e-13 * math.cosh(root)
    # beyond: (n + 1/2) pi to within e^-x
    assert free_free_roots(8)[-1] == pytest.approx(8.5 * math.pi, abs=1e-9)


def test_first_mode_nodes_at_22_4_percent_of_the_length():
    """The first mode's nodes at s/L = 0.224158 and 0.775842 (the textbook 0.224 L) and a
    value of 2 at both ends; the stable form of the shape agrees with the textbook form
    ``cosh + cos - sigma (sinh + sin)`` to 1e-12 (achieved 3e-15)."""
    root = free_free_roots(1)[0]
    node = brentq(lambda s: float(bending_shape(root, s)), 0.1, 0.4, xtol=1e-15)
    assert node == pytest.approx(0.2241575227, abs=1e-10)
    assert brentq(lambda s: float(bending_shape(root, s)), 0.6, 0.9, xtol=1e-15) == pytest.approx(1 - node, abs=1e-10)
    assert float(bending_shape(root, 0.0)) == pytest.approx(2.0, abs=1e-12)
    assert float(bending_shape(root, 1.0)) == pytest.approx(2.0, abs=1e-12)
    sigma = (math.cosh(root) - math.cos(root)) / (math.sinh(root) - math.sin(root))
    s = np.linspace(0, 1, 11)
    textbook = np.cosh(root * s) + np.cos(root * s) - sigma * (np.sinh(root * s) + np.sin(root * s))
    assert np.max(np.abs(bending_shape(root, s) - textbook)) < 1e-12


def test_rigid_and_flexible_modes_are_orthogonal_and_normalised():
    """With respect to the uniform mass: the bending shapes have mean square 1 (so
    ``W / sqrt(m)`` is mass-normalised), are orthogonal to each other and to both rigid
    modes (translation, rotation about the centre); the torsion shapes ``cos(n pi s)``
    likewise.  Quadrature to 1e-12 (achieved < 1e-13 for 6 modes)."""
    roots = free_free_roots(6)
    rigid = (lambda s: 1.0, lambda s: s - 0.5)
    for i, a in enumerate(roots):
        assert quad(lambda s, a=a: bending_shape(a, s) ** 2, 0, 1, epsabs=1e-14, limit=200)[0] == pytest.approx(1.0, abs=1e-12)
        for shape in rigid:
            assert abs(quad(lambda s, a=a, shape=shape: bending_shape(a, s) * shape(s), 0, 1, epsabs=1e-14, limit=200)[0]) < 1e-12
        for b in roots[:i]:
            assert abs(quad(lambda s, a=a, b=b: bending_shape(a, s) * bending_shape(b, s), 0, 1, epsabs=1e-14, limit=200)[0]) < 1e-12
    for n in range(1, 4):
        assert abs(quad(lambda s, n=n: math.cos(n * math.pi * s), 0, 1)[0]) < 1e-12
    # the generated mass matrix: identity on the modal coordinates, no rigid coupling
    equations = generate(parse_toml_model(beam_model(3), "beam.toml")).equations
    assert equations.dofs == ("CB.z", "CB.ry", "CB.vb1", "CB.vb2", "CB.vb3")
    assert sp.diag(sp.Symbol("m"), sp.Symbol("Jy"), 1, 1, 1) == equations.M


def test_mode_parameters_are_the_closed_form():
    """The frequencies and shape values the reader makes: ``omega = (bL)^2/L^2 sqrt(EI/mu)``,
    shape ``W(s)/sqrt(m)``; each is a parameter in the exact matrices (K carries
    ``CB_vb1_w**2``, the spring couples ``k*(CB_vb1_P1 + CB_vb1_P2)``)."""
    model = parse_toml_model(beam_model(2), "beam.toml")
    values = model.values()
    root = free_free_roots(1)[0]
    assert values["CB_vb1_w"] == pytest.approx(root**2 / LENGTH**2 * math.sqrt(EI * LENGTH / MASS), rel=1e-14)
    s = (HALF_BASE + LENGTH / 2) / LENGTH
    assert values["CB_vb1_P1"] == pytest.approx(float(bending_shape(root, s)) / math.sqrt(MASS), rel=1e-14)
    k = generate(model).equations.K
    w, p1, p2, kk = sp.symbols("CB_vb1_w CB_vb1_P1 CB_vb1_P2 k")
    assert sp.expand(k[2, 2] - (w**2 + kk * (p1**2 + p2**2))) == 0
    assert sp.expand(k[0, 2] - kk * (p1 + p2)) == 0


def test_set_recomputes_the_beam_modes(tmp_path):
    """The beam is a node of the parameter graph (``free_free_beam``): ``--set`` of its
    quantities or of the body's mass recomputes the modes.  ``CB_vertical_EI`` x 4 doubles
    ``CB_vb1_w`` (omega ~ sqrt(EI), to 1e-15) and gives the natural frequencies of a file
    written with that EI (to 1e-12); ``m`` x 4 halves the frequency and the shapes
    (omega ~ 1/sqrt(mu), phi ~ 1/sqrt(m)); a beam whose EI is an expression of a parameter
    (``vertical_EI = "EIv"``) follows ``--set EIv``; a station follows its offset (``a``)."""
    from express.model.parameters import with_values

    model = parse_toml_model(beam_model(2), "beam.toml")
    values = model.values()
    stiff = with_values(model, {"CB_vertical_EI": 4 * EI})
    assert stiff.values()["CB_vb1_w"] == pytest.approx(2 * values["CB_vb1_w"], rel=1e-15)
    assert stiff.values()["CB_vb1_P1"] == pytest.approx(values["CB_vb1_P1"], rel=1e-15)
    path = tmp_path / "stiff.toml"
    path.write_text(beam_model(2, ei=4 * EI), encoding="utf-8")
    equations = generate(stiff).equations
    at = {sp.Symbol(name): value for name, value in stiff.values().items()}
    found = np.sqrt(sl.eigh(np.array(equations.K.subs(at), dtype=float), np.array(equations.M.subs(at), dtype=float),
                            eigvals_only=True)) / (2 * math.pi)
    assert found == pytest.approx(frequencies(str(path)), rel=1e-12)
    heavy = with_values(model, {"m": "160 t"}).values()
    assert heavy["CB_vb1_w"] == pytest.approx(values["CB_vb1_w"] / 2, rel=1e-14)
    assert heavy["CB_vb2_P2"] == pytest.approx(values["CB_vb2_P2"] / 2, rel=1e-14)
    moved = with_values(model, {"a": "12 m"}).values()  # P1 at the end: W = 2
    assert moved["CB_vb1_P1"] == pytest.approx(2 / math.sqrt(MASS), rel=1e-12)
    named = beam_model(2).replace(f'vertical_EI = "{EI} N*m^2"', 'vertical_EI = "EIv"').replace(
        '[parameters]', '[parameters]\nEIv = "2e9 N*m^2"')
    by_name = parse_toml_model(named, "named.toml")
    assert by_name.values()["CB_vb1_w"] == pytest.approx(values["CB_vb1_w"], rel=1e-15)
    assert with_values(by_name, {"EIv": 9 * EI}).values()["CB_vb1_w"] == pytest.approx(3 * values["CB_vb1_w"], rel=1e-15)


def test_set_of_the_beam_through_the_command_line(tmp_path, capsys):
    """``express eigen --set CB_vertical_EI=...`` moves the named bending mode (x sqrt(2)
    for 2 EI free-free: 8.920 -> 12.697 Hz, 1.4234 on the coach's air springs, asserted
    sqrt(2) within 2 %; and the eigenvalue of the same coach written with that EI, 1e-9); a value the beam refuses
    (a negative EI, a length that leaves points outside) exits 2 naming the file, its line
    and the beam, nothing written."""
    from cli_support import EXAMPLES, run_json

    coach = EXAMPLES / "manchester-flexible.toml"
    changed = tmp_path / "stiffer.toml"
    text = coach.read_text(encoding="utf-8")
    assert text.count('"3.0e9 N*m^2"') == 1
    changed.write_text(text.replace('"3.0e9 N*m^2"', '"6.0e9 N*m^2"'), encoding="utf-8")

    def bending(*argv) -> float:
        data = run_json(capsys, "eigen", *argv, "--speed", "160")
        return next(m["frequency_hz"] for m in data["modes"] if m["label"] == "car body first vertical bending")

    base, stiffer = bending(coach), bending(coach, "--set", "CB_vertical_EI=6e9")
    assert stiffer == pytest.approx(bending(changed), rel=1e-9)
    assert stiffer / base == pytest.approx(math.sqrt(2), rel=0.02)  # the suspension's share
    for setting, says in (("CB_vertical_EI=-6e9", "vertical_EI must be positive"),
                          ("CB_length=10 m", "beyond the beam's ends")):
        message = assert_input_error(capsys, "eigen", coach, "--set", setting, mentions=says)
        found = PROBLEM_LINE.match(message.splitlines()[0])
        assert found and found["item"] == "flexible CB beam" and found["file"].endswith("manchester-flexible.toml")


def test_sensitivity_to_the_beam_stiffness_goes_through_its_modes():
    """``d CB_vb1_w / d CB_vertical_EI`` through the parameter graph (the beam's node by
    central differences, step 1e-4 relative) against the closed form ``omega / (2 EI)``:
    measured 1.2e-9 relative, asserted 1e-7; the shapes do not depend on EI (rate 0)."""
    from express.analysis.study.derivatives import graph_rates

    model = parse_toml_model(beam_model(2), "beam.toml")
    equations = generate(model).equations
    rates = graph_rates(model, equations).rates(model.values(), ["CB_vertical_EI"])
    w = model.values()["CB_vb1_w"]
    assert rates["CB_vb1_w"][0] == pytest.approx(w / (2 * EI), rel=1e-7)
    assert "CB_vb1_P1" not in rates or abs(rates["CB_vb1_P1"][0]) < 1e-9 * abs(model.values()["CB_vb1_P1"]) / EI


# --------------------------------------------------------------------------- against a FE beam


def test_modal_beam_on_two_springs_converges_to_a_finite_element_beam():
    """The uniform car body on two springs: the modal model's first five frequencies
    against 240 Hermite elements (converged to about 1e-7).  Relative errors measured:

    ======  ========  ========  ========  ========
    modes   bounce    pitch     1st bend  2nd bend
    ======  ========  ========  ========  ========
    rigid   3.9e-3    6.9e-4    --        --
    2       6.6e-4    3.4e-4    4.4e-6    2.6e-7
    6       2.5e-5    2.3e-5    4.5e-8    8.4e-9
    10      1.2e-5    4.2e-6    4.2e-8    4.9e-9
    ======  ========  ========  ========  ========

    (Rayleigh-Ritz: from above, never worse for more modes.)  Asserted: each at most 1.3
    times the value measured, the bounce and pitch errors non-increasing; the bending
    errors with 6 and 10 modes at the reference's own accuracy, 3e-7 (another machine's
    rounding gave 1.7e-7 and 3.8e-8 with 6 modes, 2026-12-03)."""
    reference = hermite_beam(240)[:5]
    assert reference[2] == pytest.approx(6.7939, abs=1e-4)
    limits = {0: (5.1e-3, 9.0e-4), 2: (8.6e-4, 4.5e-4, 5.8e-6, 3.4e-7), 6: (3.3e-5, 3.0e-5, 3e-7, 3e-7),
              10: (1.5e-5, 5.5e-6, 3e-7, 3e-7)}
    previous = None
    for modes, bounds in limits.items():
        found = frequencies(beam_model(modes))[: len(bounds)]
        errors = np.abs(found - reference[: len(bounds)]) / reference[: len(bounds)]
        assert np.all(errors <= np.array(bounds)), (modes, errors)
        assert np.all(found >= reference[: len(bounds)] * (1 - 1e-7))  # from above
        if previous is not None:
            assert np.all(errors[:2] <= previous[:2] * (1 + 1e-9))
        previous = errors


def test_rigid_car_body_recovered_as_the_bending_stiffness_grows():
    """EI x 1e2, 1e4, 1e6: bounce and pitch tend to the rigid model's, the error falling
    as 1/EI (measured 3.16e-5, 3.16e-7, 3.2e-9 relative; asserted: the last < 5e-9, the
    ratio of the first two 1e-2 within 2 %), and the bending frequency tends to the
    free-free beam's ``omega_1`` (the springs' share falling alike: 3.16e-5, 3.16e-7,
    3.2e-9; asserted < 4e-5 * 1e2 / factor)."""
    rigid = frequencies(beam_model(0))
    errors = []
    for factor in (1e2, 1e4, 1e6):
        text = beam_model(2, EI * factor)
        found = frequencies(text)
        errors.append(np.max(np.abs(found[:2] - rigid) / rigid))
        free = parse_toml_model(text, "beam.toml").values()["CB_vb1_w"] / (2 * math.pi)
        assert 0 < found[2] / free - 1 < 4e-5 * 1e2 / factor
    assert errors[-1] < 5e-9
    assert errors[1] / errors[0] == pytest.approx(1e-2, rel=0.02)


def test_torsion_moves_points_off_the_axis():
    """A torsion mode turns the section: a vertical spring at lateral offset ``b`` sees
    ``psi*b``, a lateral one at height ``h`` sees ``-psi*h``; the free shaft's frequency is
    ``pi/L sqrt(GJ/rho Ip)`` (``rho Ip`` defaulting to ``Ix / L``)."""
    text = BEAM.replace('offset = ["a", 0, 0]\n[points.P2]', 'offset = ["a", 1.2, 0]\n[points.P2]', 1)
    text = text.replace('dofs = ["z", "ry"]', 'dofs = ["z", "rx", "ry"]')
    text += """
[points.P3]
body = "CB"
offset = [0, 0, -0.5]
[elements.K3]
from = "P3"
to = "G1"
direction = "y"
stiffness = "k"

[flexible.CB.beam]
length = "24 m"
torsion_GJ = "1.5e9 N*m^2"
torsion = 1
"""
    model = parse_toml_model(text, "torsion.toml")
    assert model.values()["CB_to1_w"] == pytest.approx(torsion_frequency(1, 24.0, 1.5e9, 60000.0 / 24.0), rel=1e-14)
    assert model.values()["CB_to1_w"] == pytest.approx(math.pi / 24 * math.sqrt(1.5e9 * 24 / 60000), rel=1e-14)
    equations = generate(model).equations
    k, psi1, psi3, w = sp.symbols("k CB_to1_P1 CB_to1_P3 CB_to1_w")
    q = equations.dofs.index("CB.to1")
    assert sp.expand(equations.K[q, q] - (w**2 + k * (sp.Rational(6, 5) * psi1) ** 2 + k * (psi3 / 2) ** 2)) == 0


# --------------------------------------------------------------------------- bad input


@pytest.mark.parametrize(
    "extra, mentions",
    [
        ('[flexible.CB.modes.vb1]\nkind = "vertical"\nfrequency = "-9 Hz"\nshapes = { P1 = 0.01, P2 = 0.01 }\n',
         "frequency must be positive"),
        ('[flexible.CB.modes.vb1]\nkind = "vertical"\nfrequency = "9 Hz"\nshapes = { P1 = 0.01 }\n',
         "no mode shape at P2"),
        ('[flexible.CB.modes.vb1]\nkind = "vertical"\nfrequency = "9 kg"\nshapes = { P1 = 0.01, P2 = 0.01 }\n',
         "frequency"),
        ('[flexible.CB.modes.vb1]\nkind = "bending"\nfrequency = "9 Hz"\nshapes = { P1 = 0.01, P2 = 0.01 }\n',
         "kind must be"),
        ('[flexible.CB.beam]\nlength = "24 kg"\nvertical_EI = "2e9 N*m^2"\nvertical = 1\n', "length"),
        ('[flexible.CB.beam]\nlength = "24 m"\nvertical_EI = "2e9 N*m"\nvertical = 1\n', "vertical_EI"),
    ],
)
def test_bad_modal_input_exits_2_with_file_and_line(tmp_path, capsys, extra, mentions):
    """A negative frequency, a missing shape at a used CP, a frequency or beam value of the
    wrong unit, an unknown kind: exit status 2, ``error: file:line: item: message``
    lines naming the file and a line inside it, nothing written."""
    text = BEAM + "\n[flexible.CB]\n" + extra
    model = tmp_path / "bad.toml"
    model.write_text(text, encoding="utf-8")
    target = tmp_path / "out.json"
    err = assert_input_error(capsys, "generate", model, "--format", "json", "-o", target, "--no-cache")
    lines = [line for line in err.splitlines() if line.strip()]
    assert any(mentions in line for line in lines), lines
    for line in lines:
        match = PROBLEM_LINE.match(line)
        assert match, line
        assert match["file"] == str(model)
        assert 1 <= int(match["line"]) <= len(text.splitlines())
    assert not target.exists()


def test_given_modes_and_the_beam_agree():
    """Modes given by value (as from a FE model) with the beam's numbers give the same
    matrices' values as the beam source."""
    beam = parse_toml_model(beam_model(1), "beam.toml")
    values = beam.values()
    given = BEAM + f"""
[flexible.CB.modes.vb1]
kind = "vertical"
frequency = "{values['CB_vb1_w'] / (2 * math.pi)!r} Hz"
damping = 0
shapes = {{ P1 = {values['CB_vb1_P1']!r}, P2 = {values['CB_vb1_P2']!r} }}
"""
    assert frequencies(given) == pytest.approx(frequencies(beam_model(1)), rel=1e-12)


def test_convert_writes_the_modes_back():
    """``express convert`` (:func:`express.io.model_to_toml`) writes every mode by value:
    the file reads back to the same parameters (frequencies to 2 ulp through Hz) and the
    same natural frequencies (to 1e-12)."""
    from express.io import model_to_toml

    model = parse_toml_model(beam_model(3, damping=0.02), "beam.toml")
    text = model_to_toml(model)
    assert "[flexible.CB.modes.vb3]" in text
    again = parse_toml_model(text, "again.toml")
    assert again.values() == pytest.approx(model.values(), rel=1e-15)
    assert frequencies(text) == pytest.approx(frequencies(beam_model(3, damping=0.02)), rel=1e-12)


def test_sensitivity_to_a_bending_frequency_is_exact():
    """``K`` holds ``CB_vb1_w**2``: the derivative of an eigenvalue ``omega_n^2`` by the
    bending frequency from the exact ``dK/dp`` (``phi^T dK/dp phi / phi^T M phi``) against
    central differences of the eigenvalues (step 1e-4 relative: measured 3e-8 relative on
    the bounce, 5e-12 of the largest; asserted 1e-6), the bending mode's ``d omega^2/dw``
    0.99982 x ``2 w`` (asserted 1e-3), the bounce's 1.8e-4 x."""
    model = parse_toml_model(beam_model(2), "beam.toml")
    equations = generate(model).equations
    values = {sp.Symbol(name): value for name, value in equations.values.items()}
    w = sp.Symbol("CB_vb1_w")
    mass = np.array(equations.M.subs(values), dtype=float)

    def eigen(at: dict):
        return sl.eigh(np.array(equations.K.subs(at), dtype=float), mass)

    squares, vectors = eigen(values)
    derivative = np.array(equations.K.diff(w).subs(values), dtype=float)
    exact = np.einsum("in,ij,jn->n", vectors, derivative, vectors)  # eigh: phi^T M phi = 1
    step = 1e-4 * values[w]
    upper, lower = eigen({**values, w: values[w] + step})[0], eigen({**values, w: values[w] - step})[0]
    numeric = (upper - lower) / (2 * step)
    assert exact == pytest.approx(numeric, rel=1e-6, abs=1e-9 * np.max(np.abs(numeric)))
    bending = int(np.argmin(np.abs(np.sqrt(squares) - values[w])))
    assert exact[bending] == pytest.approx(2 * values[w], rel=1e-3)


def test_gravity_with_a_flexible_body():
    """With ``[gravity]`` the model generates (the static preloads of the body held rigid)
    and the modes' rows of K are those without gravity: a body on vertical springs whose
    ends coincide has no geometric stiffness in its modes."""
    text = beam_model(2)
    plain = generate(parse_toml_model(text, "beam.toml")).equations
    weighed = generate(parse_toml_model(text + '\n[gravity]\nacceleration = "9.81"\n', "beam.toml")).equations
    assert weighed.dofs == plain.dofs
    for i in (2, 3):
        assert sp.simplify(weighed.K.row(i) - plain.K.row(i)) == sp.zeros(1, len(plain.dofs))


def test_readable_matrices_split_the_mode_shapes_exactly():
    """``express generate``'s factored entries split a mode-shape polynomial from the rest
    before factoring (``ExactDomain(separate=...)``, for speed): every entry of M, C, K
    equals the expanded generation's exactly, and a coupling entry shows the split
    (``k*(CB_vb1_P1 + CB_vb1_P2)``: one factor in the shapes, one in the rest)."""
    model = parse_toml_model(beam_model(3, damping=0.02), "beam.toml")
    readable, expanded = generate(model).equations, generate(model, readable=False).equations
    for name in ("M", "C", "K"):
        a, b = getattr(readable, name), getattr(expanded, name)
        assert all(sp.expand(a[i, j] - b[i, j]) == 0 for i in range(a.rows) for j in range(a.cols)), name
    k, p1, p2 = sp.symbols("k CB_vb1_P1 CB_vb1_P2")
    assert readable.K[0, 2] == k * (p1 + p2)
