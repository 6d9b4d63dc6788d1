"""The paper's figures: Fig. 3 (lever step), Fig. 9 (curving), Fig. 10 (frequency
response), Fig. 11 (critical speed against conicity), and a quick look at a simulation run.

Every function takes plain arrays (SI unless the name says km/h) and returns a
:class:`matplotlib.figure.Figure`; plotted units are the ones people read (km/h, kN, mrad).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from express.analysis.plots._base import (
    BLUE,
    CONVENTIONAL,
    GREEN,
    GREY,
    ORANGE,
    PURPLE,
    RED,
    STEERED,
    add_caption,
    axes_for,
    runs,
    styled,
)

__all__ = [
    "figure_critical_speed",
    "figure_curving",
    "figure_frequency_response",
    "figure_lever_step",
    "figure_simulation",
]

# --------------------------------------------------------------------------------------
# Fig. 3: lever step response
# --------------------------------------------------------------------------------------


@styled
def figure_lever_step(
    time: np.ndarray,
    cases: Sequence[Mapping],
    *,
    step: float,
    caption: str | None = None,
    ax=None,
):
    """Lever angle ``q2`` against time after a step of ``q1`` (paper Fig. 3).

    Parameters
    ----------
    time : numpy.ndarray, shape (T,)
        Time [s].
    cases : sequence of mapping
        One per leverage case: ``label``, ``q2`` (shape (T,) [rad]) and ``steady``
        (the static value [rad]).
    step : float
        Size of the ``q1`` step [rad].
    caption : str, optional
    ax : matplotlib.axes.Axes, optional
        Draw into this axes and return it (the figure's layout, title and caption are then
        the caller's); by default a new figure is made and returned.
    """
    figure, axis = axes_for(ax, figsize=(7.2, 4.8))
    colours = (BLUE, RED, GREEN, PURPLE)
    axis.axhline(0.0, color=GREY, linewidth=0.6, zorder=1)
    extent = 0.0
    for k, case in enumerate(cases):
        colour = colours[k % len(colours)]
        values = np.asarray(case["q2"]) * 1e3
        extent = max(extent, float(np.max(np.abs(values))))
        axis.plot(time * 1e3, values, color=colour, label=case["label"], zorder=3 + k,
                  linewidth=2.2 if k == 2 else 1.5)
        axis.axhline(case["steady"] * 1e3, color=colour, linestyle=":", linewidth=1.0, zorder=2)
    axis.set_xlabel("time t [ms] (step of q1 at t = 0)")
    axis.set_ylabel("lever angle q2 [mrad]")
    axis.set_title(f"Fig. 3 - lever angle q2 after a step q1 = {step * 1e3:g} mrad (dotted: static value)")
    axis.set_xlim(time[0] * 1e3, time[-1] * 1e3)
    extent = extent or 1.0
    axis.set_ylim(-1.15 * extent, 1.9 * extent)
    axis.legend(loc="upper right", framealpha=0.95)
    if ax is not None:
        return ax
    figure.tight_layout(rect=(0, 0.09 if caption else 0, 1, 1))
    add_caption(figure, caption)
    return figure


# --------------------------------------------------------------------------------------
# Fig. 9: curve negotiation
# --------------------------------------------------------------------------------------


@styled
def figure_curving(
    steered: Mapping[str, np.ndarray],
    conventional: Mapping[str, np.ndarray] | None,
    *,
    ideal_yaw: float,
    geometric_lever: float | None = None,
    title: str = "Fig. 9 - curve negotiation",
    caption: str | None = None,
    ax=None,
):
    """Three panels against ``d1`` (paper Fig. 9).

    Parameters
    ----------
    steered, conventional : mapping of str to numpy.ndarray
        ``d1``, ``rho1``, ``theta_L1`` (steered only), ``psi_TW1``, ``psi_TW2``, ``Q1``,
        ``Q2`` (SI), each of one length.  ``conventional`` may be None.  ``Q1``, ``Q2``
        are the paper's names of the lateral forces (its Fig. 9c): the runs'
        ``Y1``, ``Y2`` (:mod:`express.paper.demo_curving`).
    ideal_yaw : float
        The radial steering angle ``a/R`` [rad], dashed as ``+-a/R`` in panel (b)
        (``psi_TW2`` is negative in a left curve: the rear wheelset turns the other way).
    geometric_lever : float, optional
        The geometric lever angle ``b_L l_T / (R l_LU)`` [rad], dashed in panel (a).
    title, caption : str
    ax : sequence of matplotlib.axes.Axes, optional
        Draw into these axes (one per panel, three) and return them (the figure's layout,
        title and caption are then the caller's); by default a new figure is made and returned.
    """
    figure, (top, middle, bottom) = axes_for(ax, 3, 1, figsize=(7.6, 9.6), sharex=True)
    _panel_lever(top, steered, geometric_lever)
    _panel_steering(middle, steered, conventional, ideal_yaw)
    _panel_forces(bottom, steered, conventional)
    if ax is not None:
        return ax
    figure.suptitle(title, fontsize=11.5)
    figure.tight_layout(rect=(0, 0.045 if caption else 0, 1, 1))
    add_caption(figure, caption)
    return figure


def _panel_lever(top, steered: Mapping[str, np.ndarray], geometric_lever: float | None) -> None:
    """(a) curvature and lever angle, the zero of both axes at the same height."""
    d = steered["d1"]
    rho_top = float(np.max(np.abs(steered["rho1"]))) or 1.0
    low, high = -0.08, 1.45  # fractions of each axis' reference value
    top.plot(d, steered["rho1"] * 1e3, color=GREY, label=r"curvature $\rho_1$ (left axis)")
    top.set_ylabel(r"curvature $\rho_1$ [10$^{-3}$ 1/m]")
    top.set_ylim(low * rho_top * 1e3, high * rho_top * 1e3)
    twin = top.twinx()
    twin.grid(False)
    handles = [top.get_lines()[0]]
    if "theta_L1" in steered:
        (line,) = twin.plot(d, steered["theta_L1"], color=BLUE, label=r"lever angle $\theta_{L1}$ (right axis)")
        handles.append(line)
        largest = float(np.max(np.abs(steered["theta_L1"])))
        # with the geometric angle as reference, the geometric lever angle b_L l_T rho / l_LU
        # would lie exactly on the curvature curve
        reference = geometric_lever if geometric_lever and largest < 1.4 * geometric_lever else (largest or 1.0)
        if geometric_lever is not None:
            ref = twin.axhline(geometric_lever, color=BLUE, linestyle="--", linewidth=1.0,
                               label=fr"geometric $b_L l_T/(R\,l_{{LU}})$ = {geometric_lever:.3f} rad")
            handles.append(ref)
        twin.set_ylim(low * reference, high * reference)
    twin.set_ylabel(r"lever angle $\theta_{L1}$ [rad]", color=BLUE)
    twin.tick_params(axis="y", colors=BLUE)
    top.legend(handles=handles, loc="upper center", ncol=2, framealpha=0.9)
    top.set_title("(a) curvature at the leading wheelset and front steering-lever angle", loc="left")


def _panel_steering(middle, steered, conventional, ideal_yaw: float) -> None:
    """(b) signed steering angles of axles 1 and 2, the ideal ``+-a/R`` dashed."""
    d = steered["d1"]
    for key, colour, name in (("psi_TW1", BLUE, "axle 1"), ("psi_TW2", ORANGE, "axle 2")):
        middle.plot(d, steered[key] * 1e3, color=colour, label=f"{name}, steered", **STEERED)
        if conventional is not None:
            middle.plot(conventional["d1"], conventional[key] * 1e3, color=colour,
                        label=f"{name}, conventional", **CONVENTIONAL)
    middle.axhline(ideal_yaw * 1e3, color="black", linestyle="--", linewidth=1.0,
                   label=fr"ideal radial $\pm a/R$ = $\pm${ideal_yaw * 1e3:.2f} mrad")
    middle.axhline(-ideal_yaw * 1e3, color="black", linestyle="--", linewidth=1.0)
    middle.axhline(0.0, color="black", linewidth=0.6)
    middle.set_ylabel(r"bogie-wheelset yaw $\psi_{TW}$ [mrad]")
    middle.set_ylim(-ideal_yaw * 1e3 * 1.6, ideal_yaw * 1e3 * 2.1)
    middle.legend(loc="upper right", ncol=2, framealpha=0.9)
    middle.set_title(r"(b) steering angle $\psi_{TW}$ (signed: axle 1 turns left (+), axle 2 right (-) in this "
                     "left curve)", loc="left")


def _panel_forces(bottom, steered, conventional) -> None:
    """(c) lateral forces Q1, Q2 [kN] against d1."""
    d = steered["d1"]
    for key, colour, name in (("Q1", BLUE, "axle 1"), ("Q2", ORANGE, "axle 2")):
        bottom.plot(d, steered[key] * 1e-3, color=colour, label=f"$Q_{key[1]}$ {name}, steered", **STEERED)
        if conventional is not None:
            bottom.plot(conventional["d1"], conventional[key] * 1e-3, color=colour,
                        label=f"$Q_{key[1]}$ {name}, conventional", **CONVENTIONAL)
    bottom.axhline(0.0, color="black", linewidth=0.6)
    bottom.set_ylabel("lateral force Q [kN]")
    bottom.set_xlabel(r"distance of the leading wheelset $d_1$ [m]")
    high = max(float(np.max(s[k])) for s in (steered, conventional) if s is not None for k in ("Q1", "Q2")) * 1e-3
    bottom.set_ylim(-0.05 * high, 1.35 * high)
    bottom.legend(loc="upper right", ncol=2, framealpha=0.9)
    bottom.set_title("(c) lateral force Q from the rail on the outer wheel (flange + half the creep force)", loc="left")
    bottom.set_xlim(float(d[0]), float(d[-1]))


# --------------------------------------------------------------------------------------
# Fig. 10: frequency response
# --------------------------------------------------------------------------------------


@styled
def figure_frequency_response(
    frequencies: np.ndarray,
    curves: Sequence[Mapping],
    *,
    title: str = "Fig. 10 - car-body floor acceleration",
    ylabel: str = "acceleration amplitude [m/s²]",
    caption: str | None = None,
    ax=None,
):
    """Amplitudes against frequency on a log frequency axis (paper Fig. 10).

    Parameters
    ----------
    frequencies : numpy.ndarray, shape (F,)
        Frequencies [Hz], > 0.
    curves : sequence of mapping
        ``label``, ``values`` (real amplitudes, shape (F,)), and optional ``color`` and
        ``style`` (``"steered"`` solid, ``"conventional"`` dashed).
    title, ylabel, caption : str
    ax : matplotlib.axes.Axes, optional
        Draw into this axes and return it (the figure's layout, title and caption are then
        the caller's); by default a new figure is made and returned.
    """
    figure, axis = axes_for(ax, figsize=(7.2, 4.6))
    palette = (BLUE, ORANGE, GREEN, RED, PURPLE, GREY)
    for k, curve in enumerate(curves):
        style = CONVENTIONAL if curve.get("style") == "conventional" else STEERED
        axis.plot(frequencies, curve["values"], color=curve.get("color", palette[k % len(palette)]),
                  label=curve["label"], **style)
    _log_frequency_axis(axis)
    axis.set_xlim(float(frequencies[0]), float(frequencies[-1]))
    axis.set_ylim(bottom=0.0)
    axis.set_xlabel("frequency f [Hz]")
    axis.set_ylabel(ylabel)
    axis.set_title(title)
    axis.grid(True, which="minor", alpha=0.15)
    axis.legend(loc="upper left", framealpha=0.9)
    if ax is not None:
        return ax
    figure.tight_layout(rect=(0, 0.06 if caption else 0, 1, 1))
    add_caption(figure, caption)
    return figure


#: Axis label of each unit of :func:`figure_frequency_responses`.
_UNIT_LABELS = {"m/s^2": "acceleration amplitude [m/s²]", "m": "displacement amplitude [m]",
                "rad": "rotation amplitude [rad]", "N": "force amplitude [N]"}


def figure_frequency_responses(frequencies: np.ndarray, panels: Mapping[str, Sequence[Mapping]], *,
                               title: str = "", log: bool = False, ax=None):
    """Amplitudes against frequency, one axis per unit (never two units on one axis).

    Parameters
    ----------
    frequencies : numpy.ndarray, shape (F,)
        [Hz], > 0.
    panels : mapping of str to sequence of mapping
        Unit (``"m/s^2"``, ``"m"``, ``"rad"``, ``"N"``) -> curves with ``label`` and
        ``values`` (real amplitudes, shape (F,)); one axis per unit, stacked.
    title : str
    log : bool
        Logarithmic amplitude axes (the frequency axis is always logarithmic).
    ax : sequence of matplotlib.axes.Axes, optional
        Draw into these axes (one per panel, one per unit) and return them (the figure's layout,
        title and caption are then the caller's); by default a new figure is made and returned.
    """
    figure, axes = axes_for(ax, len(panels), 1, figsize=(7.2, 1.0 + 3.0 * len(panels)), sharex=True, squeeze=False)
    palette = (BLUE, ORANGE, GREEN, RED, PURPLE, GREY)
    for axis, (unit, curves) in zip(axes[:, 0], panels.items(), strict=True):
        for k, curve in enumerate(curves):
            linestyle = ("-", "--", ":", "-.")[(k // len(palette)) % 4]
            axis.plot(frequencies, curve["values"], color=palette[k % len(palette)], linestyle=linestyle,
                      label=curve["label"])
        _log_frequency_axis(axis)
        if log:
            axis.set_yscale("log")
        else:
            axis.set_ylim(bottom=0.0)
        axis.set_ylabel(_UNIT_LABELS.get(unit, f"amplitude [{unit}]"))
        axis.grid(True, which="minor", alpha=0.15)
        axis.legend(loc="best", framealpha=0.9, fontsize="small", ncol=2 if len(curves) > 6 else 1)
    axes[-1, 0].set_xlim(float(frequencies[0]), float(frequencies[-1]))
    axes[-1, 0].set_xlabel("frequency f [Hz]")
    axes[0, 0].set_title(title)
    if ax is not None:
        return ax
    figure.tight_layout()
    return figure


def _log_frequency_axis(axis) -> None:
    from matplotlib.ticker import FuncFormatter, LogLocator

    axis.set_xscale("log")
    axis.xaxis.set_major_locator(LogLocator(base=10.0, subs=(1.0, 2.0, 5.0)))
    axis.xaxis.set_major_formatter(FuncFormatter(lambda x, _: f"{x:g}"))


# --------------------------------------------------------------------------------------
# Fig. 11: critical speed against conicity
# --------------------------------------------------------------------------------------


def _segments(speeds: np.ndarray, flagged: np.ndarray, tops: np.ndarray) -> list[np.ndarray]:
    """Indices of the pieces of a ``V_cr`` line: runs of finite, not flagged points, cut
    between neighbours whose unstable ranges ``[V_cr, top]`` are both known and disjoint."""
    pieces = []
    for run in runs(np.isfinite(speeds) & ~flagged):
        indices = np.arange(run.start, run.stop)
        start = 0
        for k in range(indices.size - 1):
            i, j = indices[k], indices[k + 1]
            if not (np.isnan(tops[i]) or np.isnan(tops[j])) and (tops[i] < speeds[j] or tops[j] < speeds[i]):
                pieces.append(indices[start:k + 1])
                start = k + 1
        pieces.append(indices[start:])
    return pieces


@styled
def figure_critical_speed(
    curves: Sequence[Mapping],
    *,
    running_speed_kmh: float | None = None,
    nominal_conicity: float | None = None,
    title: str = r"Fig. 11 - critical speed $V_{cr}$ against conicity $\Gamma$",
    caption: str | None = None,
    ax=None,
):
    """``V_cr`` [km/h] against ``Gamma`` (paper Fig. 11).

    Each curve is drawn as separate segments, so the line never joins across an unstable
    window: a point where no critical speed was found below the search limit (nan) or
    where the vehicle is unstable at every speed scanned (``unstable_at_min``, marked
    with a cross) breaks the line, and so does a jump between neighbours whose unstable
    ranges ``[V_cr, window_end]`` do not overlap (a window that closes; the window is
    drawn as a bar).

    Parameters
    ----------
    curves : sequence of mapping
        ``label``, ``conicity`` (shape (G,)), ``speed_kmh`` (shape (G,), nan where no
        critical speed was found below the search limit), and optional
        ``unstable_at_min`` (bool, shape (G,)), ``window_end_kmh`` (shape (G,): the speed
        from which the vehicle is stable again, ``inf`` if never, nan if unknown),
        ``color`` and ``style``.
    running_speed_kmh : float, optional
        Drawn as a dotted horizontal line.
    nominal_conicity : float, optional
        Drawn as a dash-dotted vertical line.
    title, caption : str
    ax : matplotlib.axes.Axes, optional
        Draw into this axes and return it (the figure's layout, title and caption are then
        the caller's); by default a new figure is made and returned.
    """
    figure, axis = axes_for(ax, figsize=(7.0, 4.6))
    palette = (BLUE, RED, GREEN, PURPLE)
    top = 0.0
    for k, curve in enumerate(curves):
        style = CONVENTIONAL if curve.get("style") == "conventional" else STEERED
        conicity = np.asarray(curve["conicity"], dtype=float)
        speeds = np.asarray(curve["speed_kmh"], dtype=float)
        colour = curve.get("color", palette[k % len(palette)])
        flagged = np.asarray(curve.get("unstable_at_min", np.zeros(speeds.size, bool)), dtype=bool)
        tops = np.asarray(curve.get("window_end_kmh", np.full(speeds.size, np.nan)), dtype=float)
        for n, piece in enumerate(_segments(speeds, flagged, tops)):
            axis.plot(conicity[piece], speeds[piece], color=colour, marker="o", markersize=2.8,
                      label=curve["label"] if n == 0 else "_segment", **style)
        if flagged.any():
            axis.plot(conicity[flagged], speeds[flagged], linestyle="none", marker="X", markersize=8,
                      color=colour, label=f"{curve['label']}: unstable from the lowest speed scanned")
        windows = np.isfinite(tops) & np.isfinite(speeds)
        if windows.any():
            axis.vlines(conicity[windows], speeds[windows], tops[windows], color=colour, linewidth=3.0, alpha=0.45,
                        label=f"{curve['label']}: unstable window (stable again above)")
            top = max(top, float(np.max(tops[windows])))
        if np.isfinite(speeds).any():
            top = max(top, float(np.nanmax(speeds)))
    if running_speed_kmh is not None:
        axis.axhline(running_speed_kmh, color=GREY, linestyle=":", linewidth=1.2,
                     label=f"running speed {running_speed_kmh:g} km/h")
    if nominal_conicity is not None:
        axis.axvline(nominal_conicity, color=GREY, linestyle="-.", linewidth=0.9,
                     label=fr"nominal $\Gamma$ = {nominal_conicity:g}")
    axis.set_xlabel(r"tread conicity $\Gamma$ [-]")
    axis.set_ylabel(r"critical speed $V_{cr}$ [km/h]")
    axis.set_xlim(left=0.0)
    axis.set_ylim(0.0, top * 1.12 if top > 0 else None)
    axis.set_title(title)
    axis.legend(loc="best", framealpha=0.9)
    if ax is not None:
        return ax
    figure.tight_layout(rect=(0, 0.06 if caption else 0, 1, 1))
    add_caption(figure, caption)
    return figure


# --------------------------------------------------------------------------------------
# a run of ``express simulate``
# --------------------------------------------------------------------------------------


@styled
def figure_simulation(distance: np.ndarray, outputs: Mapping[str, np.ndarray], *, title: str, ax=None):
    """A quick look at one run (``express simulate --plot``): curvature and lever
    angles, steering angles, lateral forces against ``d1``.

    Parameters
    ----------
    distance : numpy.ndarray, shape (T,)
        Distance of the leading wheelset ``d1`` [m].
    outputs : mapping of str to numpy.ndarray
        ``rho1`` and any of ``theta_*``, ``psi_TW*``, ``Y<n>`` (the dead-band model's lateral
        force of the flanging wheel) or ``Y<n><L|R>`` (the contact tables' lateral force of
        each wheel) (SI, shape (T,)).
    title : str
    ax : sequence of matplotlib.axes.Axes, optional
        Draw into these axes (one per panel, three) and return them (the figure's layout,
        title and caption are then the caller's); by default a new figure is made and returned.
    """
    figure, (top, middle, bottom) = axes_for(ax, 3, 1, figsize=(7.6, 8.6), sharex=True)
    colours = (BLUE, ORANGE, GREEN, RED)
    top.plot(distance, outputs["rho1"] * 1e3, color=GREY, label=r"curvature $\rho_1$ [1/km]")
    thetas = sorted(k for k in outputs if k.startswith("theta_"))
    if thetas:
        twin = top.twinx()
        twin.grid(False)
        for k, name in enumerate(thetas):
            twin.plot(distance, outputs[name], color=colours[k % 4], label=name)
        twin.set_ylabel("lever angle [rad]")
        twin.legend(loc="upper right", ncol=2)
    top.set_ylabel(r"$\rho_1$ [1/km]")
    top.legend(loc="upper left")
    top.set_title("(a) curvature at the leading wheelset" + (" and lever angles" if thetas else ""), loc="left")
    steering = sorted(k for k in outputs if k.startswith("psi_TW"))
    for k, name in enumerate(steering):
        middle.plot(distance, outputs[name] * 1e3, color=colours[k % 4], label=name)
    middle.set_ylabel(r"$\psi_{TW}$ [mrad]")
    if steering:
        middle.legend(loc="upper right", ncol=4)
    middle.set_title("(b) wheelset yaw relative to its bogie", loc="left")
    forces = sorted((k for k in outputs if k[:1] == "Y" and k[1:].isdigit()), key=lambda s: int(s[1:]))
    panel = "(c) lateral force Y on the flanging wheel"
    if not forces:  # the contact from profile tables: the lateral force Y of every wheel (Q is its vertical load)
        forces = sorted((k for k in outputs if k[:1] == "Y" and k[1:-1].isdigit() and k[-1:] in "LR"),
                        key=lambda s: (int(s[1:-1]), s[-1]))
        panel = "(c) lateral force Y on each wheel"
    for k, name in enumerate(forces):
        bottom.plot(distance, outputs[name] * 1e-3, color=colours[k % 4], label=name,
                    linestyle="-" if k < 4 else "--")
    bottom.set_ylabel("Y [kN]")
    bottom.set_xlabel(r"distance of the leading wheelset $d_1$ [m]")
    if forces:
        bottom.legend(loc="upper right", ncol=4)
    else:
        bottom.text(0.5, 0.5, "no wheel/rail forces in this run", transform=bottom.transAxes, ha="center")
    bottom.set_title(panel, loc="left")
    bottom.set_xlim(float(distance[0]), float(distance[-1]))
    if ax is not None:
        return ax
    figure.suptitle(title)
    figure.tight_layout()
    return figure


