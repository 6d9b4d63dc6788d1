"""The demo's summary: each row a :class:`Verdict` computed from the results.

A verdict holds the paper's value (:data:`express.paper.numbers.PAPER`), this run's
value, the predicate between them and the words the predicate decides: a row says
"agrees" only when its test passes, and the explanations that follow are chosen by
further tests on the numbers (which way a difference goes, whether a check run reached
the paper's value).  The tolerances are named below with the reason for each; they
are ours, not the paper's.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from express.base.units import KMH
from express.paper.demo_curving import Curving
from express.paper.demo_frequency import FloorResponse
from express.paper.demo_lever import LEVER_VALUES, LeverStep, swapped_cases
from express.paper.demo_stability import StabilitySweep, VcrShape, vcr_shape
from express.paper.numbers import PAPER

__all__ = [
    "CONICITY_FACTOR",
    "DIFFERENT",
    "FORCE_TOLERANCE",
    "GEOMETRY_TOLERANCE",
    "LEVER_TOLERANCE",
    "MERGE",
    "NEARLY_EQUAL",
    "RADIAL_TOLERANCE",
    "SHARP_FALL",
    "Verdict",
    "agreement",
    "relative_difference",
    "summary_rows",
]

#: Forces within 15 % of the paper's "agree": the car data are ours (the paper's ref. 4
#: was not available), and the paper's values are read from its text.
FORCE_TOLERANCE = 0.15
#: Lever angle as a share of the geometric angle, within 15 % of the paper's share.
LEVER_TOLERANCE = 0.15
#: Input geometry (lengths, ratios) within 2 %: the paper rounds to two digits.
GEOMETRY_TOLERANCE = 0.02
#: A steering angle within 25 % of ``a/R`` "approaches the radial position".
RADIAL_TOLERANCE = 0.25
#: ``Q2/Q1`` within 25 % of 1 is "nearly equal" (the paper: "almost equal").
NEARLY_EQUAL = 0.25
#: The steered car's largest ``V_cr`` within a factor 2 of the paper's conicity is "near" it.
CONICITY_FACTOR = 2.0
#: ``V_cr`` at the smallest conicity below half the maximum is a "sharp fall".
SHARP_FALL = 0.5
#: Front and rear floor responses "differ" when they part by more than 10 % somewhere.
DIFFERENT = 0.10
#: Two ``V_cr`` curves within 5 % at the largest conicity have "merged".
MERGE = 0.05


@dataclass(frozen=True)
class Verdict:
    """One row of ``summary.md``.

    Attributes
    ----------
    key : str
        Stable identifier (``"lever_angle"``, ``"q2_over_q1"``, ...).
    quantity : str
        What is compared, with the paper's figure.
    paper : float or None
        The paper's number that is compared (SI); None where the paper states a trend.
    computed : float
        This run's number that is compared (SI), or the measure the test is made on.
    agrees : bool
        The outcome of the predicate.
    test : str
        The predicate in words.
    paper_text, computed_text : str
        The table's "Paper" and "This run" cells.
    wording : str
        The verdict sentence; chosen by ``agrees``.
    why : str
        The explanation; its sentences chosen by further tests on the numbers.
    """

    key: str
    quantity: str
    paper: float | None
    computed: float
    agrees: bool
    test: str
    paper_text: str
    computed_text: str
    wording: str
    why: str = ""

    @property
    def difference(self) -> float | None:
        """``computed / paper - 1`` when the paper gives a non-zero number."""
        if self.paper is None or self.paper == 0:
            return None
        return relative_difference(self.computed, self.paper)

    def cells(self) -> tuple[str, str, str, str, str]:
        """The table row: quantity, paper, this run, verdict, why."""
        return self.quantity, self.paper_text, self.computed_text, self.wording, self.why


def relative_difference(computed: float, paper: float) -> float:
    """``computed / paper - 1``."""
    return computed / paper - 1.0


def agreement(computed: float, paper: float, tolerance: float) -> tuple[bool, str]:
    """Does ``computed`` lie within ``tolerance`` (relative) of ``paper``, and the sentence
    saying so: "Agrees with the paper (within 15 %: +10 %)." or "Differs from the
    paper by +66 %."."""
    difference = relative_difference(computed, paper)
    if abs(difference) <= tolerance:
        return True, f"Agrees with the paper (within {_pct(tolerance)}: {_pct(difference, sign=True)})."
    return False, f"Differs from the paper by {_pct(difference, sign=True)}."


def _pct(fraction: float, *, sign: bool = False) -> str:
    return f"{fraction * 100:+.0f} %" if sign else f"{fraction * 100:.0f} %"


def _kn(force: float) -> str:
    return f"{force / 1e3:.1f} kN"


def _flanges(flags: Sequence[bool]) -> str:
    on = [f"axle {j}" for j, flag in zip((1, 2), flags, strict=True) if flag]
    return " and ".join(on) if on else "neither axle"


def _unlike(parts: Sequence[str]) -> str:
    return "Unlike the paper: " + "; ".join(parts) + "."


# --------------------------------------------------------------------------------------
# Fig. 9: geometry, lever angle, steering angles, lateral forces
# --------------------------------------------------------------------------------------


def steering_geometry_verdict(curving: Curving) -> Verdict:
    """The geometric lever angle and the lever ratio of our car and track against the paper's."""
    paper_angle, paper_factor = PAPER.lever_angle_geometric.value, PAPER.lever_ratio_factor.value
    factor = curving.lever_ratio / curving.ideal_lever_ratio
    same_angle, _ = agreement(curving.geometric_lever, paper_angle, GEOMETRY_TOLERANCE)
    same_factor, _ = agreement(factor, paper_factor, GEOMETRY_TOLERANCE)
    agrees = same_angle and same_factor
    parts = []
    if not same_angle:
        parts.append(f"the geometric lever angle is {curving.geometric_lever:.4f} rad, not {paper_angle:g} rad")
    if not same_factor:
        parts.append(f"the lever ratio is {factor:.2f} times a/l_T, not {paper_factor:g} times")
    g = curving.geometry
    return Verdict(
        key="steering_geometry", quantity="Steering geometry: car and curve (§4.4)",
        paper=paper_angle, computed=curving.geometric_lever, agrees=agrees,
        test=f"θ_geo and γ_L/(a/l_T) each within {_pct(GEOMETRY_TOLERANCE)} of the paper's",
        paper_text=(f"b_L l_T/(R l_LU) = {paper_angle:g} rad at R = {PAPER.radius.value:g} m; lever ratio "
                    f"γ_L = {paper_factor:g} a/l_T"),
        computed_text=(f"{curving.geometric_lever:.4f} rad at R = {g.radius:g} m (track); γ_L = "
                       f"{curving.lever_ratio:.3f} = {factor:.3f} a/l_T (model)"),
        wording=("Agrees with the paper: the same geometry, so the angles below compare like with like."
                 if agrees else _unlike(parts) + " The angles below are compared as shares of our own geometry."),
        why=(f"Read from the track (R = {g.radius:g} m, cant {g.cant * 1e3:g} mm) and the model "
             f"(l_LL/l_LU = {curving.lever_ratio:.3f}, a/l_T = {curving.ideal_lever_ratio:.4f}, "
             f"l_LU = {curving.upper_arm:g} m)."),
    )


def _check_run_sentence(curving: Curving, paper_angle: float) -> str:
    theta, check = curving.steady["theta_L1"], curving.lever_angle_check
    if curving.link_stiffness_for_paper_angle is None:
        return ""
    k = curving.link_stiffness_for_paper_angle
    text = (f" Holding that force, the paper's {paper_angle:g} rad would need k_LU ≈ {k / 1e6:.2g} MN/m "
            f"({'softer' if k < curving.link_stiffness else 'stiffer'} than ours).")
    if check is None:
        return text
    text += f" A check run with that value gives θ_L1 = {check:.3f} rad"
    if agreement(check, paper_angle, LEVER_TOLERANCE)[0]:
        return text + ", the paper's angle."
    if (check > paper_angle) == (theta > paper_angle):
        if check > paper_angle:
            return text + (": still above the paper's, because the link force falls as the steering weakens, so "
                           "the paper's linkage must be softer still.")
        return text + (": still below the paper's, because the link force rises as the steering strengthens, so "
                       "the paper's linkage must be stiffer still.")
    return text + ": past the paper's angle, so the paper's k_LU lies between ours and that estimate."


def lever_angle_verdict(curving: Curving) -> Verdict:
    """Fig. 9(a): the lever angle as a share of the geometric one, against the paper's share."""
    paper_angle, paper_geometric = PAPER.lever_angle.value, PAPER.lever_angle_geometric.value
    paper_share, share = paper_angle / paper_geometric, curving.lever_fraction
    agrees, _ = agreement(share, paper_share, LEVER_TOLERANCE)
    theta = curving.steady["theta_L1"]
    if agrees:
        wording = (f"Agrees with the paper: the lever reaches the paper's share of its geometric angle (within "
                   f"{_pct(LEVER_TOLERANCE)}).")
    else:
        closer = share > paper_share
        wording = (f"{'Closer to' if closer else 'Further from'} the geometric angle than the paper's "
                   f"({_pct(share)} against {_pct(paper_share)}): our link k_LU passes on "
                   f"{'more' if closer else 'less'} of the geometric angle, so it is "
                   f"{'stiffer' if closer else 'softer'} than the paper's.")
    why = (f"The shortfall is the stretch of the link k_LU between the lever top and the car-body steering beam "
           f"(paper §4.1). Our k_LU = {curving.link_stiffness / 1e6:.3g} MN/m (docs/parameters.md, not tuned) stretches "
           f"{curving.link_stretch * 1e3:.1f} mm under a link force of about {_kn(curving.link_force)}."
           + _check_run_sentence(curving, paper_angle) + " The paper does not give its k_LU.")
    return Verdict(
        key="lever_angle", quantity="Lever angle θ_L1, steady curve (Fig. 9a)",
        paper=paper_share, computed=share, agrees=agrees,
        test=f"|(θ_L1/θ_geo) / ({paper_angle:g}/{paper_geometric:g}) − 1| ≤ {_pct(LEVER_TOLERANCE)}",
        paper_text=(f"≈ {paper_angle:g} rad = {_pct(paper_share)} of the geometric b_L l_T/(R l_LU) = "
                    f"{paper_geometric:g} rad"),
        computed_text=f"{theta:.4f} rad = {_pct(share)} of the geometric {curving.geometric_lever:.4f} rad",
        wording=wording, why=why,
    )


def steering_steered_verdict(curving: Curving) -> Verdict:
    """Fig. 9(b) with steering: both axles near ``a/R``, axle 2 below axle 1."""
    s, ideal = curving.steady, curving.ideal_yaw
    psi1, psi2 = s["psi_TW1_steered"], s["psi_TW2_steered"]
    shares = (abs(psi1) / ideal, abs(psi2) / ideal)
    radial = [abs(r - 1.0) <= RADIAL_TOLERANCE for r in shares]
    ordered = abs(psi2) < abs(psi1)
    agrees = all(radial) and ordered
    parts = [f"axle {j} reaches {_pct(r)} of a/R" for j, (r, ok) in enumerate(zip(shares, radial, strict=True), 1) if not ok]
    if not ordered:
        parts.append("|ψ_TW2| ≥ |ψ_TW1|")
    factor = curving.lever_ratio / curving.ideal_lever_ratio
    as_paper = agreement(factor, PAPER.lever_ratio_factor.value, GEOMETRY_TOLERANCE)[0]
    paper_choice = "as in the paper" if as_paper else f"the paper: {PAPER.lever_ratio_factor.value:g} times"
    why = ("The paper explains |ψ_TW2| < |ψ_TW1| by the larger creep moment on axle 2 deforming its k_LL link more. "
           f"Axle 1 {'over' if shares[0] > 1 else 'under'}-steers ({_pct(shares[0])} of a/R): the lever ratio "
           f"l_LL/l_LU = {curving.lever_ratio:.2f} is {factor:.2f} times the ideal a/l_T = "
           f"{curving.ideal_lever_ratio:.3f} ({paper_choice}), and our k_LU passes {_pct(curving.lever_fraction)} "
           "of the geometric lever angle on to the lever.")
    direction = curving.geometry.direction
    if (psi2 < 0) == (direction == "left"):
        why += (f" ψ_TW2 is {'negative' if psi2 < 0 else 'positive'} because, in a {direction} curve, the rear "
                f"wheelset turns the other way relative to its bogie.")
    return Verdict(
        key="steering_steered", quantity="Steering angle ψ_TW1, ψ_TW2 with steering (Fig. 9b)",
        paper=PAPER.steering_angle_ideal.value, computed=abs(psi1), agrees=agrees,
        test=f"|ψ_TW1|, |ψ_TW2| within {_pct(RADIAL_TOLERANCE)} of a/R and |ψ_TW2| < |ψ_TW1|",
        paper_text=f"both approach the ideal a/R = {PAPER.steering_angle_ideal.value:g} rad; |ψ_TW2| < |ψ_TW1|",
        computed_text=(f"ψ_TW1 = {psi1 * 1e3:+.2f} mrad ({_pct(shares[0])} of a/R = {ideal * 1e3:.2f} mrad), "
                       f"ψ_TW2 = {psi2 * 1e3:+.2f} mrad ({_pct(shares[1])})"),
        wording=(f"As in the paper, both axles come within {_pct(RADIAL_TOLERANCE)} of the radial angle a/R and "
                 "|ψ_TW2| < |ψ_TW1|." if agrees else _unlike(parts)),
        why=why,
    )


def steering_conventional_verdict(curving: Curving) -> Verdict:
    """Fig. 9(b) without steering: both angles below ``a/R``."""
    s, ideal = curving.steady, curving.ideal_yaw
    psi = (s["psi_TW1_conventional"], s["psi_TW2_conventional"])
    shares = [abs(p) / ideal for p in psi]
    agrees = all(r < 1.0 for r in shares)
    k_conventional, k_steered = curving.kx1.get("conventional"), curving.kx1.get("steered")
    why = ""
    if k_conventional and k_steered:
        why = (f"The conventional axle-box support is {'stiffer' if k_conventional > k_steered else 'not stiffer'} "
               f"(k_x1 = {k_conventional / 1e6:g} MN/m, against {k_steered / 1e6:g} MN/m on the steered bogie)"
               + (", so the wheelsets stay almost parallel to the frame." if max(shares) < RADIAL_TOLERANCE else "."))
    return Verdict(
        key="steering_conventional", quantity="Steering angle without steering (Fig. 9b)",
        paper=PAPER.steering_angle_ideal.value, computed=max(abs(p) for p in psi), agrees=agrees,
        test="|ψ_TW1|, |ψ_TW2| < a/R",
        paper_text="smaller in magnitude than a/R on both axles",
        computed_text=(f"ψ_TW1 = {psi[0] * 1e3:+.3f} mrad, ψ_TW2 = {psi[1] * 1e3:+.3f} mrad "
                       f"({_pct(shares[0])} and {_pct(shares[1])} of a/R)"),
        wording=("Agrees with the paper: both smaller than a/R." if agrees else
                 _unlike([f"axle {j} reaches {_pct(r)} of a/R" for j, r in enumerate(shares, 1) if r >= 1.0])),
        why=why,
    )


def q1_conventional_verdict(curving: Curving) -> Verdict:
    """Fig. 9(c) without steering: Q1 against the paper's 32 kN."""
    s, paper = curving.steady, PAPER.q1_conventional.value
    q1, q2 = s["Q1_conventional"], s["Q2_conventional"]
    agrees, wording = agreement(q1, paper, FORCE_TOLERANCE)
    flanges = _flanges(curving.flanging["conventional"])
    share = ("the leading outer wheel carries most of the bogie's lateral load" if q1 > q2
             else "the two axles share the bogie's lateral load")
    why = (f"With flange contact on {flanges}, {share}, which is set by the cant deficiency v²/R − gS/G = "
           f"{curving.cant_deficiency:.2f} m/s² on our {curving.car_mass / 1e3:.1f} t car. We did not have the paper's "
           "car data (its ref. 4), so the mass and suspension are ours. Q is the lateral force on the flanging "
           "wheel: the flange force plus that wheel's half of the lateral creep force.")
    return Verdict(
        key="q1_conventional", quantity="Lateral force Q1 without steering (Fig. 9c)",
        paper=paper, computed=q1, agrees=agrees, test=f"|Q1/{paper / 1e3:g} kN − 1| ≤ {_pct(FORCE_TOLERANCE)}",
        paper_text=f"{paper / 1e3:g} kN",
        computed_text=(f"{_kn(q1)} (steady curve; peak {_kn(curving.peaks['Q1_conventional_max'])}); Q2 = {_kn(q2)}; "
                       f"flange contact on {flanges}"),
        wording=wording, why=why,
    )


def q1_steered_verdict(curving: Curving) -> Verdict:
    """Fig. 9(c) with steering: Q1 against the paper's 14 kN, and the even-share bound."""
    s = curving.steady
    paper, paper_before = PAPER.q1_steered.value, PAPER.q1_conventional.value
    q1 = s["Q1_steered"]
    agrees, wording = agreement(q1, paper, FORCE_TOLERANCE)
    per_axle = curving.bogie_force / 2
    why = (f"Once the two axles share the load, each carries half of the bogie's cant-deficiency force, "
           f"(m_c/2 + m_t + 2 m_w)(v²/R − gS/G)/2 = {_kn(per_axle)} for our car.")
    if per_axle > paper * (1 + FORCE_TOLERANCE):
        why += (f" That alone exceeds the paper's {paper / 1e3:g} kN, so the paper's model must have carried a "
                "smaller lateral load (a lighter car, or less cant deficiency).")
    elif per_axle < paper * (1 - FORCE_TOLERANCE):
        why += f" That is below the paper's {paper / 1e3:g} kN: the paper's car carried a larger lateral load."
    else:
        why += f" That matches the paper's {paper / 1e3:g} kN."
    why += f" Our Q1 is {(q1 - per_axle) / 1e3:+.1f} kN off that even share."
    reduction = 1 - q1 / s["Q1_conventional"]
    return Verdict(
        key="q1_steered", quantity="Lateral force Q1 with steering (Fig. 9c)",
        paper=paper, computed=q1, agrees=agrees, test=f"|Q1/{paper / 1e3:g} kN − 1| ≤ {_pct(FORCE_TOLERANCE)}",
        paper_text=f"about {paper / 1e3:g} kN (a {_pct(1 - paper / paper_before)} reduction)",
        computed_text=(f"{_kn(q1)} ({_pct(reduction)} reduction; peak {_kn(curving.peaks['Q1_steered_max'])}); "
                       f"flange contact on {_flanges(curving.flanging['steered'])}"),
        wording=wording, why=why,
    )


def q2_over_q1_verdict(curving: Curving) -> Verdict:
    """Fig. 9(c): with steering Q1 falls, Q2 rises and the two become nearly equal."""
    s = curving.steady
    q1c, q2c, q1s, q2s = s["Q1_conventional"], s["Q2_conventional"], s["Q1_steered"], s["Q2_steered"]
    ratio = q2s / q1s
    falls, rises = q1s < q1c, q2s > q2c
    equal = abs(ratio - PAPER.q2_over_q1_steered.value) <= NEARLY_EQUAL
    agrees = falls and rises and equal
    parts = []
    if not falls:
        parts.append("Q1 does not fall with steering")
    if not rises:
        parts.append("Q2 does not rise with steering")
    if not equal:
        parts.append(f"Q2 is {_pct(ratio)} of Q1, not nearly equal")
    return Verdict(
        key="q2_over_q1", quantity="Q2 against Q1 with steering (Fig. 9c)",
        paper=PAPER.q2_over_q1_steered.value, computed=ratio, agrees=agrees,
        test=f"Q1 falls, Q2 rises, |Q2/Q1 − 1| ≤ {_pct(NEARLY_EQUAL)}",
        paper_text="Q1 falls, Q2 rises, and the two become almost equal",
        computed_text=f"Q2/Q1 = {ratio:.2f}; Q1 {_kn(q1c)} → {_kn(q1s)}, Q2 {_kn(q2c)} → {_kn(q2s)}",
        wording=(f"As in the paper: Q1 falls, Q2 rises, and the two are nearly equal (within {_pct(NEARLY_EQUAL)})."
                 if agrees else _unlike(parts)),
        why=("How evenly the two wheelsets share the bogie's lateral load follows how near both come to the radial "
             f"position (ψ_TW rows above); flange contact on {_flanges(curving.flanging['steered'])} with steering."),
    )


# --------------------------------------------------------------------------------------
# Fig. 11, Fig. 3, Fig. 10
# --------------------------------------------------------------------------------------


def vcr_conventional_verdict(shape: VcrShape) -> Verdict:
    """Fig. 11 without steering: ``V_cr`` falls as the conicity grows."""
    agrees = shape.conventional_falls
    how = "falls monotonically" if shape.conventional_monotonic else ("falls" if agrees else "does not fall steadily")
    why = ("A larger conicity shortens the kinematic wavelength and raises the hunting frequency at a given speed, "
           "and the creep damping (∝ 1/v) runs out at a lower speed. " if agrees else "")
    return Verdict(
        key="vcr_conventional", quantity="V_cr against Γ, conventional bogies (Fig. 11)",
        paper=None, computed=shape.conventional_last_kmh / shape.conventional_first_kmh, agrees=agrees,
        test="V_cr lower at the largest Γ than at the smallest, no rise between beyond the bisection tolerance",
        paper_text="V_cr falls as Γ grows",
        computed_text=(f"{how} from {shape.conventional_first_kmh:.0f} km/h (Γ = {shape.first_conicity:.2f}) to "
                       f"{shape.conventional_last_kmh:.0f} km/h (Γ = {shape.last_conicity:.2f}); "
                       f"{shape.conventional_at_reference_kmh:.0f} km/h at Γ = {shape.reference_conicity:g}"),
        wording="Same shape as the paper." if agrees else "Unlike the paper, V_cr does not fall steadily as Γ grows.",
        why=why + ("The paper's text gives no absolute V_cr, so only the shape can be compared. A linear V_cr with a "
                   "constant equivalent conicity is not a prediction for service."),
    )


def _low_conicity_sentence(sweep: StabilitySweep) -> str:
    low = sweep.low_conicity
    if low is None:
        return ""
    cut = low.link_cut_kmh
    text = (f" At Γ = {low.conicity:.2f} the mode that goes unstable is '{low.mode}' at {low.frequency_hz:.2f} Hz, "
            f"already at {low.speed_kmh:.0f} km/h. With the steering link cut (k_LU → 0, a check run) the same car "
            f"is stable up to {sweep.v_max / KMH if cut is None else cut:.0f} km/h")
    if cut is None or cut > 2 * low.speed_kmh:
        return text + (". So the fall comes from the linkage, which feeds the car-body–bogie yaw into the wheelsets, "
                       "while a small conicity gives the wheelsets little restoring force.")
    return text + ". So the linkage is not what makes it fall."


def _merge_sentence(sweep: StabilitySweep, shape: VcrShape) -> str:
    gap = abs(shape.steered_last_kmh - shape.conventional_last_kmh) / shape.conventional_last_kmh
    if not math.isfinite(gap):
        return ""
    if gap > MERGE:
        return f" At Γ = {shape.last_conicity:.2f} the two curves stay {_pct(gap)} apart."
    hunting = all("hunting" in (sweep.modes[name][-1] or "") for name in ("steered", "conventional"))
    return (f" Towards large Γ the two curves merge ({shape.steered_last_kmh:.0f} and {shape.conventional_last_kmh:.0f} "
            f"km/h at Γ = {shape.last_conicity:.2f})"
            + (": bogie hunting limits both cars." if hunting else "."))


def vcr_steered_verdict(sweep: StabilitySweep, shape: VcrShape) -> Verdict:
    """Fig. 11 with steering: a maximum near the paper's conicity, a sharp fall towards 0."""
    reference = PAPER.conicity_of_max_vcr.value
    near = abs(math.log(shape.steered_max_conicity / reference)) <= math.log(CONICITY_FACTOR)
    sharp = shape.steered_fall < SHARP_FALL
    agrees = near and sharp
    parts = []
    if not near:
        parts.append(f"the maximum lies at Γ = {shape.steered_max_conicity:.2f}, not near {reference:g}")
    if not sharp:
        parts.append(f"V_cr at Γ = {shape.first_conicity:.2f} is still {_pct(shape.steered_fall)} of the maximum")
    half = (f"below half the maximum for Γ ≤ {shape.steered_half_conicity:.2f}; "
            if shape.steered_half_conicity is not None else "")
    first = (f"unstable from the lowest speed scanned at Γ = {shape.first_conicity:.2f}"
             if shape.steered_first_unstable_at_min else
             f"{shape.steered_first_kmh:.0f} km/h at Γ = {shape.first_conicity:.2f}")
    return Verdict(
        key="vcr_steered", quantity="V_cr against Γ, forced steering (Fig. 11)",
        paper=reference, computed=shape.steered_max_conicity, agrees=agrees,
        test=(f"Γ of the maximum within a factor {CONICITY_FACTOR:g} of {reference:g}, and V_cr at the smallest Γ "
              f"< {_pct(SHARP_FALL)} of the maximum"),
        paper_text=f"maximum near Γ ≈ {reference:g}, then a sharp fall towards Γ → 0",
        computed_text=(f"maximum {shape.steered_max_kmh:.0f} km/h at Γ = {shape.steered_max_conicity:.2f}; "
                       f"{shape.steered_at_reference_kmh:.0f} km/h at Γ = {shape.reference_conicity:g}; {half}{first}"),
        wording=("Same shape as the paper: the maximum lies near its Γ and V_cr falls sharply towards Γ → 0."
                 if agrees else _unlike(parts)),
        why=(_low_conicity_sentence(sweep) + _merge_sentence(sweep, shape)).strip(),
    )


def lever_step_verdict(lever: LeverStep) -> Verdict:
    """Fig. 3: the sign of the static lever angle in each Table 1 case."""
    tiny = 1e-9 * lever.step
    signs = [0 if abs(q) <= tiny else int(np.sign(q)) for q in lever.static_q2]
    expected = [case.expected_sign for case in lever.cases]
    wrong = [case.case for case, s, e in zip(lever.cases, signs, expected, strict=True) if s != e]
    relation = {1: ">", -1: "<", 0: "="}
    why = ""
    for printed, used in swapped_cases(lever):
        symbol = printed.condition.split()[2]
        why += (f"Case {printed.case} as printed (l_LU {printed.upper_arm:.2f} m, l_LL {printed.lower_arm:.2f} m, k_LU "
                f"{printed.upper_stiffness / 1e3:g} and k_LL {printed.lower_stiffness / 1e3:g} kN/m) gives l_LU k_LU = "
                f"{printed.upper_moment / 1e3:g} kN against l_LL k_LL = {printed.lower_moment / 1e3:g} kN. That "
                f"violates its own condition, so it could not give q2 {relation[printed.expected_sign]} 0. We use "
                f"l_LU {used.upper_arm:.2f} m and l_LL {used.lower_arm:.2f} m instead, for which {used.upper_moment / 1e3:g} "
                f"{symbol} {used.lower_moment / 1e3:g} kN. ")
    why += (f"J2 = {LEVER_VALUES['J2']:g} kg m², an added damper c_L = {lever.damping:g} N m s/rad and b = "
            f"{LEVER_VALUES['b']:g} m are our choices; they shape only the transient.")
    return Verdict(
        key="lever_step", quantity="Lever step response (Fig. 3, Table 1)",
        paper=None, computed=float(len(expected) - len(wrong)), agrees=not wrong,
        test="sign of the static q2 = the sign Table 1's condition states, in every case",
        paper_text=", ".join(f"q2 {relation[c.expected_sign]} 0 in case {c.case}" for c in lever.printed),
        computed_text=("static q2 = " + ", ".join(f"{v * 1e3:+.3f} mrad" for v in lever.static_q2)
                       + f" for a q1 step of {lever.step * 1e3:g} mrad"),
        wording=("Agrees with the paper: the sign of q2 follows l_LU k_LU against l_LL k_LL in every case."
                 if not wrong else _unlike([f"case {c}: q2 has the wrong sign" for c in wrong])),
        why=why,
    )


def floor_verdict(response: FloorResponse) -> Verdict:
    """Fig. 10: the front and rear floor responses differ."""
    differences = response.front_rear_difference
    agrees = all(d > DIFFERENT for d in differences.values())
    near = response.nearest_mode
    why = "The paper's text gives no amplitudes to compare with."
    if near is not None:
        frequency = response.peaks["floor_front_steered"][1]
        why += (f" The steered car's front peak at {frequency:.2f} Hz lies next to its mode '{near['description']}' "
                f"({near['frequency_hz']:.2f} Hz, damping ratio {near['damping_ratio']:.2f}) at "
                f"{response.speed / KMH:.0f} km/h.")
    why += (f" The dips recur about every v/(2 l_T) = {response.notch_spacing:.1f} Hz. The rear bogie meets the same "
            f"irregularity {response.bogie_delay:.2f} s later, so the inputs of the two bogies alternately add and "
            "cancel (geometric filtering).")
    peaks = "; ".join(f"{k.replace('floor_', '').replace('_', ', ')} {a:.3f} m/s² at {f:.2f} Hz"
                      for k, (a, f) in response.peaks.items())
    return Verdict(
        key="floor_front_rear", quantity="Floor acceleration above the bogie centres (Fig. 10)",
        paper=None, computed=min(differences.values()), agrees=agrees,
        test=f"max |a_front − a_rear| / max a > {_pct(DIFFERENT)} for each car",
        paper_text="front and rear differ because of the phase between the car body's sway, yaw and roll",
        computed_text=(f"peaks: {peaks}; front and rear part by up to "
                       + ", ".join(f"{_pct(d)} ({name})" for name, d in differences.items())),
        wording=("As in the paper, the front and rear responses differ." if agrees else
                 f"Unlike the paper, the front and rear responses stay within {_pct(DIFFERENT)} of each other."),
        why=why,
    )


def summary_rows(lever: LeverStep, curving: Curving, response: FloorResponse, sweep: StabilitySweep) -> list[Verdict]:
    """Every row of the summary, in the table's order."""
    shape = vcr_shape(sweep)
    return [
        steering_geometry_verdict(curving),
        lever_angle_verdict(curving),
        steering_steered_verdict(curving),
        steering_conventional_verdict(curving),
        q1_conventional_verdict(curving),
        q1_steered_verdict(curving),
        q2_over_q1_verdict(curving),
        vcr_conventional_verdict(shape),
        vcr_steered_verdict(sweep, shape),
        lever_step_verdict(lever),
        floor_verdict(response),
    ]
