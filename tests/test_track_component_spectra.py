"""Random track components from a spectrum per component (``docs/track.md``, "Random
components"; ``docs/ride.md``, "A track file's spectra"): the track-file tables, the
realisation's band variance, the registry's spectrum, determinism, independence of the
components, a time run against the frequency-domain ride, bad input, and
``express ride --track FILE.toml``."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from cli_support import assert_input_error, run, run_json
from express.analysis.ride.vehicle import ride_response, track_class_spectra
from express.analysis.time.simulate import simulate
from express.analysis.time.track_inputs import track_inputs
from express.base.diagnostics import InputError, ModelError
from express.numeric.statespace import load_vehicle
from express.rail.track import (
    TRACK_COMPONENTS,
    BandLimitedSpectrum,
    SpectrumIrregularity,
    component_seed,
    get_spectrum,
    load_track,
    track_from_dict,
    track_spectra,
)
from express.rail.track.spectra import SPECTRA_BY_COMPONENT
from express.rail.track.tabulated_spectra import TabulatedSpectrum
from test_ride_vehicle import two_axle_toml

#: The file's table of each component.
TABLE = {"alignment": "irregularity", "vertical": "vertical", "cross_level": "cross_level", "gauge": "gauge"}
STRAIGHT = '[[segment]]\ntype = "straight"\nlength = 500.0\n'


def _write(folder, text, name="t.toml"):
    path = folder / name
    path.write_text(text, encoding="utf-8")
    return path


def _spectrum_table(component, spectrum, **keys):
    lines = [f"[{TABLE[component]}]", 'type = "spectrum"', f'spectrum = "{spectrum}"']
    lines += [f"{key} = {json.dumps(value)}" for key, value in keys.items()]
    return "\n".join(lines) + "\n"


def _mean_square_over_a_period(irregularity, step=0.25):
    s = np.arange(0.0, irregularity.period, step)
    return float(np.mean(np.asarray(irregularity.value(s)) ** 2))


# --- the tables ------------------------------------------------------------------------------


@pytest.mark.parametrize("component", TRACK_COMPONENTS)
@pytest.mark.parametrize("name, registered", [("ERRI-high", "erri_high"), ("erri low", "erri_low"),
                                              ("FRA-5", "fra5"), ("fra_6", "fra6"), ("AAR-5", "aar5"),
                                              ("FRA-2", "fra2")])
def test_each_component_draws_from_its_registered_spectrum_with_the_band_variance(tmp_path, component, name,
                                                                                   registered):
    """The realisation of ``[<component>] type = "spectrum"`` draws from
    ``get_spectrum(name, component)`` (the same object), and its harmonics carry the band
    variance: ``sum a_k^2 / 2 = spectrum.variance(2 pi / wavelength_max, 2 pi /
    wavelength_min)``, a telescoping sum of the exact primitive, to rounding (asserted
    1e-12, achieved 2.2e-16); the profile's mean square over one period, sampled every
    0.25 m (the cosines orthogonal on the grid), the same to 1e-9 (achieved 8.9e-16). The band in
    units: 2.5 m to 0.1 km, period 1.5 km. Every name is registered for every component
    (issue 32 item 1: ERRI, FRA and AAR classes each)."""
    text = STRAIGHT + _spectrum_table(component, name, seed=4, wavelength_min="2.5 m", wavelength_max="0.1 km",
                                      period="1.5 km")
    irregularity = load_track(_write(tmp_path, text)).component(component)
    assert isinstance(irregularity, SpectrumIrregularity)
    spectrum = get_spectrum(registered, component)
    assert irregularity.psd_spectrum is spectrum and irregularity.harmonics.spectrum is spectrum
    assert spectrum.component == component
    assert (irregularity.wavelength_min, irregularity.wavelength_max, irregularity.period) == (2.5, 100.0, 1500.0)
    band = spectrum.variance(2 * math.pi / 100.0, 2 * math.pi / 2.5)
    assert np.sum(irregularity.amplitudes**2) / 2 == pytest.approx(band, rel=1e-12)
    assert irregularity.band_variance == pytest.approx(band, rel=1e-15)
    assert _mean_square_over_a_period(irregularity) == pytest.approx(band, rel=1e-9)


def test_the_defaults_and_the_seeds(tmp_path):
    """Defaults: the band 3 m to 120 m, period 10 km, as the alignment's; every seed derived
    from the track's ``seed`` (default 0): the alignment's is that seed itself (a file
    written before the other components could be random draws the same alignment), each
    other component's :func:`component_seed` (a 32-bit word of
    ``SeedSequence([seed, index])``), all four different; a table's own ``seed`` wins."""
    tables = "".join(_spectrum_table(c, "ERRI-low") for c in TRACK_COMPONENTS)
    track = load_track(_write(tmp_path, STRAIGHT + tables))
    seeds = {c: track.component(c).seed for c in TRACK_COMPONENTS}
    assert seeds == {c: component_seed(0, c) for c in TRACK_COMPONENTS}
    assert seeds["alignment"] == 0 and len(set(seeds.values())) == 4
    for c in TRACK_COMPONENTS:
        irregularity = track.component(c)
        assert (irregularity.wavelength_min, irregularity.wavelength_max, irregularity.period) == (3.0, 120.0, 1e4)
    s = np.linspace(0.0, 400.0, 801)
    old = SpectrumIrregularity("erri_low")  # the alignment of a file without seeds, as before
    np.testing.assert_array_equal(track.irregularity.value(s), old.value(s))
    seeded = load_track(_write(tmp_path, "seed = 7\n" + STRAIGHT + tables + "seed = 3\n"))  # gauge's own seed
    assert {c: seeded.component(c).seed for c in TRACK_COMPONENTS} == {
        "alignment": 7, "vertical": component_seed(7, "vertical"), "cross_level": component_seed(7, "cross_level"),
        "gauge": 3}
    with pytest.raises(InputError, match="non-negative integer"):
        component_seed(-1, "vertical")


def test_the_same_seed_gives_the_same_arrays(tmp_path):
    """Two reads of one file: the same phases, amplitudes and values, bit for bit; another
    track seed: other phases for every component, the same amplitudes."""
    tables = "".join(_spectrum_table(c, "FRA-5") for c in TRACK_COMPONENTS)
    path = _write(tmp_path, "seed = 11\n" + STRAIGHT + tables)
    first, second = load_track(path), load_track(path)
    other = load_track(_write(tmp_path, "seed = 12\n" + STRAIGHT + tables, "other.toml"))
    s = np.linspace(-50.0, 700.0, 3001)
    for c in TRACK_COMPONENTS:
        a, b, o = first.component(c), second.component(c), other.component(c)
        for field in ("wavenumbers", "amplitudes", "phases"):
            np.testing.assert_array_equal(getattr(a, field), getattr(b, field))
        np.testing.assert_array_equal(a.value(s), b.value(s))
        np.testing.assert_array_equal(a.rate(s), b.rate(s))
        np.testing.assert_array_equal(a.amplitudes, o.amplitudes)
        assert not np.any(a.phases == o.phases)


def _correlation(first, second):
    """Sample correlation over one period of two realisations on the same wavenumbers,
    ``sum a_k b_k cos(phi_k - psi_k) / sqrt(sum a_k^2 sum b_k^2)`` (the cosines are
    orthogonal over the period), and its standard deviation over independent uniform
    phases, ``sqrt(sum a_k^2 b_k^2 / 2) / sqrt(sum a_k^2 sum b_k^2)`` (Var cos = 1/2)."""
    a, b = first.amplitudes, second.amplitudes
    norm = math.sqrt(np.sum(a**2) * np.sum(b**2))
    return (float(np.sum(a * b * np.cos(first.phases - second.phases)) / norm),
            float(math.sqrt(np.sum(a**2 * b**2) / 2) / norm))


def test_the_components_are_uncorrelated(tmp_path):
    """The four components of a track (ERRI high, 3-120 m, period 10 km, the defaults),
    each pair's sample cross-correlation over one period, from profiles sampled every
    0.25 m: equal to the harmonic formula of :func:`_correlation` (1e-9), and within 4 of
    its standard deviations of zero. Why a bound and not zero: a finite realisation has
    about ``N_eff = sum a^2 sum b^2 / sum a^2 b^2`` independent harmonics (the red spectra
    put most power in the longest waves), so its sample correlation scatters by
    ``1/sqrt(2 N_eff)`` about the zero of the ensemble: here 0.021-0.048 (the alignment
    and vertical spectra share their shape, the largest). Measured: |rho| <= 0.044, at
    most 1.73 standard deviations; the sampled and the harmonic formula agree to 1.4e-15.
    Over 100 track seeds the z-scores have a standard deviation within 0.8-1.2 (the stated
    spread; achieved 0.95-1.03); the same explicit seed for the alignment and the vertical
    (refused by the reader) would give the same phases, correlation 1.0."""
    tables = "".join(_spectrum_table(c, "ERRI-high") for c in TRACK_COMPONENTS)
    track = load_track(_write(tmp_path, STRAIGHT + tables))
    s = np.arange(0.0, 1e4, 0.25)
    values = {c: np.asarray(track.component(c).value(s)) for c in TRACK_COMPONENTS}
    pairs = [(c1, c2) for i, c1 in enumerate(TRACK_COMPONENTS) for c2 in TRACK_COMPONENTS[i + 1:]]
    for c1, c2 in pairs:
        rho, sigma = _correlation(track.component(c1), track.component(c2))
        sampled = np.mean(values[c1] * values[c2]) / math.sqrt(np.mean(values[c1] ** 2) * np.mean(values[c2] ** 2))
        assert sampled == pytest.approx(rho, abs=1e-9)
        assert 0.02 < sigma < 0.05 and abs(rho) < 4 * sigma, (c1, c2, rho, sigma)
    z = {pair: [] for pair in pairs}
    for seed in range(100):
        drawn = track_from_dict({"seed": seed, "segment": [{"type": "straight", "length": 10.0}],
                                 **{TABLE[c]: {"type": "spectrum", "spectrum": "erri_high"} for c in TRACK_COMPONENTS}})
        for c1, c2 in pairs:
            rho, sigma = _correlation(drawn.component(c1), drawn.component(c2))
            z[(c1, c2)].append(rho / sigma)
    for pair, scores in z.items():
        assert 0.8 < np.std(scores) < 1.2, pair
    same = [SpectrumIrregularity(get_spectrum("erri_high", c), seed=5) for c in ("alignment", "vertical")]
    assert _correlation(*same)[0] > 0.9


# --- a time run against the frequency-domain ride --------------------------------------------

SPEED, KH, CH, B0 = 27.0, 1.0e9, 2.0e5, 0.75  # the two-axle model of tests/test_track_components.py
BAND, PERIOD, LEAD = (3.0, 60.0), 400.0, 60.0  # m


@pytest.fixture(scope="module")
def two_axle(tmp_path_factory):
    path = tmp_path_factory.mktemp("component_spectra") / "two_axle.toml"
    path.write_text(two_axle_toml(contact_damping=CH), encoding="utf-8")
    return load_vehicle(path)


def _wheel_loads(vehicle, track, dt):
    """Each wheel's dynamic load ``-(kH d + cH d')``, ``d`` the contact deflection, over the
    last full period of a linear run (the track is LEAD + PERIOD + LEAD long)."""
    result = simulate(vehicle, track, speed=SPEED, dt=dt, flange=False, saturation=False, progress=False)
    inputs = track_inputs(vehicle, track, result.distance, SPEED)
    steps = round(PERIOD / (SPEED * dt))
    last = slice(result.time.size - 1 - steps, result.time.size - 1)
    loads = {}
    for wheelset in ("W1", "W2"):
        z, rx = vehicle.dof_index(f"{wheelset}.z"), vehicle.dof_index(f"{wheelset}.rx")
        for side, arm in (("L", B0), ("R", -B0)):
            rail = vehicle.inputs.index(f"{wheelset}_rail{side}.z")
            deflection = result.q[:, z] + arm * result.q[:, rx] - inputs.u[:, rail]
            rate = result.q_dot[:, z] + arm * result.q_dot[:, rx] - inputs.u_rate[:, rail]
            loads[f"{wheelset}.dQ{side}"] = -(KH * deflection + CH * rate)[last]
    return loads


def _vertical_track(tmp_path, seed):
    text = ('[[segment]]\ntype = "straight"\nlength = ' + f"{PERIOD + 2 * LEAD}\n"
            + _spectrum_table("vertical", "ERRI-high", seed=seed, wavelength_min=f"{BAND[0]} m",
                              wavelength_max=f"{BAND[1]} m", period=f"{PERIOD} m"))
    return load_track(_write(tmp_path, text, f"vertical_{seed}.toml"))


def test_wheel_loads_of_a_time_run_match_the_frequency_domain_ride(two_axle, tmp_path):
    """The 3-D two-axle vehicle (1 GN/m, 2e5 N s/m contact springs to per-rail grounds) at
    27 m/s on a track file's ERRI-high vertical level, 3-60 m (0.45-9 Hz), period 400 m,
    seed 1, in a linear ``simulate`` run: the RMS of each wheel's dynamic load over the last
    full period against ``ride_response`` with the file's spectrum
    (:func:`track_spectra`: the same spectrum over the same band; 8001 frequencies over the
    band, trapezoids).

    Finite-realisation scatter: over a whole period the cosines are orthogonal, so the mean
    square of the (periodic, linear) response is ``sum_k |H(f_k)|^2 a_k^2 / 2`` whatever the
    phases: no phase scatter (a second seed moves the RMS by 3.5e-5-4.2e-5, the transient's
    residue; asserted 5e-4). What is left: (a) the rectangle rule of the harmonic sum
    against the integral, 1.3e-4 here (asserted 5e-4, computed with the ride's own transfer
    functions at the harmonics); (b) the step, second order: 0.11-0.44 % at 1 ms,
    0.027-0.10 % at 0.5 ms against the harmonic sum (ratio 3.93-4.26, asserted 3.5-4.6).
    Asserted: the 0.5 ms run within 0.3 % of the ride (achieved 0.014-0.12 %). Over a
    window that is not a whole number of periods (a measured track) the RMS would scatter
    by about ``1 / (2 sqrt(B_e T))``, ``B_e = (int G)^2 / int G^2`` the statistical
    bandwidth (Bendat & Piersol, *Random Data*, 4th ed., section 8.2), here 1.4 Hz (front
    wheels) and 3.0 Hz (rear): 11 % and 7.5 % over the 14.8 s of this period; the RMS of
    the half periods of the two seeds lie at 0.86-1.12 of the ride's (asserted: a spread of
    more than 1 %), as that predicts."""
    track = _vertical_track(tmp_path, 1)
    spectra, notes = track_spectra(track)
    assert list(spectra) == ["vertical"] and notes == ()
    assert spectra["vertical"].base is get_spectrum("erri_high", "vertical")
    f = np.linspace(SPEED / BAND[1], SPEED / BAND[0], 8001)
    ride = ride_response(two_axle, spectra, SPEED, f)
    harmonics = track.vertical.harmonics
    at_lines = ride_response(two_axle, spectra, SPEED, harmonics.wavenumbers * SPEED / (2 * math.pi))
    fine, coarse = _wheel_loads(two_axle, track, 0.0005), _wheel_loads(two_axle, track, 0.001)
    other_seed = _wheel_loads(two_axle, _vertical_track(tmp_path, 2), 0.0005)
    halves = []
    for name, load in fine.items():
        predicted = ride.rms(name)
        transfer = at_lines.transfer[:, at_lines.index(name), 0]
        line_sum = math.sqrt(np.sum(np.abs(transfer) ** 2 * harmonics.amplitudes**2 / 2))
        assert line_sum == pytest.approx(predicted, rel=5e-4)  # achieved 1.3e-4
        rms_fine, rms_coarse = (math.sqrt(np.mean(x**2)) for x in (load, coarse[name]))
        assert rms_fine == pytest.approx(predicted, rel=3e-3), name  # achieved 0.014-0.12 %
        assert 3.5 < (rms_coarse / line_sum - 1) / (rms_fine / line_sum - 1) < 4.6, name  # second order
        assert math.sqrt(np.mean(other_seed[name] ** 2)) == pytest.approx(rms_fine, rel=5e-4)  # no phase scatter
        half = load.size // 2
        for history in (load, other_seed[name]):
            halves += [math.sqrt(np.mean(history[:half] ** 2)) / predicted, math.sqrt(np.mean(history[half:] ** 2))
                       / predicted]
        assert 1000.0 < predicted < 5000.0  # N: a few kN on a 57 kN wheel
    assert np.ptp(halves) > 0.01


# --- bad input ------------------------------------------------------------------------------

_VERTICAL_ONLY = TabulatedSpectrum("test vertical only", (0.01, 10.0), (1e-6, 1e-6), "vertical")


@pytest.fixture
def vertical_only(monkeypatch):
    """A user's spectrum registered for the vertical only (removed after the test)."""
    monkeypatch.setitem(SPECTRA_BY_COMPONENT["vertical"], "test_vertical_only", _VERTICAL_ONLY)

BAD = [
    # (tables after the segment, line, item, message)
    (_spectrum_table("vertical", "FRA-9"), 8, "vertical (spectrum)",
     "unknown spectrum 'FRA-9' (known vertical spectra: erri_low, erri_high, fra1"),
    (_spectrum_table("gauge", "test vertical only"), 8, "gauge (spectrum)",
     "unknown spectrum 'test vertical only' (known gauge spectra: erri_low, erri_high, fra1, fra2, fra3, fra4, fra5, "
     "fra6, aar1, aar2, aar3, aar4, aar5, aar6); 'test vertical only' is registered for the vertical, not the gauge"),
    (_spectrum_table("alignment", "AAR-7"), 8, "irregularity (spectrum)",
     "unknown spectrum 'AAR-7' (known alignment spectra: fra5, fra6, erri_low, erri_high, fra1, fra2, fra3, fra4, "
     "aar1, aar2, aar3, aar4, aar5, aar6)"),
    ('[cross_level]\ntype = "spectrum"\n', 6, "cross_level (spectrum)",
     "missing 'spectrum' (one of erri_low, erri_high, fra1"),
    ('[cross_level]\ntype = "spectrum"\nspectrum = 5\n', 8, "cross_level (spectrum)",
     "'spectrum' must be the name of a spectrum (one of erri_low"),
    (_spectrum_table("vertical", "erri_low", wavelength_min="50 m", wavelength_max="20 m"), 9, "vertical (spectrum)",
     "'wavelength_min' (50.0) must be < 'wavelength_max' (20.0)"),
    (_spectrum_table("vertical", "erri_low", wavelength_min="3 kg"), 9, "vertical (spectrum)",
     "'wavelength_min': unit kg is a mass (kg), expected a length (m)"),
    (_spectrum_table("gauge", "erri_low", wavelength_max=-5), 9, "gauge (spectrum)",
     "'wavelength_max' must be > 0 m, got -5.0"),
    (_spectrum_table("vertical", "erri_low", period="100 m"), 9, "vertical (spectrum)",
     "'period' (100.0) must be >= 'wavelength_max' (120.0)"),
    (_spectrum_table("vertical", "erri_low", wavelength_min="1 mm", period="1000 km"), 10, "vertical (spectrum)",
     "'period' (1e+06 m) with 'wavelength_min' (0.001 m) and 'wavelength_max' (120 m) needs 1e+09 harmonics, more "
     "than the limit 200000"),
    (_spectrum_table("cross_level", "erri_low", seed=-2), 9, "cross_level (spectrum)",
     "'seed' must be a non-negative integer, got -2"),
    (_spectrum_table("cross_level", "erri_low", seed=1.5), 9, "cross_level (spectrum)",
     "'seed' must be a non-negative integer, got 1.5"),
    (_spectrum_table("vertical", "erri_low", wavelength=3), 9, "vertical (spectrum)",
     "unknown key 'wavelength' (allowed: period, seed, spectrum, type, wavelength_max, wavelength_min)"),
    (_spectrum_table("vertical", "erri_low", seed=5) + _spectrum_table("gauge", "erri_low", seed=5), 13,
     "gauge (spectrum)", "seed 5 is that of [vertical] too: the two would draw the same phases"),
    (_spectrum_table("vertical", "erri_low"), 1, "track", "'seed' must be a non-negative integer, got 'one'"),
]


@pytest.mark.parametrize("tables, line, item, message", BAD, ids=[f"{case[2]}: {case[3][:40]}" for case in BAD])
def test_bad_spectrum_tables_are_reported_with_file_line_and_item(tmp_path, vertical_only, tables, line, item,
                                                                  message):
    head = 'seed = "one"\n' if item == "track" else "\n"
    path = _write(tmp_path, head + STRAIGHT + "\n" + tables)
    with pytest.raises(InputError) as info:
        load_track(path)
    assert f"{path}:{line}: {item}: {message}" in str(info.value)


def test_every_problem_at_once_and_exit_2_with_nothing_written(capsys, tmp_path):
    """One file with a bad track seed and one problem in each of its four component
    tables: every one reported, by line; from ``express simulate`` exit 2 and no output
    file."""
    tables = "".join(table for table, *_ in (BAD[0], BAD[2], BAD[3], BAD[7]))
    path = _write(tmp_path, 'seed = "one"\n' + STRAIGHT + tables)
    with pytest.raises(ModelError) as info:
        load_track(path)
    found = [(p.line, p.item) for p in info.value.problems]
    assert found == [(1, "track"), (7, "vertical (spectrum)"), (10, "irregularity (spectrum)"),
                     (11, "cross_level (spectrum)"), (16, "gauge (spectrum)")]
    out = tmp_path / "run.csv"
    assert_input_error(capsys, "simulate", "examples/conventional.toml", "--track", str(path), "-o", str(out),
                       mentions="unknown spectrum 'FRA-9'")
    assert not out.exists()


# --- express ride --track FILE.toml ------------------------------------------------------------


@pytest.fixture(scope="module")
def two_axle_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("component_spectra_cli") / "two_axle.toml"
    path.write_text(two_axle_toml(contact_damping=CH), encoding="utf-8")
    return path


def test_ride_on_a_track_file_is_the_ride_on_its_spectra(capsys, tmp_path, two_axle_file):
    """``express ride --track FILE.toml`` takes each component's spectrum over its band: a
    file with the four ERRI-high components, 3-120 m, gives at 100 km/h the same numbers
    as ``--track ERRI-high`` over the matching frequencies (``--fmin v/120 --fmax v/3``:
    every grid point inside the band, so the same PSDs; 1e-9, achieved rounding); the notes
    say what was taken and the coherence assumption; a narrower band in the file lowers
    every RMS; a deterministic component is named as left out."""
    tables = "".join(_spectrum_table(c, "ERRI-high") for c in TRACK_COMPONENTS)
    path = _write(tmp_path, STRAIGHT + tables)
    v = 100 / 3.6
    band = ["--fmin", repr(v / 120.0), "--fmax", repr(v / 3.0), "--points", "400", "--speed", "100"]
    from_file = run_json(capsys, "ride", two_axle_file, "--track", path, *band)
    from_class = run_json(capsys, "ride", two_axle_file, "--track", "ERRI-high", *band)
    assert from_file["components"] == from_class["components"] == ["alignment", "vertical", "cross_level"]
    for point, comfort in from_class["output_points"].items():
        for axis, rms in comfort["rms"].items():
            assert from_file["output_points"][point]["rms"][axis] == pytest.approx(rms, rel=1e-9)
    for wheelset, forces in from_class["wheelsets"].items():
        assert from_file["wheelsets"][wheelset]["dq_rms"]["L"] == pytest.approx(forces["dq_rms"]["L"], rel=1e-9)
        assert from_file["wheelsets"][wheelset]["y_rms"] == pytest.approx(forces["y_rms"], rel=1e-9)
    taken = [note for note in from_file["notes"] if note.startswith("track file")]
    assert taken and "vertical from ERRI B176 high vertical, wavelengths 3-120 m" in taken[0]
    assert "mutually uncorrelated, each fully coherent between the wheelsets with its delay" in taken[0]
    # the file's own band: 3-30 m drops the long waves, and every RMS with them
    narrow = _write(tmp_path, STRAIGHT + _spectrum_table("vertical", "ERRI-high", wavelength_max="30 m")
                    + '[cross_level]\ntype = "sinusoid"\namplitude = "2 mm"\nwavelength = "20 m"\n', "narrow.toml")
    data = run_json(capsys, "ride", two_axle_file, "--track", narrow, "--points", "400")
    whole = run_json(capsys, "ride", two_axle_file, "--track", "ERRI-high", "--points", "400")
    assert data["components"] == ["vertical"]
    assert data["wheelsets"]["W1"]["dq_rms"]["L"] < whole["wheelsets"]["W1"]["dq_rms"]["L"]
    assert any("cross_level: the track file gives a SinusoidIrregularity" in note for note in data["notes"])


def test_ride_refuses_a_track_file_without_spectra_or_with_problems(capsys, tmp_path, two_axle_file):
    """Exit 2, nothing written: a file with no random component, and a bad file (its
    problems by line, as the reader gives them)."""
    out = tmp_path / "psd.csv"
    shapes = _write(tmp_path, STRAIGHT + '[vertical]\ntype = "points"\npoints = [[0, 0], [10, 0.003]]\n', "shapes.toml")
    assert_input_error(capsys, "ride", two_axle_file, "--track", shapes, "-o", out,
                       mentions="the track file has no random component")
    bad = _write(tmp_path, STRAIGHT + _spectrum_table("gauge", "FRA-9"), "bad.toml")
    err = assert_input_error(capsys, "ride", two_axle_file, "--track", bad, "-o", out,
                             mentions=f"{bad}:6: gauge (spectrum): unknown spectrum 'FRA-9'")
    assert "known gauge spectra" in err
    assert not out.exists()
    status, _, _ = run(capsys, "ride", two_axle_file, "--track", "examples/tracks/straight_erri_high.toml",
                       "--points", "100")
    assert status == 0


def test_the_example_track_file(capsys):
    """``examples/tracks/straight_erri_high.toml``: the four ERRI-high components, seeds
    derived from its one seed, each from its component's registered spectrum."""
    track = load_track("examples/tracks/straight_erri_high.toml")
    assert track.applied_components == TRACK_COMPONENTS
    for component in TRACK_COMPONENTS:
        assert track.component(component).psd_spectrum is get_spectrum("erri_high", component)
        assert track.component(component).seed == component_seed(1, component)
    spectra, _ = track_spectra(track)
    for component, spectrum in spectra.items():
        assert isinstance(spectrum, BandLimitedSpectrum)
        assert spectrum.base is track_class_spectra("ERRI-high")[component]
