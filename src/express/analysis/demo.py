"""``express demo``: the paper's results with the bundled vehicles, in well under a minute.

:func:`run_demo` writes into one directory:

``matrices/``
    The symbolic matrices of ``forced_steering``, ``conventional`` and the paper's
    Fig. 2/5 ``lever``, each as MATLAB (``.m``), LaTeX (``.tex``) and JSON.
``fig3_lever_step``, ``fig9_curving``, ``fig10_frequency_response``, ``fig11_critical_speed``
    Each as ``.png``, ``.svg`` and the data behind it as ``.csv`` (SI units).
``summary.md``
    Key figures next to the paper's stated values, each with a sentence on the
    difference and why it arises; ``summary.json`` holds the same numbers.

Nothing here is tuned to the paper: the vehicle parameters are the bundled ones
(``docs/parameters.md``).  The choices the paper leaves open are stated in the figure
captions and in the summary.
"""

from __future__ import annotations

import csv
import io
import json
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..io.output import json_safe

__all__ = ["run_demo", "find_examples", "lever_step_response", "LEVER_CASES", "PAPER"]

KMH = 1.0 / 3.6

#: The paper's stated values (Tanifuji & Suzuki 2001, section 4.4).
PAPER = {
    "lever_angle_rad": 0.04,
    "lever_angle_geometric_rad": 0.06,
    "steering_angle_ideal_rad": 0.0029,
    "Q1_conventional_kN": 32.0,
    "Q1_steered_kN": 14.0,
    "conicity_of_max_vcr": 0.1,
}

#: Table 1 leverage cases used for Fig. 3 (lLU, lLL [m], kLU, kLL [N/m]).  Case 3 as
#: printed (0.06, 0.30, 1000, 5000 kN/m) violates its own condition lLU kLU = lLL kLL
#: (60 against 1500 kN): the arms are swapped here, which satisfies it (300 = 300 kN).
LEVER_CASES = (
    {"case": 1, "condition": "lLU kLU < lLL kLL", "lLU": 0.30, "lLL": 0.06, "kLU": 500e3, "kLL": 5500e3},
    {"case": 2, "condition": "lLU kLU > lLL kLL", "lLU": 0.06, "lLL": 0.30, "kLU": 5500e3, "kLL": 500e3},
    {"case": 3, "condition": "lLU kLU = lLL kLL", "lLU": 0.30, "lLL": 0.06, "kLU": 1000e3, "kLL": 5000e3},
)
#: Values of the lever model that Table 1 does not give (our choice, stated in Fig. 3):
#: lever inertia J2 [kg m^2] (as the bundled steering lever), a rotational damper on the
#: lever c_L [N m s/rad] added so that the curve settles, pin offset b [m], step of q1 [rad].
LEVER_VALUES = {"J1": 10.0, "m": 20.0, "J2": 0.5, "b": 1.0, "c": 0.0}
LEVER_DAMPING = 40.0
LEVER_STEP = 1e-3

V_MAX = 200.0  # m/s, top of the critical-speed scan
CONICITIES = np.round(np.linspace(0.02, 0.40, 39), 4)
FRF_FREQUENCIES = np.geomspace(0.1, 20.0, 300)


def find_examples(examples: Path | None = None) -> Path:
    """The directory of the bundled models (``examples/`` of the source tree)."""
    candidates = [examples] if examples is not None else [
        Path(__file__).resolve().parents[3] / "examples",
        Path.cwd() / "examples",
    ]
    for candidate in candidates:
        if candidate is not None and (candidate / "forced-steering.toml").is_file():
            return candidate
    where = ", ".join(str(c) for c in candidates if c is not None)
    raise ValueError(f"cannot find the bundled models (forced-steering.toml) in {where}; give --examples DIR")


# --------------------------------------------------------------------------------------
# small helpers
# --------------------------------------------------------------------------------------


def _csv(columns: dict[str, object]) -> str:
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(list(columns))
    data = [list(v) if not isinstance(v, np.ndarray) else v.tolist() for v in columns.values()]
    for row in zip(*data):
        writer.writerow([f"{x:.9g}" if isinstance(x, float) else ("" if x is None else x) for x in row])
    return buffer.getvalue()


def _write(path: Path, text: str) -> None:
    from ..io.output import write_output

    write_output(path, text)


def _figure(figure, stem: Path) -> list[Path]:
    from .plots import save_figure

    return save_figure(figure, [stem.with_suffix(".png"), stem.with_suffix(".svg")])


def _steady(values: np.ndarray, distance: np.ndarray, window: tuple[float, float]) -> float:
    inside = (distance >= window[0]) & (distance <= window[1])
    return float(np.mean(values[inside]))


# --------------------------------------------------------------------------------------
# Fig. 3: the lever of Figs. 2 and 5
# --------------------------------------------------------------------------------------


def lever_step_response(equations, case: dict, time_s: np.ndarray, *, step: float = LEVER_STEP,
                        damping: float = LEVER_DAMPING) -> tuple[np.ndarray, float]:
    """``q2(t)`` of the lever after a step ``q1 = step`` at ``t = 0`` (``q1`` prescribed).

    The lever row of the generated equations, ``M22 q2'' + (C22 + c_L) q2' + K22 q2 =
    -K21 q1``, is integrated exactly (matrix exponential); ``c_L`` is the added damper.
    Returns ``(q2, static q2)``.
    """
    from scipy.linalg import expm

    from ..statespace import evaluate_matrices

    values = {**LEVER_VALUES, **{k: case[k] for k in ("lLU", "lLL", "kLU", "kLL")}}
    values = {name: values[name] for name in equations.parameters}
    matrices = evaluate_matrices(equations, values)
    i1, i2 = equations.dofs.index("B1.rz"), equations.dofs.index("B2.ry")
    mass = matrices["M"][i2, i2]
    damping_total = matrices["C"][i2, i2] + damping
    stiffness = matrices["K"][i2, i2]
    coupling = matrices["K"][i2, i1]
    static = -coupling * step / stiffness
    a = np.array([[0.0, 1.0], [-stiffness / mass, -damping_total / mass]])
    phi = expm(a * float(time_s[1] - time_s[0]))
    # the deviation from the static value starts at -static (q2 = 0, at rest) at t = 0
    deviation = np.array([-static, 0.0])
    q2 = np.zeros(time_s.size)
    for k, t in enumerate(time_s):
        if t < 0:
            continue
        q2[k] = static + deviation[0]
        deviation = phi @ deviation
    return q2, float(static) + 0.0  # no negative zero


def _figure3(outdir: Path, examples: Path, log) -> dict:
    from ..io import load_model
    from ..rail.build import generate_vehicle
    from .plots import figure_lever_step

    equations = generate_vehicle(load_model(examples / "lever.exp")).equations
    time_s = np.round(np.arange(-0.01, 0.12 + 1e-12, 1e-4), 6)
    cases, columns = [], {"time_s": time_s}
    statics = {}
    for case in LEVER_CASES:
        q2, static = lever_step_response(equations, case, time_s)
        statics[case["case"]] = static
        condition = case["condition"].replace("lLU kLU", "$l_{LU}k_{LU}$").replace("lLL kLL", "$l_{LL}k_{LL}$")
        label = (f"case {case['case']}: {condition}  ($l_{{LU}}$ {case['lLU']:.2f} m, $l_{{LL}}$ {case['lLL']:.2f} m, "
                 f"$k_{{LU}}$ {case['kLU'] / 1e3:.0f}, $k_{{LL}}$ {case['kLL'] / 1e3:.0f} kN/m)")
        cases.append({"label": label, "q2": q2, "steady": static})
        columns[f"q2_case{case['case']}_rad"] = q2
    caption = (f"examples/lever.exp, q1 prescribed as a step of {LEVER_STEP * 1e3:g} mrad. Our choices: J2 = "
               f"{LEVER_VALUES['J2']:g} kg m², an added lever damper c_L = {LEVER_DAMPING:g} N m s/rad, "
               f"b = {LEVER_VALUES['b']:g} m. Case 3 as printed in Table 1 (lLU 0.06 m, lLL 0.30 m) violates "
               "lLU kLU = lLL kLL; the arms are swapped here (0.30/0.06 m) so that it holds.")
    figure = figure_lever_step(time_s, cases, step=LEVER_STEP, caption=caption)
    paths = _figure(figure, outdir / "fig3_lever_step")
    _write(outdir / "fig3_lever_step.csv", _csv(columns))
    log(f"  Fig. 3: static q2 = {', '.join(f'{v * 1e3:+.3f}' for v in statics.values())} mrad")
    return {"static_q2_rad": statics, "files": paths}


# --------------------------------------------------------------------------------------
# Fig. 9: curve negotiation
# --------------------------------------------------------------------------------------


@dataclass
class _Cars:
    steered: object
    conventional: object


def _figure9(outdir: Path, cars: _Cars, log) -> dict:
    from ..rail.track import paper_curve
    from .plots import figure_curving
    from .simulate import simulate

    track = paper_curve()
    runs = {name: simulate(vehicle, track, progress=False) for name, vehicle in
            (("steered", cars.steered), ("conventional", cars.conventional))}
    steered, conventional = runs["steered"], runs["conventional"]
    if steered.distance.size != conventional.distance.size:  # same speed and dt: same grid
        raise RuntimeError("the two runs have different time grids")
    values = cars.steered.values
    radius = 400.0
    boundaries = track.boundaries  # 0, 50, 145, 315, 410, 460
    curve_start, curve_end = float(boundaries[2]), float(boundaries[3])
    span = max(w.station for w in cars.steered.wheelsets) - min(w.station for w in cars.steered.wheelsets)
    window = (curve_start + span + 5.0, curve_end - 5.0)
    d = steered.distance

    def pick(result, keys):
        return {k: result.outputs[k] for k in keys if k in result.outputs} | {"d1": result.distance}

    keys = ("rho1", "theta_L1", "psi_TW1", "psi_TW2", "Q1", "Q2")
    data_s, data_c = pick(steered, keys), pick(conventional, keys)
    ideal = values["a"] / radius
    geometric = values["bL"] * values["lT"] / (radius * values["lLU"])
    caption = ("Paper's curve: 50 m straight, 95 m half-sine transition, R = 400 m with 95 mm cant for 170 m, "
               "transition, straight; left curve; 120 km/h; flange clearance 6 mm, creep saturation (mu = 0.3). "
               "Solid: forced steering; dashed: conventional bogies. (a): the axes are scaled so that the geometric "
               "lever angle b_L l_T rho_1 / l_LU would lie on the curvature curve.")
    figure = figure_curving(data_s, data_c, ideal_yaw=ideal, geometric_lever=geometric,
                            title="Fig. 9 - curve negotiation, R = 400 m, V = 120 km/h", caption=caption)
    paths = _figure(figure, outdir / "fig9_curving")
    columns = {"d1_m": d, "rho1_1_m": data_s["rho1"], "theta_L1_rad": data_s["theta_L1"]}
    for vehicle, data in (("steered", data_s), ("conventional", data_c)):
        for k in ("psi_TW1", "psi_TW2"):
            columns[f"{k}_{vehicle}_rad"] = data[k]
        for k in ("Q1", "Q2"):
            columns[f"{k}_{vehicle}_N"] = data[k]
    _write(outdir / "fig9_curving.csv", _csv(columns))

    steady = {
        f"{k}_{vehicle}": _steady(data[k], d, window)
        for vehicle, data in (("steered", data_s), ("conventional", data_c))
        for k in ("psi_TW1", "psi_TW2", "Q1", "Q2")
    }
    steady["theta_L1"] = _steady(data_s["theta_L1"], d, window)
    peaks = {f"{k}_{vehicle}_max": float(np.max(data[k])) for vehicle, data in
             (("steered", data_s), ("conventional", data_c)) for k in ("Q1", "Q2")}
    flanging = {
        vehicle: [bool(_steady(np.abs(result.outputs[f"flange{j}"]), d, window) > 0) for j in (1, 2)]
        for vehicle, result in runs.items()
    }
    # cant-deficiency force on the car body's half, a bogie and its two wheelsets
    v = cars.steered.speed
    deficiency = v**2 / radius - values["g"] * 0.095 / values["G"]
    bogie_force = (values["mc"] / 2 + values["mt"] + 2 * values["mw"]) * deficiency
    # link force and the stiffness the paper's 0.04 rad would need at that force (estimate)
    stroke = values["bL"] * values["lT"] / radius
    link_force = values["kLU"] * (stroke - values["lLU"] * steady["theta_L1"])
    klu_paper = link_force / (stroke - values["lLU"] * PAPER["lever_angle_rad"])
    # check of that estimate (a sensitivity run, not a change of the model)
    softer = simulate(cars.steered.with_values({"kLU": klu_paper}), track, progress=False)
    theta_softer = _steady(softer.outputs["theta_L1"], softer.distance, window)
    log(f"  Fig. 9: theta_L1 = {steady['theta_L1']:.4f} rad, Q1 = {steady['Q1_steered'] / 1e3:.1f} kN (steered), "
        f"{steady['Q1_conventional'] / 1e3:.1f} kN (conventional)")
    return {
        "files": paths,
        "window_m": window,
        "steady": steady,
        "peaks": peaks,
        "flanging": flanging,
        "ideal_yaw_rad": ideal,
        "geometric_lever_rad": geometric,
        "cant_deficiency_m_s2": deficiency,
        "bogie_lateral_force_N": bogie_force,
        "link_force_N": link_force,
        "kLU_N_m": values["kLU"],
        "kLU_for_paper_angle_N_m": klu_paper,
        "theta_with_that_kLU_rad": theta_softer,
        "lever_ratio": values["lLL"] / values["lLU"],
        "ideal_lever_ratio": values["a"] / values["lT"],
        "car_mass_kg": values["mc"] + 2 * values["mt"] + 4 * values["mw"],
        "kx1_steered": values.get("kx1"),
        "kx1_conventional": cars.conventional.values.get("kx1"),
    }


# --------------------------------------------------------------------------------------
# Fig. 10: frequency response
# --------------------------------------------------------------------------------------


def _figure10(outdir: Path, cars: _Cars, log) -> dict:
    from .frequency import frequency_response
    from .plots import figure_frequency_response

    frequencies = FRF_FREQUENCIES
    responses = {name: frequency_response(vehicle, frequencies, amplitude=1e-3)
                 for name, vehicle in (("steered", cars.steered), ("conventional", cars.conventional))}
    curves, columns, peaks = [], {"frequency_hz": frequencies}, {}
    colours = {"floor_front": "#1f77b4", "floor_rear": "#ff7f0e"}
    where = {"floor_front": "front", "floor_rear": "rear"}
    for vehicle, response in responses.items():
        for point in ("floor_front", "floor_rear"):
            values = np.abs(response.acceleration_of(point))
            curves.append({"label": f"{where[point]} ($a_{{{'fr' if point == 'floor_front' else 'tr'}}}$), {vehicle}",
                           "values": values, "color": colours[point], "style": vehicle})
            columns[f"{point}_{vehicle}_acc_m_s2"] = values
            k = int(np.argmax(values))
            peaks[f"{point}_{vehicle}"] = (float(values[k]), float(frequencies[k]))
    speed = cars.steered.speed
    from .stability import eigen_analysis

    amplitude, frequency = peaks["floor_front_steered"]
    modes = [m for m in eigen_analysis(cars.steered, speed).modes if 0.5 * frequency < m.frequency_hz < 2 * frequency]
    near = min(modes, key=lambda m: abs(m.frequency_hz - frequency)) if modes else None
    caption = (f"Sinusoidal lateral irregularity Y = 1 mm at the leading wheelset, delayed by 2a/v, 2lT/v, 2(a+lT)/v at "
               f"the others; straight track, {speed / KMH:.0f} km/h, linear creep. Floor 1.2 m above rail, "
               "above the bogie centres. Solid: forced steering; dashed: conventional.")
    figure = figure_frequency_response(
        frequencies, curves, caption=caption,
        title="Fig. 10 - car-body floor acceleration above the bogie centres (Y = 1 mm)",
        ylabel="lateral acceleration amplitude [m/s²]",
    )
    paths = _figure(figure, outdir / "fig10_frequency_response")
    _write(outdir / "fig10_frequency_response.csv", _csv(columns))
    log("  Fig. 10: peak floor acceleration " + ", ".join(f"{k} {a:.3f} m/s2 at {f:.2f} Hz" for k, (a, f) in peaks.items()))
    nearest = None if near is None else {"description": near.describe(), "frequency_hz": near.frequency_hz,
                                         "damping_ratio": near.damping_ratio}
    return {"files": paths, "peaks": peaks, "nearest_mode": nearest, "speed": speed,
            "bogie_delay_s": 2 * cars.steered.values["lT"] / speed,
            "notch_spacing_hz": speed / (2 * cars.steered.values["lT"])}


# --------------------------------------------------------------------------------------
# Fig. 11: critical speed against conicity
# --------------------------------------------------------------------------------------


def _figure11(outdir: Path, cars: _Cars, log) -> dict:
    from .plots import figure_critical_speed
    from .stability import critical_speed, critical_speed_vs_conicity

    options = {"v_min": 1.0, "v_max": V_MAX, "tolerance_kmh": 0.1}
    sweeps = {name: critical_speed_vs_conicity(vehicle, CONICITIES, **options)
              for name, vehicle in (("steered", cars.steered), ("conventional", cars.conventional))}
    columns: dict[str, object] = {"Gamma": CONICITIES}
    curves, result = [], {}
    for name, sweep in sweeps.items():
        speeds = np.array([c.speed_kmh if c is not None else np.nan for c in sweep])
        unstable = np.array([c is not None and c.unstable_at_min for c in sweep])
        columns[f"Vcr_{name}_kmh"] = speeds
        columns[f"unstable_at_lowest_speed_{name}"] = unstable.astype(int).tolist()
        columns[f"mode_{name}"] = [c.mode.describe() if c is not None else "" for c in sweep]
        curves.append({"label": "forced steering" if name == "steered" else "conventional bogies",
                       "conicity": CONICITIES, "speed_kmh": speeds, "style": name, "unstable_at_min": unstable,
                       "color": "#1f77b4" if name == "steered" else "#d62728"})
        result[name] = {"speeds_kmh": speeds, "unstable_at_min": unstable,
                        "modes": [c.mode.describe() if c is not None else None for c in sweep]}
    caption = ("Eigenvalues of A(v) on straight track, linear creep; V_cr = lowest speed at which a real part turns "
               f"positive (scan {options['v_min'] / KMH:.1f}-{options['v_max'] / KMH:.0f} km/h, bisection to "
               f"{options['tolerance_kmh']} km/h). Crosses: unstable already at the lowest speed scanned.")
    figure = figure_critical_speed(curves, running_speed_kmh=cars.steered.speed / KMH,
                                   nominal_conicity=cars.steered.values.get("Gamma"), caption=caption)
    paths = _figure(figure, outdir / "fig11_critical_speed")
    _write(outdir / "fig11_critical_speed.csv", _csv(columns))
    shape = _vcr_shape(result)
    # what drives the low-conicity fall: the same car with the steering link cut
    low = [(g, c) for g, c in zip(CONICITIES, sweeps["steered"]) if c is not None and not c.unstable_at_min
           and c.speed_kmh < 0.5 * shape["steered_max_kmh"]]
    if low:
        gamma, case = low[0]
        cut = critical_speed(cars.steered.with_values({"Gamma": float(gamma), "kLU": 1.0}), **options)
        shape["low_gamma"] = float(gamma)
        shape["low_gamma_kmh"] = case.speed_kmh
        shape["low_gamma_mode"] = case.mode.describe()
        shape["low_gamma_frequency_hz"] = case.mode.frequency_hz
        shape["low_gamma_link_cut_kmh"] = cut.speed_kmh if cut is not None else None
    log(f"  Fig. 11: steered max {shape['steered_max_kmh']:.0f} km/h at Gamma {shape['steered_max_gamma']:.2f}; "
        f"conventional {shape['conventional_first_kmh']:.0f} -> {shape['conventional_last_kmh']:.0f} km/h")
    return {"files": paths, **result, "shape": shape}


def _vcr_shape(result: dict) -> dict:
    g = CONICITIES
    steered = result["steered"]["speeds_kmh"]
    conventional = result["conventional"]["speeds_kmh"]
    k = int(np.nanargmax(steered))
    finite_c = conventional[np.isfinite(conventional)]
    below_half = [gamma for gamma, v in zip(g, steered) if gamma < g[k] and v < 0.5 * steered[k]]
    at = {gamma: i for i, gamma in enumerate(g)}
    i010 = at.get(0.1, int(np.argmin(np.abs(g - 0.1))))
    return {
        "steered_max_kmh": float(steered[k]),
        "steered_max_gamma": float(g[k]),
        "steered_first_kmh": float(steered[0]),
        "steered_first_unstable_at_min": bool(result["steered"]["unstable_at_min"][0]),
        "steered_half_gamma": float(max(below_half)) if below_half else None,
        "steered_at_0.1_kmh": float(steered[i010]),
        "steered_last_kmh": float(steered[-1]),
        "conventional_first_kmh": float(conventional[0]),
        "conventional_last_kmh": float(conventional[-1]),
        "conventional_at_0.1_kmh": float(conventional[i010]),
        "conventional_monotonic": bool(finite_c.size == conventional.size and np.all(np.diff(finite_c) < 0)),
        "gamma_first": float(g[0]),
        "gamma_last": float(g[-1]),
    }


# --------------------------------------------------------------------------------------
# matrices
# --------------------------------------------------------------------------------------


def _matrices(outdir: Path, examples: Path, log) -> dict:
    from ..export import FORMATS
    from ..io import load_model
    from ..rail.build import generate_vehicle

    written = {}
    for source in ("forced-steering.toml", "conventional.toml", "lever.exp"):
        equations = generate_vehicle(load_model(examples / source)).equations
        name = equations.name
        files = []
        for fmt, suffix in (("matlab", ".m"), ("latex", ".tex"), ("json", ".json")):
            path = outdir / "matrices" / f"{name}{suffix}"
            text = FORMATS[fmt](equations, name=name) if fmt == "matlab" else FORMATS[fmt](equations)
            _write(path, text)
            files.append(path)
        written[name] = {"files": files, "dofs": len(equations.dofs), "inputs": len(equations.inputs)}
    log("  matrices: " + ", ".join(f"{k} ({v['dofs']} DOFs)" for k, v in written.items()))
    return written


# --------------------------------------------------------------------------------------
# summary
# --------------------------------------------------------------------------------------


def _summary(results: dict, elapsed: float) -> tuple[str, dict]:
    f9, f10, f11, f3 = results["fig9"], results["fig10"], results["fig11"], results["fig3"]
    s = f9["steady"]
    mrad = 1e3
    theta = s["theta_L1"]
    geometric = f9["geometric_lever_rad"]
    ideal = f9["ideal_yaw_rad"]
    q1s, q2s = s["Q1_steered"] / 1e3, s["Q2_steered"] / 1e3
    q1c, q2c = s["Q1_conventional"] / 1e3, s["Q2_conventional"] / 1e3
    shape = f11["shape"]
    per_axle = f9["bogie_lateral_force_N"] / 2e3
    reduction = 1.0 - q1s / q1c
    flange_s = f9["flanging"]["steered"]
    flange_c = f9["flanging"]["conventional"]
    fr = f10["peaks"]

    def flanges(flags):
        on = [f"axle {j}" for j, f in zip((1, 2), flags) if f]
        return " and ".join(on) if on else "neither axle"

    low_fall = ""
    if "low_gamma" in shape:
        cut = shape["low_gamma_link_cut_kmh"]
        low_fall = (
            f" At Γ = {shape['low_gamma']:.2f} the mode that goes unstable is "
            f"'{shape['low_gamma_mode']}' at {shape['low_gamma_frequency_hz']:.2f} Hz, already at "
            f"{shape['low_gamma_kmh']:.0f} km/h. With the steering link cut (kLU → 0, a check run) the same car is "
            + (f"stable up to {V_MAX / KMH:.0f} km/h" if cut is None else f"stable up to {cut:.0f} km/h")
            + ". So the fall comes from the linkage, which feeds the car-body–bogie yaw into the wheelsets, while a "
            "small conicity gives the wheelsets little restoring force."
        )
    near = f10["nearest_mode"]
    near_text = (
        f" The steered car's front peak at {fr['floor_front_steered'][1]:.2f} Hz lies next to its mode "
        f"'{near['description']}' ({near['frequency_hz']:.2f} Hz, damping ratio {near['damping_ratio']:.2f}) at "
        f"{f10['speed'] / KMH:.0f} km/h, a mode of the bogie under the front floor."
        if near else ""
    )
    rows = [
        (
            "Lever angle θ_L1, steady curve (Fig. 9a)",
            f"≈ 0.04 rad, against the geometric b_L l_T/(R l_LU) = {PAPER['lever_angle_geometric_rad']:.2f} rad",
            f"{theta:.4f} rad = {theta / geometric:.0%} of the geometric {geometric:.4f} rad",
            f"Closer to the geometric value than the paper's two thirds. The shortfall is the stretch of the link kLU "
            f"between the lever top and the car-body steering beam (paper §4.1). Our kLU = "
            f"{f9['kLU_N_m'] / 1e6:.0f} MN/m is an estimate for a rubber-bushed rod (docs/parameters.md) and was not "
            f"tuned. It is evidently stiffer than the paper's: it stretches only "
            f"{(geometric - theta) * 0.3 * 1e3:.1f} mm under a link force of about {f9['link_force_N'] / 1e3:.1f} kN. "
            f"Holding that force, 0.04 rad would need kLU ≈ {f9['kLU_for_paper_angle_N_m'] / 1e6:.1f} MN/m. A check "
            f"run with that value gives θ_L1 = {f9['theta_with_that_kLU_rad']:.3f} rad: the link force drops as the "
            f"steering weakens, so the paper's linkage must be softer still. The paper does not give its kLU.",
        ),
        (
            "Steering angle ψ_TW1, ψ_TW2 with steering (Fig. 9b)",
            f"both approach the ideal a/R = {PAPER['steering_angle_ideal_rad']} rad; |ψ_TW2| < |ψ_TW1|",
            f"ψ_TW1 = {s['psi_TW1_steered'] * mrad:+.2f} mrad ({abs(s['psi_TW1_steered']) / ideal:.0%} of a/R = "
            f"{ideal * mrad:.2f} mrad), ψ_TW2 = {s['psi_TW2_steered'] * mrad:+.2f} mrad "
            f"({abs(s['psi_TW2_steered']) / ideal:.0%})",
            f"As in the paper, both axles take nearly the radial position and |ψ_TW2| < |ψ_TW1|. The paper explains "
            f"this ordering by the larger creep moment on axle 2 deforming its kLL link more. Axle 1 reaches "
            f"{abs(s['psi_TW1_steered']) / ideal:.0%} of a/R for two reasons. The lever ratio l_LL/l_LU = "
            f"{f9['lever_ratio']:.2f} is 1.25 times the ideal a/l_T = {f9['ideal_lever_ratio']:.3f} (the paper's own "
            f"choice). Our stiff kLU passes {theta / geometric:.0%} of the geometric lever angle on to the lever. ψ_TW2 "
            f"is negative because, in a left curve, the rear wheelset turns right relative to its bogie.",
        ),
        (
            "Steering angle without steering (Fig. 9b)",
            "smaller in magnitude than a/R on both axles",
            f"ψ_TW1 = {s['psi_TW1_conventional'] * mrad:+.3f} mrad, ψ_TW2 = {s['psi_TW2_conventional'] * mrad:+.3f} mrad "
            f"({abs(s['psi_TW1_conventional']) / ideal:.0%} and {abs(s['psi_TW2_conventional']) / ideal:.0%} of a/R)",
            f"Agrees with the paper. The conventional axle-box support is stiff (kx1 = "
            f"{(f9['kx1_conventional'] or 0) / 1e6:.0f} MN/m, against {(f9['kx1_steered'] or 0) / 1e6:.0f} MN/m on the "
            f"steered bogie), so the wheelsets stay almost parallel to the frame.",
        ),
        (
            "Lateral force Q1 without steering (Fig. 9c)",
            f"{PAPER['Q1_conventional_kN']:.0f} kN",
            f"{q1c:.1f} kN (steady curve; peak {f9['peaks']['Q1_conventional_max'] / 1e3:.1f} kN); Q2 = {q2c:.1f} kN; "
            f"flange contact on {flanges(flange_c)}",
            f"{(q1c / PAPER['Q1_conventional_kN'] - 1):+.0%} against the paper. With flange contact on {flanges(flange_c)}, "
            f"the leading outer wheel carries most of the bogie's lateral load, which is set by the cant deficiency "
            f"v²/R − gS/G = {f9['cant_deficiency_m_s2']:.2f} m/s² on our {f9['car_mass_kg'] / 1e3:.1f} t car. We did not "
            f"have the paper's car data (its ref. 4), so the mass and suspension are ours, and a few kN of difference "
            f"is expected. Q is the lateral force on the flanging wheel: the flange force plus that wheel's half of the "
            f"lateral creep force.",
        ),
        (
            "Lateral force Q1 with steering (Fig. 9c)",
            f"about {PAPER['Q1_steered_kN']:.0f} kN (a {1 - PAPER['Q1_steered_kN'] / PAPER['Q1_conventional_kN']:.0%} "
            f"reduction); Q2 rises to about the same as Q1",
            f"{q1s:.1f} kN ({reduction:.0%} reduction; peak {f9['peaks']['Q1_steered_max'] / 1e3:.1f} kN); "
            f"Q2 = {q2s:.1f} kN (from {q2c:.1f} kN), Q2/Q1 = {q2s / q1s:.2f}; flange contact on {flanges(flange_s)}",
            f"The trend matches the paper: Q1 falls, Q2 rises, and the two become nearly equal. Our level is higher. "
            f"Once the two axles share the load, each must carry half of the bogie's cant-deficiency force, "
            f"(m_c/2 + m_t + 2 m_w)(v²/R − gS/G)/2 = {per_axle:.1f} kN for our car. That alone exceeds the paper's "
            f"14 kN, so the paper's model must have carried a smaller lateral load (a lighter car, or less cant "
            f"deficiency). Our Q1 is {q1s - per_axle:+.1f} kN off that even share and Q2 {q2s - per_axle:+.1f} kN.",
        ),
        (
            "V_cr against Γ, conventional bogies (Fig. 11)",
            "V_cr falls as Γ grows",
            f"falls {'monotonically ' if shape['conventional_monotonic'] else ''}from "
            f"{shape['conventional_first_kmh']:.0f} km/h (Γ = {shape['gamma_first']:.2f}) to "
            f"{shape['conventional_last_kmh']:.0f} km/h (Γ = {shape['gamma_last']:.2f}); "
            f"{shape['conventional_at_0.1_kmh']:.0f} km/h at Γ = 0.1",
            "Same shape as the paper. A larger conicity shortens the kinematic wavelength and raises the hunting "
            "frequency at a given speed, and the creep damping (∝ 1/v) runs out at a lower speed. The paper's text "
            "gives no absolute V_cr, so only the shape can be compared. A linear V_cr with a constant equivalent "
            "conicity is not a prediction for service.",
        ),
        (
            "V_cr against Γ, forced steering (Fig. 11)",
            f"maximum near Γ ≈ {PAPER['conicity_of_max_vcr']}, then a sharp fall towards Γ → 0",
            f"maximum {shape['steered_max_kmh']:.0f} km/h at Γ = {shape['steered_max_gamma']:.2f}; "
            f"{shape['steered_at_0.1_kmh']:.0f} km/h at Γ = 0.1; below half the maximum for Γ ≤ "
            f"{shape['steered_half_gamma']:.2f}; "
            + (f"unstable from the lowest speed scanned at Γ = {shape['gamma_first']:.2f}"
               if shape["steered_first_unstable_at_min"] else f"{shape['steered_first_kmh']:.0f} km/h at Γ = {shape['gamma_first']:.2f}"),
            "Same shape as the paper." + low_fall + " Towards large Γ, bogie hunting limits both cars and the two "
            "curves merge.",
        ),
        (
            "Lever step response (Fig. 3, Table 1)",
            "q2 > 0 in case 1, q2 < 0 in case 2, q2 = 0 in case 3",
            "static q2 = " + ", ".join(f"{v * 1e3:+.3f} mrad" for v in f3["static_q2_rad"].values())
            + f" for a q1 step of {LEVER_STEP * 1e3:g} mrad",
            "Agrees with the paper. Case 3 as printed (l_LU 0.06 m, l_LL 0.30 m, k_LU 1000 and k_LL 5000 kN/m) "
            "gives l_LU k_LU = 60 kN against l_LL k_LL = 1500 kN. That violates its own condition, so it could not "
            "give q2 = 0. We use l_LU 0.30 m and l_LL 0.06 m instead, for which 300 = 300 kN. J2 = 0.5 kg m², an "
            f"added damper c_L = {LEVER_DAMPING:g} N m s/rad and b = 1 m are our choices; they shape only the "
            "transient.",
        ),
        (
            "Floor acceleration above the bogie centres (Fig. 10)",
            "front and rear differ because of the phase between the car body's sway, yaw and roll",
            "peaks: " + "; ".join(f"{k.replace('floor_', '').replace('_', ', ')} {a:.3f} m/s² at {f:.2f} Hz"
                                  for k, (a, f) in fr.items()),
            "As in the paper, the front and rear responses differ. The paper's text gives no amplitudes to compare "
            "with." + near_text + f" The dips recur about every v/(2 l_T) = {f10['notch_spacing_hz']:.1f} Hz. The "
            f"rear bogie meets the same irregularity {f10['bogie_delay_s']:.2f} s later, so the inputs of the two "
            "bogies alternately add and cancel (geometric filtering).",
        ),
    ]
    lines = [
        "# EXPRESS demo: the paper's results with the bundled vehicles",
        "",
        "Tanifuji & Suzuki (2001), section 4.4, re-created with `examples/forced-steering.toml` and "
        "`examples/conventional.toml` (parameters: `docs/parameters.md`, chosen from published data and "
        "**not tuned** to the paper's figures), and the paper's lever `examples/lever.exp`.",
        "Steady values are means over the leading wheelset at "
        f"d1 = {f9['window_m'][0]:.0f}–{f9['window_m'][1]:.0f} m, where the whole car is in the circular curve. "
        "Paper values are the ones its text states (its figures are not machine-readable).",
        "",
        "| Quantity | Paper | This run | Difference and why |",
        "|---|---|---|---|",
    ]
    for row in rows:
        lines.append("| " + " | ".join(cell.replace("|", "\\|") for cell in row) + " |")
    lines += [
        "",
        "## Files",
        "",
        "- `matrices/`: symbolic M, C, K, P, Pd of each vehicle and of the lever (`.m`, `.tex`, `.json`)",
        "- `fig3_lever_step`, `fig9_curving`, `fig10_frequency_response`, `fig11_critical_speed`: "
        "`.png`, `.svg` and the data as `.csv` (SI units)",
        "- `summary.json`: the numbers of this table",
        "",
        f"Run time: {elapsed:.1f} s.",
        "",
    ]
    numbers = {
        "paper": PAPER,
        "lever_angle_rad": theta,
        "lever_angle_geometric_rad": geometric,
        "steering_angle_ideal_rad": ideal,
        "steady": s,
        "peaks": f9["peaks"],
        "cant_deficiency_m_s2": f9["cant_deficiency_m_s2"],
        "bogie_lateral_force_N": f9["bogie_lateral_force_N"],
        "kLU_for_paper_angle_N_m": f9["kLU_for_paper_angle_N_m"],
        "critical_speed_shape": shape,
        "critical_speed_kmh": {"Gamma": CONICITIES.tolist(),
                               "steered": f11["steered"]["speeds_kmh"].tolist(),
                               "conventional": f11["conventional"]["speeds_kmh"].tolist()},
        "lever_static_q2_rad": {str(k): v for k, v in f3["static_q2_rad"].items()},
        "floor_acceleration_peaks": {k: {"amplitude_m_s2": a, "frequency_hz": f} for k, (a, f) in fr.items()},
    }
    return "\n".join(lines), numbers


# --------------------------------------------------------------------------------------
# entry point
# --------------------------------------------------------------------------------------


def run_demo(outdir: str | Path = "demo-out", *, examples: Path | None = None,
             log: Callable[[str], None] = print) -> Path:
    """Write every result of the paper's section 4.4 into ``outdir``; return the path of
    ``summary.md``.

    Parameters
    ----------
    outdir : path
        Created if needed; files in it are replaced.
    examples : path, optional
        Directory of the bundled models (found automatically in a source checkout).
    log : callable
        Receives one line per step (progress and key numbers).
    """
    from ..io import load_model
    from ..statespace import vehicle_model

    start = time.perf_counter()
    outdir = Path(outdir)
    examples = find_examples(examples)
    try:
        outdir.mkdir(parents=True, exist_ok=True)
    except OSError as error:
        raise ValueError(f"{outdir}: cannot create the output directory ({error.strerror or error})") from None
    log(f"express demo: writing {outdir}/")
    results = {"matrices": _matrices(outdir, examples, log)}
    cars = _Cars(
        steered=vehicle_model(load_model(examples / "forced-steering.toml")),
        conventional=vehicle_model(load_model(examples / "conventional.toml")),
    )
    results["fig3"] = _figure3(outdir, examples, log)
    results["fig9"] = _figure9(outdir, cars, log)
    results["fig10"] = _figure10(outdir, cars, log)
    results["fig11"] = _figure11(outdir, cars, log)
    text, numbers = _summary(results, time.perf_counter() - start)
    _write(outdir / "summary.json", json.dumps(json_safe(numbers), indent=2) + "\n")
    summary = outdir / "summary.md"
    _write(summary, text)
    log(f"  done in {time.perf_counter() - start:.1f} s")
    return summary
