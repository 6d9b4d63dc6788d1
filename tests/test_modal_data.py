"""Modal data files (``express.io.modal_data``): the CSV format of a FE model's modes,
its normalisation by the modal mass, its units and its errors (file and line, exit 2)."""

from __future__ import annotations

import math

import pytest

from cli_support import PROBLEM_LINE, assert_input_error
from express.io.toml_model import parse_toml_model
from test_modal_body import BEAM, frequencies

#: Two vertical modes scaled to 1 at the supports, generalised masses 10 t and 12 t.
SCALED = """# two modes, scaled shapes
mode, kind, frequency, damping, modal_mass, P1, P2
unit, , Hz, -, t, -, -
vb1, vertical, 8.9, 0.02, 10, 1.0, 1.0
vb2, vertical, 20, , 12, 1.0, -1.0
"""


def write(tmp_path, csv_text: str):
    (tmp_path / "modes.csv").write_text(csv_text, encoding="utf-8")
    model = tmp_path / "coach.toml"
    model.write_text(BEAM + '\n[flexible.CB]\ndamping = 0.03\nfile = "modes.csv"\n', encoding="utf-8")
    return model


def test_scaled_shapes_are_divided_by_the_root_of_the_modal_mass(tmp_path):
    """``phi / sqrt(modal mass)``: 1/sqrt(10000 kg) at the supports of the first mode; the
    frequency in Hz becomes ``omega = 2 pi f``; an empty damping cell takes the body's
    damping.  The same modes given mass-normalised (unit 1/sqrt(kg)) or with the
    frequency in rad/s give the same natural frequencies (to 1e-12)."""
    model = parse_toml_model(write(tmp_path, SCALED).read_text(), str(tmp_path / "coach.toml"))
    values = model.values()
    assert values["CB_vb1_P1"] == pytest.approx(1 / math.sqrt(1e4), rel=1e-15)
    assert values["CB_vb2_P2"] == pytest.approx(-1 / math.sqrt(1.2e4), rel=1e-15)
    assert values["CB_vb1_w"] == pytest.approx(2 * math.pi * 8.9, rel=1e-15)
    assert values["CB_vb1_zeta"] == pytest.approx(0.02)
    assert values["CB_vb2_zeta"] == pytest.approx(0.03)
    reference = frequencies(model.source)
    a, b = 1 / math.sqrt(1e4), 1 / math.sqrt(1.2e4)
    normalised = (f"mode, kind, frequency, damping, P1, P2\nunit, , rad/s, -, 1/sqrt(kg), 1/sqrt(kg)\n"
                  f"vb1, vertical, {2 * math.pi * 8.9!r}, 0.02, {a!r}, {a!r}\n"
                  f"vb2, vertical, {2 * math.pi * 20!r}, , {b!r}, {-b!r}\n")
    assert frequencies(str(write(tmp_path, normalised))) == pytest.approx(reference, rel=1e-12)


@pytest.mark.parametrize(
    "old, new, line, mentions",
    [
        ("vb2, vertical, 20,", "vb2, vertical, -20,", 5, "frequency must be a positive number"),
        ("unit, , Hz, -, t,", "unit, , Hz, -, kg*m,", 3, "is not a mass"),
        ("unit, , Hz,", "unit, , kg,", 3, "is not a frequency"),
        ("1.0, -1.0\n", "1.0,\n", 5, "no mode shape at P2"),
        ("unit, , Hz, -, t, -, -", "unit, , Hz, -, t, m, m", 3, "shape units"),
    ],
)
def test_bad_modal_data_exits_2_naming_the_data_file_and_line(tmp_path, capsys, old, new, line, mentions):
    """A negative frequency, a modal mass or frequency of the wrong unit, a shape missing
    at a used CP, shapes of an unknown unit: exit status 2, the CSV file and its line,
    nothing written."""
    assert old in SCALED
    model = write(tmp_path, SCALED.replace(old, new))
    target = tmp_path / "out.json"
    err = assert_input_error(capsys, "generate", model, "--format", "json", "-o", target, "--no-cache")
    matches = [PROBLEM_LINE.match(text) for text in err.splitlines() if text.strip()]
    assert all(matches), err
    hit = [m for m in matches if m and mentions in m["message"]]
    assert hit, err
    assert hit[0]["file"] == str(tmp_path / "modes.csv")
    assert int(hit[0]["line"]) == line
    assert not target.exists()
