"""The bundled curves (express.rail.track.named) keep the values docs/curving.md states."""

from __future__ import annotations

import pytest

from express.base.diagnostics import ModelError
from express.rail.track.named import NAMED_CURVES, named_track

#: name -> cant deficiency [mm] on a 1500 mm base, as docs/curving.md tabulates it
DEFICIENCY_MM = {"R250": 115, "R400": 116, "R600": 110, "R1000": 115, "R3000": 78}


@pytest.mark.parametrize("name", list(NAMED_CURVES))
def test_bundled_curve_follows_its_design_rules(name):
    curve = NAMED_CURVES[name]
    track, description = named_track(name)
    v_kmh = curve.speed * 3.6
    deficiency = 11.8 * v_kmh**2 / curve.radius - curve.cant * 1e3  # mm, 1500 mm base
    assert deficiency == pytest.approx(DEFICIENCY_MM[name], abs=0.6)
    gradient = curve.cant * 1e3 / curve.transition  # mm/m
    assert gradient <= 2.25
    assert gradient * curve.speed <= 50.0  # mm/s
    assert track.speed == curve.speed and f"R = {curve.radius:g} m" in description
    assert track.curvature(50.0 + curve.transition + 1.0) == pytest.approx(-1.0 / curve.radius)


def test_paper_and_unknown_names():
    track, description = named_track("paper")
    assert "Fig. 9" in description and track.length == pytest.approx(460.0)
    with pytest.raises(KeyError, match="R250"):
        named_track("R123")


@pytest.mark.parametrize("name", ["R250", "R400", "R600", "R1000", "R3000", "paper"])
def test_load_track_takes_a_bundled_name_as_the_command_line_does(name, tmp_path, monkeypatch):
    """Issue 35 item 4: ``express.load_track("R400")`` failed though ``--track R400`` works;
    a bundled name comes before a file of that name, as on the command line, and a Path
    is always a file."""
    from pathlib import Path

    from express.rail.track import load_track

    monkeypatch.chdir(tmp_path)
    (tmp_path / name).write_text("not a track", encoding="utf-8")
    assert load_track(name) == named_track(name)[0]
    with pytest.raises(ModelError):
        load_track(Path(name))
