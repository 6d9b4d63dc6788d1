"""The reference paper's stated numbers and claims, in one place.

Tanifuji, K. and Suzuki, H. (2001), the automatic generation of equations of motion for
rail vehicles with linkages (EXPRESS), summarized in ``docs/results.md``.  The paper's
figures are not machine-readable; what it states in its text and in Table 1 is recorded
here, each with the figure, table or section it comes from.  Nothing else in the package
types these numbers: the demo (:mod:`express.paper.demo`) compares its results with
:data:`PAPER`, and the track and vehicle values it uses are read from the track and
model objects.

Values are SI (m, rad, N, m/s); ``unit`` names the unit of ``value``.
"""

from __future__ import annotations

from dataclasses import dataclass, field

__all__ = ["PAPER", "Claim", "LeverCase", "PaperReference", "PaperValue"]


@dataclass(frozen=True)
class PaperValue:
    """One number the paper states.

    Attributes
    ----------
    value : float
        In SI units.
    unit : str
        Unit of ``value`` (SI; ``"1"`` for a ratio).
    source : str
        Where the paper states it (figure, table, section).
    note : str
        How it was read (e.g. a misprint corrected), if anything needs saying.
    """

    value: float
    unit: str
    source: str
    note: str = ""


@dataclass(frozen=True)
class Claim:
    """A trend the paper states without a number (its figures are not readable)."""

    text: str
    source: str


@dataclass(frozen=True)
class LeverCase:
    """One leverage case of Table 1 (paper Figs. 2 and 3): the arms ``l_LU``, ``l_LL``
    [m] and link stiffnesses ``k_LU``, ``k_LL`` [N/m] above (upper) and below (lower)
    the lever's pin."""

    case: int
    condition: str
    upper_arm: float
    lower_arm: float
    upper_stiffness: float
    lower_stiffness: float

    @property
    def upper_moment(self) -> float:
        """``l_LU k_LU`` [N]."""
        return self.upper_arm * self.upper_stiffness

    @property
    def lower_moment(self) -> float:
        """``l_LL k_LL`` [N]."""
        return self.lower_arm * self.lower_stiffness

    @property
    def expected_sign(self) -> int:
        """Sign of the lever angle ``q2`` after a positive step of ``q1`` that the case's
        *condition* states: +1 for ``l_LU k_LU < l_LL k_LL``, -1 for ``>``, 0 for ``=``."""
        return {"<": 1, ">": -1, "=": 0}[self._relation()]

    def satisfies_condition(self) -> bool:
        """Do the case's own numbers satisfy its stated condition?"""
        upper, lower = self.upper_moment, self.lower_moment
        relation = self._relation()
        if relation == "=":
            return abs(upper - lower) <= 1e-9 * max(upper, lower)
        return upper < lower if relation == "<" else upper > lower

    def _relation(self) -> str:
        for symbol in ("<", ">", "="):
            if f" {symbol} " in self.condition:
                return symbol
        raise ValueError(f"case {self.case}: no relation in {self.condition!r}")


def _table1() -> tuple[LeverCase, ...]:
    kn = 1e3
    return (
        LeverCase(1, "lLU kLU < lLL kLL", 0.30, 0.06, 500 * kn, 5500 * kn),
        LeverCase(2, "lLU kLU > lLL kLL", 0.06, 0.30, 5500 * kn, 500 * kn),
        LeverCase(3, "lLU kLU = lLL kLL", 0.06, 0.30, 1000 * kn, 5000 * kn),
    )


@dataclass(frozen=True)
class PaperReference:
    """Everything the paper states that the demo compares with (section 4.4 unless noted)."""

    # the forced-steering car (section 4.4, text on Fig. 9)
    half_pin_spacing: PaperValue = PaperValue(1.0, "m", "§4.4, Fig. 9(a) text", "2 b_L = 2.0 m")
    half_bogie_spacing: PaperValue = PaperValue(7.2, "m", "§4.4, Fig. 9(a) text", "2 l_T = 14.4 m")
    lever_upper_arm: PaperValue = PaperValue(0.3, "m", "§4.4, Fig. 9(a) text", "l_LU")
    half_wheelbase: PaperValue = PaperValue(1.15, "m", "§4.4, Fig. 9(b) text", "2a = 2.3 m")
    lever_ratio: PaperValue = PaperValue(
        0.2, "1", "§4.4, Fig. 9(b) text",
        "gamma_L = l_LL/l_LU, printed as 0.02; 1.25 x 0.16 = 0.2 is meant")
    ideal_lever_ratio: PaperValue = PaperValue(
        0.16, "1", "§4.1 and Fig. 9(b) text", "a/l_T, printed as 0.016; 1.15/7.2 = 0.16")
    lever_ratio_factor: PaperValue = PaperValue(1.25, "1", "§4.4, Fig. 9(b) text", "gamma_L against a/l_T")

    # the curve of Fig. 9
    radius: PaperValue = PaperValue(400.0, "m", "Fig. 9 caption, §4.4")
    cant: PaperValue = PaperValue(0.095, "m", "§4.4, Fig. 9 text")
    curve_length: PaperValue = PaperValue(170.0, "m", "§4.4, Fig. 9 text", "circular part")
    transition_length: PaperValue = PaperValue(95.0, "m", "§4.4, Fig. 9 text", "each side")
    speed: PaperValue = PaperValue(120.0 / 3.6, "m/s", "Fig. 9 caption", "120 km/h")
    flange_clearance: PaperValue = PaperValue(0.006, "m", "§4.4, Fig. 9 text", "delta = 6 mm")

    # results of Fig. 9
    lever_angle_geometric: PaperValue = PaperValue(
        0.06, "rad", "§4.4, Fig. 9(a) text", "b_L l_T / (R l_LU)")
    lever_angle: PaperValue = PaperValue(
        0.04, "rad", "§4.4, Fig. 9(a) text", "'about 0.04 rad', short of the geometric angle by the stretch of k_LU")
    steering_angle_ideal: PaperValue = PaperValue(0.0029, "rad", "§4.4, Fig. 9(b) text", "a/R")
    steering_steered: Claim = Claim(
        "both |psi_TW1| and |psi_TW2| approach a/R; |psi_TW2| < |psi_TW1| (larger creep moment on axle 2)",
        "§4.4, Fig. 9(b)")
    steering_conventional: Claim = Claim("both |psi_TW| smaller than a/R", "§4.4, Fig. 9(b)")
    q1_conventional: PaperValue = PaperValue(32e3, "N", "§4.4, Fig. 9(c) text", "32 kN")
    q1_steered: PaperValue = PaperValue(14e3, "N", "§4.4, Fig. 9(c) text", "'about 14 kN'")
    q2_over_q1_steered: PaperValue = PaperValue(
        1.0, "1", "§4.4, Fig. 9(c) text", "Q2 rises and 'the two are almost equal'")

    # Fig. 10
    irregularity_amplitude: PaperValue = PaperValue(0.001, "m", "§4.4, Fig. 10 text", "Y_R = 1 mm")
    floor_front_rear: Claim = Claim(
        "the front and rear floor accelerations differ (phase of the car body's sway, yaw and roll)",
        "§4.4, Fig. 10")

    # Fig. 11
    conicity_of_max_vcr: PaperValue = PaperValue(
        0.1, "1", "§4.4, Fig. 11 text", "forced steering: V_cr is largest near Gamma = 0.1")
    vcr_conventional: Claim = Claim("V_cr falls as Gamma grows", "§4.4, Fig. 11")
    vcr_steered: Claim = Claim("maximum near Gamma = 0.1, a sharp fall as Gamma -> 0", "§4.4, Fig. 11")

    # Fig. 3
    table1: tuple[LeverCase, ...] = field(default_factory=_table1)
    lever_step: Claim = Claim("q2 > 0 in case 1, q2 < 0 in case 2, q2 = 0 in case 3", "§3, Fig. 3 and Table 1")


#: The paper's numbers and claims.
PAPER = PaperReference()
