"""Fuzzing of track files (issue 17): the bundled tracks mutated line by line and
tracks generated with extreme fields, through the reader (``load_track``: a Track whose
geometry evaluates to finite numbers, or a ModelError naming the file) and through
``express simulate --track`` (status 0, 1 or 2, no traceback, within a time bound, the
earlier output intact when refused).  Derandomized (``tests/fuzz_support.py``).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from hypothesis import assume, given
from hypothesis import strategies as st

from cli_support import CONVENTIONAL
from express.base.diagnostics import InputError
from express.rail.track import load_track
from fuzz_support import NASTY_NUMBERS, assert_untouched, check, fuzz, mutated, snapshot, time_limit

pytestmark = pytest.mark.slow

TRACKS = Path(CONVENTIONAL).parent / "tracks"
NAMES = sorted(p.name for p in TRACKS.glob("*.toml"))
FIELD = st.one_of(st.sampled_from(NASTY_NUMBERS), st.sampled_from(['"1 km"', '"95 mm"', '"-5 m"', '"3 kg"', "1e6",
                                                                   "1e-9", '"1e6 m"', "10", "0.1"]))


TRACK_NAMES = ['"t"', '"\\u0000"', "3", '"é"']
SOURCES = ['"erri_low"', '"fra5"', '"/dev/zero"', '"missing.csv"', '"/etc/passwd"', '"."']


@st.composite
def generated_tracks(draw) -> str:
    """A track of one to three segments and an irregularity, with drawn fields."""
    name = draw(st.sampled_from(TRACK_NAMES))
    speed = draw(st.one_of(st.just('"120 km/h"'), FIELD))
    lines = [f"name = {name}", f"speed = {speed}"]
    for _ in range(draw(st.integers(0, 3))):
        kind = draw(st.sampled_from(["straight", "curve", "transition", "spiral"]))
        lines += ["", "[[segment]]", f'type = "{kind}"', f"length = {draw(FIELD)}"]
        if kind == "curve" or draw(st.booleans()):
            lines += [f"radius = {draw(FIELD)}", f"cant = {draw(FIELD)}",
                      f'direction = "{draw(st.sampled_from(["left", "right", "up"]))}"']
    kind = draw(st.sampled_from(["none", "sinusoid", "spectrum", "profile", "other"]))
    lines += ["", "[irregularity]", f'type = "{kind}"']
    for key in draw(st.lists(st.sampled_from(["amplitude", "wavelength", "phase", "spectrum", "seed",
                                               "wavelength_min", "wavelength_max", "period", "file", "step"]),
                             max_size=4, unique=True)):
        value = draw(st.one_of(FIELD, st.sampled_from(SOURCES)))
        lines.append(f"{key} = {value}")
    return "\n".join(lines) + "\n"


def _read(path: Path):
    """The track, or None for a clean refusal; geometry evaluated when it loads."""
    try:
        with time_limit(30):
            track = load_track(path)
    except InputError as error:
        assert str(error) and "Traceback" not in str(error)
        assert all(len(line) < 800 for line in str(error).splitlines())
        return None
    s = np.linspace(0.0, min(track.length, 1e5), 201)
    with time_limit(30):
        values = [track.curvature(s), track.cant(s), track.lateral_irregularity(s)]
    assert all(np.isfinite(np.asarray(v, dtype=float)).all() for v in values), path
    return track


@fuzz(100)
@given(data=st.data(), name=st.sampled_from(NAMES))
def test_mutated_tracks_load_or_are_refused(tmp_path_factory, data, name):
    text = data.draw(mutated((TRACKS / name).read_text(encoding="utf-8")), label="track")
    path = tmp_path_factory.mktemp("track") / name
    path.write_text(text, encoding="utf-8")
    _read(path)


@fuzz(100)
@given(text=generated_tracks())
def test_generated_tracks_load_or_are_refused(tmp_path_factory, text):
    path = tmp_path_factory.mktemp("track") / "track.toml"
    path.write_text(text, encoding="utf-8")
    _read(path)


@fuzz(20)
@given(data=st.data(), name=st.sampled_from(NAMES))
def test_simulate_on_mutated_tracks_ends_cleanly(tmp_path_factory, data, name):
    text = data.draw(mutated((TRACKS / name).read_text(encoding="utf-8"), most=2), label="track")
    folder = tmp_path_factory.mktemp("run")
    path = folder / name
    path.write_text(text, encoding="utf-8")
    track = _read(path)
    assume(track is None or track.length <= 50e3)  # a longer run is long by request, not by fault
    target = folder / "run.csv"
    target.write_text("an earlier run\n")
    before = snapshot(folder)
    argv = ["simulate", CONVENTIONAL, "--track", path, "--speed", "300", "--dt", "0.02", "-o", target]
    status, _, _ = check(argv)
    if status != 0:
        assert_untouched(before, folder, argv, diverged=status == 1)
    else:
        header = target.read_text().splitlines()[0]
        assert header.startswith("time_s,")
