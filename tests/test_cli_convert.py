"""``express convert`` (``express.cli.convert``): classic -> modern TOML, written whole,
loading back to the same equations."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from cli_support import LEVER, STEERED, assert_input_error, run


def test_converted_lever_gives_the_same_equations(tmp_path, capsys):
    target = tmp_path / "lever.toml"
    status, out, err = run(capsys, "convert", LEVER, "-o", target)
    assert status == 0, err
    assert out == "" and f"wrote {target}" in err
    assert run(capsys, "generate", target)[1] == run(capsys, "generate", LEVER)[1]


def test_convert_to_stdout_and_to_dash_agree(tmp_path, capsys):
    target = tmp_path / "lever.toml"
    assert run(capsys, "convert", LEVER, "-o", target)[0] == 0
    assert run(capsys, "convert", LEVER)[1] == target.read_text(encoding="utf-8")
    assert run(capsys, "convert", LEVER, "-o", "-")[1] == target.read_text(encoding="utf-8")


def test_convert_applies_set_and_the_file_loads_back(tmp_path, capsys):
    target = tmp_path / "steered.toml"
    status, _, err = run(capsys, "convert", STEERED, "--set", "Gamma=0.07", "-o", target)
    assert status == 0, err
    status, out, err = run(capsys, "generate", target, "--format", "json")
    assert status == 0, err
    assert json.loads(out)["values"]["Gamma"] == pytest.approx(0.07)


def test_convert_of_missing_file(tmp_path, capsys):
    """``convert`` of a missing file: status 2, nothing written."""
    target = tmp_path / "x.toml"
    assert_input_error(capsys, "convert", tmp_path / "nope.exp", "-o", target, mentions="nope.exp")
    assert not target.exists()


def test_convert_refuses_to_overwrite_its_input(tmp_path, capsys):
    model = tmp_path / "lever.exp"
    model.write_text(Path(LEVER).read_text(encoding="utf-8"), encoding="utf-8")
    before = model.read_bytes()
    assert_input_error(capsys, "convert", model, "-o", model, mentions="refusing")
    assert model.read_bytes() == before


@pytest.mark.slow
def test_a_converted_profile_contact_model_runs(tmp_path, capsys):
    """Issue 35's case: the S1002 car converted, then ``eigen`` on the converted file
    (it failed with 12 "undefined name Gamma_e_f11" errors: the profiles' node was not
    written); the same modes as the original."""
    from cli_support import ROOT

    target = tmp_path / "ms.toml"
    assert run(capsys, "convert", ROOT / "examples" / "manchester-s1002.toml", "-o", target)[0] == 0
    status, out, err = run(capsys, "eigen", target, "--json")
    assert status == 0, err
    status, original, err = run(capsys, "eigen", ROOT / "examples" / "manchester-s1002.toml", "--json")
    assert json.loads(out)["modes"] == json.loads(original)["modes"]


def test_a_written_model_that_lost_a_name_is_an_internal_error_before_writing():
    """``convert``'s check: a name the original defines but the text lost (a writer's bug,
    made here by cutting a parameter's line) is refused; the names a classic file leaves
    to the run stay allowed."""
    from express.cli.convert import _check_loads_back
    from express.io import load_model, model_to_toml

    original = load_model(STEERED)
    text = model_to_toml(original)
    cut = "\n".join(line for line in text.split("\n") if not line.startswith("mc ="))
    with pytest.raises(RuntimeError, match="undefined name mc"):
        _check_loads_back(cut, "x.toml", original)
    classic = load_model(LEVER)
    _check_loads_back(model_to_toml(classic), "x.toml", classic)  # its names come with the run
