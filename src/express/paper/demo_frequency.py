"""The demo's Fig. 10: car-body floor acceleration of both cars for a sinusoidal lateral
irregularity of the paper's amplitude (:data:`express.paper.numbers.PAPER`)."""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from express.base.units import KMH
from express.paper.demo_common import Cars, write_figure, write_table
from express.paper.numbers import PAPER

__all__ = ["FLOOR_POINTS", "FRF_FREQUENCIES", "FloorResponse", "measure_floor_response", "write_floor_response"]

#: Frequencies of Fig. 10 [Hz].
FRF_FREQUENCIES = np.geomspace(0.1, 20.0, 300)
#: The output points of the bundled cars compared in Fig. 10.
FLOOR_POINTS = ("floor_front", "floor_rear")


@dataclass(frozen=True)
class FloorResponse:
    """Fig. 10: floor acceleration amplitudes against frequency.

    Attributes
    ----------
    frequencies : numpy.ndarray, shape (F,)
        [Hz].
    amplitudes : mapping of str to numpy.ndarray
        ``"<point>_<car>"`` -> acceleration amplitude [m/s^2], shape (F,).
    peaks : mapping of str to (float, float)
        ``"<point>_<car>"`` -> (largest amplitude [m/s^2], its frequency [Hz]).
    front_rear_difference : mapping of str to float
        Per car, ``max |a_front - a_rear| / max(a_front, a_rear)`` over frequency.
    nearest_mode : mapping or None
        The steered car's mode nearest to its front-floor peak (``description``,
        ``frequency_hz``, ``damping_ratio``), if one lies within a factor 2.
    speed : float
        [m/s].
    amplitude : float
        Irregularity amplitude ``Y`` [m].
    bogie_delay : float
        ``2 l_T / v`` [s]: the rear bogie meets the irregularity this much later.
    notch_spacing : float
        ``v / (2 l_T)`` [Hz]: the spacing of the geometric-filtering dips.
    points : mapping of str to (float, float)
        Output point -> (x [m] ahead of the car-body centre, height above rail [m]).
    """

    frequencies: np.ndarray
    amplitudes: Mapping[str, np.ndarray]
    peaks: Mapping[str, tuple[float, float]]
    front_rear_difference: Mapping[str, float]
    nearest_mode: Mapping[str, object] | None
    speed: float
    amplitude: float
    bogie_delay: float
    notch_spacing: float
    points: Mapping[str, tuple[float, float]]


def _point_place(car, name: str) -> tuple[float, float]:
    """(x, height above rail) of an output point [m], from the model's expressions."""
    from express.model.parameters import expression_value

    model = car.model
    point = next(p for p in model.rail.outputs if p.name == name)

    def number(expression) -> float:
        return expression_value(expression, car.values)

    position = model.body(point.body).position
    return number(position[0]) + number(point.offset[0]), number(position[2]) + number(point.offset[2])


def measure_floor_response(cars: Cars, frequencies: np.ndarray = FRF_FREQUENCIES) -> FloorResponse:
    """Frequency responses of both cars at their model speed."""
    from express.analysis.frequency.frequency import frequency_response
    from express.analysis.stability.stability import eigen_analysis

    amplitude = PAPER.irregularity_amplitude.value
    amplitudes, peaks, difference = {}, {}, {}
    for name, car in cars.items():
        response = frequency_response(car, frequencies, amplitude=amplitude)
        for point in FLOOR_POINTS:
            values = np.abs(response.acceleration_of(point))
            amplitudes[f"{point}_{name}"] = values
            k = int(np.argmax(values))
            peaks[f"{point}_{name}"] = (float(values[k]), float(frequencies[k]))
        front, rear = amplitudes[f"floor_front_{name}"], amplitudes[f"floor_rear_{name}"]
        difference[name] = float(np.max(np.abs(front - rear)) / max(np.max(front), np.max(rear)))
    speed = cars.steered.speed
    frequency = peaks["floor_front_steered"][1]
    modes = [m for m in eigen_analysis(cars.steered, speed).modes if 0.5 * frequency < m.frequency_hz < 2 * frequency]
    near = min(modes, key=lambda m: abs(m.frequency_hz - frequency)) if modes else None
    nearest = None if near is None else {"description": near.describe(), "frequency_hz": near.frequency_hz,
                                         "damping_ratio": near.damping_ratio}
    half_spacing = cars.steered.values["lT"]
    return FloorResponse(
        frequencies=frequencies, amplitudes=amplitudes, peaks=peaks, front_rear_difference=difference,
        nearest_mode=nearest, speed=speed, amplitude=amplitude, bogie_delay=2 * half_spacing / speed,
        notch_spacing=speed / (2 * half_spacing), points={p: _point_place(cars.steered, p) for p in FLOOR_POINTS},
    )


def write_floor_response(outdir: Path, response: FloorResponse, log: Callable[[str], None]) -> list[Path]:
    """Draw Fig. 10 and write it with its data; returns the paths written."""
    from express.analysis.plots import figure_frequency_response

    colours = {"floor_front": "#1f77b4", "floor_rear": "#ff7f0e"}
    where = {"floor_front": ("front", "fr"), "floor_rear": ("rear", "tr")}
    curves, columns = [], {"frequency_hz": response.frequencies}
    for key, values in response.amplitudes.items():
        point, _, car = key.rpartition("_")
        word, index = where[point]
        curves.append({"label": f"{word} ($a_{{{index}}}$), {car}", "values": values, "color": colours[point],
                       "style": car})
        columns[f"{key}_acc_m_s2"] = values
    (x_front, height), (x_rear, _) = response.points["floor_front"], response.points["floor_rear"]
    caption = (f"Sinusoidal lateral irregularity Y = {response.amplitude * 1e3:g} mm at the leading wheelset, delayed "
               f"by 2a/v, 2lT/v, 2(a+lT)/v at the others; straight track, {response.speed / KMH:.0f} km/h, linear "
               f"creep. Floor {height:.2f} m above rail at x = {x_front:+.2f} m and {x_rear:+.2f} m. "
               "Solid: forced steering; dashed: conventional.")
    figure = figure_frequency_response(
        response.frequencies, curves, caption=caption,
        title=f"Fig. 10 - car-body floor acceleration (Y = {response.amplitude * 1e3:g} mm)",
        ylabel="lateral acceleration amplitude [m/s²]",
    )
    paths = write_figure(figure, outdir / "fig10_frequency_response")
    paths.append(write_table(outdir / "fig10_frequency_response.csv", columns))
    log("  Fig. 10: peak floor acceleration " + ", ".join(
        f"{k} {a:.3f} m/s2 at {f:.2f} Hz" for k, (a, f) in response.peaks.items()))
    return paths
