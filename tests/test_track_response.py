"""Frequency response to each track irregularity (issue 25 item 3): vertical, cross level
and alignment at the output points, every direction, one unit per plot axis."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from express.analysis.frequency.frequency import frequency_response
from express.analysis.frequency.track_response import track_frequency_response
from express.analysis.plots import figure_frequency_responses
from express.analysis.ride.vehicle import ride_response, track_class_spectra
from express.cli import main
from express.numeric.statespace import load_vehicle
from test_ride_vehicle import quarter_car_toml, two_axle_toml

ROOT = Path(__file__).resolve().parents[1]
MANCHESTER = ROOT / "examples" / "manchester.toml"
F = np.geomspace(0.1, 30.0, 80)


@pytest.fixture(scope="module")
def manchester():
    return load_vehicle(MANCHESTER)


@pytest.fixture(scope="module")
def written(tmp_path_factory):
    folder = tmp_path_factory.mktemp("track_frf")
    vehicles = {}
    for name, text in (("quarter", quarter_car_toml()), ("two_axle", two_axle_toml(contact_damping=2.0e5))):
        path = folder / f"{name}.toml"
        path.write_text(text, encoding="utf-8")
        vehicles[name] = load_vehicle(path)
    return vehicles


def test_alignment_response_equals_the_lateral_frf(manchester):
    """Two solution routes (resolvent of A with ride outputs; dynamic stiffness with the
    output rows of frequency_response): the floor's lateral acceleration agrees to 2e-8
    of its peak (achieved 4e-9)."""
    track = track_frequency_response(manchester, F, components=["alignment"])
    lateral = frequency_response(manchester, F)
    for point in ("floor_front", "floor_rear"):
        expected = -((2 * np.pi * F) ** 2) * lateral.amplitude_of(point)
        got = track.of(f"{point}.ay", "alignment")
        assert np.max(np.abs(got - expected)) <= 2e-8 * np.max(np.abs(expected))


def test_quarter_car_vertical_transmissibility_is_the_closed_form(written):
    """Body on (ks, cs) over a wheel on kt: [[mb s^2 + cs s + ks, -(cs s + ks)],
    [-(cs s + ks), mw s^2 + cs s + ks + kt]] [zb, zw] = [0, kt zr], assembled by hand."""
    mb, mw, ks, cs, kt = 400.0, 40.0, 2.0e4, 1.5e3, 2.0e5
    y = 2e-3
    track = track_frequency_response(written["quarter"], F, components=["vertical"], amplitude=y)
    for k, f in enumerate(F):
        s = 2j * np.pi * f
        z = np.linalg.solve([[mb * s**2 + cs * s + ks, -(cs * s + ks)],
                             [-(cs * s + ks), mw * s**2 + cs * s + ks + kt]], [0.0, kt * y])
        assert track.of("body.az", "vertical")[k] == pytest.approx(s**2 * z[0], rel=1e-9)
        assert track.displacement_of("body.az", "vertical")[k] == pytest.approx(z[0], rel=1e-9)


def test_cross_level_rolls_a_symmetric_car_and_vertical_bounces_it(written):
    """Left-right symmetric two-axle car: the cross level drives lateral motion (roll)
    and no vertical motion at the centre line; the vertical irregularity the reverse."""
    track = track_frequency_response(written["two_axle"], F, components=["vertical", "cross_level"])
    assert track.components == ("vertical", "cross_level")
    bounce, sway = np.abs(track.of("centre.az", "vertical")), np.abs(track.of("centre.ay", "cross_level"))
    assert bounce.max() > 0.01 and sway.max() > 0.01  # m/s^2 for 1 mm
    assert np.abs(track.of("centre.ay", "vertical")).max() <= 1e-9 * bounce.max()
    assert np.abs(track.of("centre.az", "cross_level")).max() <= 1e-9 * sway.max()
    # the quasi-static limit: the car follows the vertical track, floor displacement -> Y
    low = track_frequency_response(written["two_axle"], [0.01], components=["vertical"])
    assert abs(low.displacement_of("centre.az", "vertical")[0]) == pytest.approx(1e-3, rel=1e-3)


def test_ride_spectra_are_the_frf_squared_times_the_track_spectra(manchester):
    """Where they overlap, G_y = sum_j |H_yj / Y|^2 G_j (one-sided, temporal)."""
    spectra = track_class_spectra("ERRI-high")
    ride = ride_response(manchester, spectra, frequencies=F)
    track = track_frequency_response(manchester, F, components=list(ride.components), amplitude=1.0)
    for name in ("floor_front.az", "floor_front.ay", "floor_rear.az"):
        expected = sum(np.abs(track.of(name, c)) ** 2 * ride.input_psd[c] for c in ride.components)
        np.testing.assert_allclose(ride.psd_of(name), expected, rtol=1e-10)


def test_one_unit_per_axis_and_log_scales():
    figure = figure_frequency_responses(F, {"m/s^2": [{"label": "a", "values": F}], "m": [{"label": "u", "values": 1 / F}]},
                                        log=True)
    axes = figure.get_axes()
    assert [axis.get_ylabel() for axis in axes] == ["acceleration amplitude [m/s²]", "displacement amplitude [m]"]
    assert all(axis.get_yscale() == "log" for axis in axes)


def test_frf_command_takes_the_track_inputs(tmp_path, capsys):
    plot, table = tmp_path / "frf.png", tmp_path / "frf.csv"
    assert main(["frf", str(MANCHESTER), "--input", "vertical", "--points", "20", "--plot", str(plot), "--log",
                 "-o", str(table)]) == 0
    out = capsys.readouterr().out
    assert "floor_front.az/vertical" in out and "floor_front.uz/vertical" in out
    assert plot.stat().st_size > 0
    header = table.read_text().splitlines()[0]
    assert "floor_rear.az/vertical_acc_amplitude" in header and "floor_rear.uz/vertical_amplitude" in header


@pytest.mark.parametrize("argv, message", [
    (["--input", "gauge"], "--input gauge: the model has no input it drives (rail grounds, docs/ride.md); "
                           "it feels: alignment, vertical, cross_level"),
    (["--input", "vertical", "--dof", "W1.y"], "--dof goes with the alignment response"),
    (["--input", "vertical_"], "invalid choice: 'vertical_'; did you mean vertical?"),
])
def test_frf_command_refuses_what_the_model_cannot_feel(capsys, argv, message):
    assert main(["frf", str(MANCHESTER), *argv]) == 2
    assert message in capsys.readouterr().err
