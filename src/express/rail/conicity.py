"""Equivalent conicity by EN 15302: the wavelength of the wheelset's kinematic
oscillation with the nonlinear rolling-radius difference, compared with Klingel's.

The kinematic (creep-free) wheelset obeys ``y'' = -delta_r(y) / (e r0)`` along the
track (e the distance between the contact points, r0 the rolling radius).  Its energy
integral gives the oscillation of amplitude ``a`` between the turning points y1 < y0 < y2
with ``S(y1) = S(y2) = C``, ``S(y) = integral_{y0}^{y} delta_r``, ``a = (y2 - y1) / 2`` and
the wavelength ``L = 2 sqrt(e r0 / 2) * I``, ``I = integral_{y1}^{y2} dy / sqrt(C - S)``.
Klingel's formula for a cone of slope ``tan(gamma)`` gives ``L = 2 pi sqrt(e r0 / (2 tan(gamma)))``;
equating the two, ``tan(gamma_e) = pi^2 / I^2``, independent of e and r0.

``delta_r`` is piecewise linear between its points, so S is piecewise quadratic and I is
summed exactly, segment by segment, in closed form (no quadrature, no smoothing): a
linear ``delta_r = 2 lambda y`` gives lambda at every amplitude to rounding.  An amplitude
inside a dead band (``delta_r = 0`` around the centre) has tan(gamma_e) = 0; an amplitude
whose turning points lie beyond the tabulated ``delta_r`` is an error, never an
extrapolation.  This is EN 15302's reference procedure (its Annex B integration of the
nonlinear equation), checked against the standard's reference cases (``docs/contact.md``).
"""

from __future__ import annotations

import itertools
import math
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numba import njit

from express.base.diagnostics import ArgumentError, ModelError, Problem, RowProblems, excerpt
from express.base.limits import read_input_text
from express.rail.contact_geometry import ContactSetup, ContactTable, contact_geometry
from express.rail.profiles import Profile, row_numbers

__all__ = [
    "DeltaR",
    "conicity_from_profiles",
    "equivalent_conicity",
    "parse_amplitudes",
    "parse_delta_r",
    "read_delta_r",
]

_HEADER = re.compile(r"(y|delta_r)_(m|mm)\Z", re.IGNORECASE)
_UNITS = {"m": 1.0, "mm": 1e-3}
_SPLIT = re.compile(r"[,;\s]+")


@dataclass(frozen=True, eq=False)
class DeltaR:
    """A rolling-radius difference function, piecewise linear between its points.

    ``y`` (strictly increasing) and ``delta_r = r_left - r_right`` in metres, shape (n,);
    ``source`` names the file for messages.
    """

    y: np.ndarray
    delta_r: np.ndarray
    source: str = "<delta_r>"


# ----------------------------------------------------------------------------- reading


def read_delta_r(path: str | Path) -> DeltaR:
    """Read a Δr CSV file: header ``y_m,delta_r_m`` (or ``y_mm,delta_r_mm``), then one
    ``y,delta_r`` pair a line; ``#`` starts a comment.

    Raises
    ------
    ModelError
        Every problem at once, with file and line: unreadable, missing or wrong header,
        wrong column count, a value that is not a finite number, y not increasing, too few
        points, values implausible for the unit, no centred position (Δr never rises
        through zero).
    """
    path = Path(path)
    return parse_delta_r(read_input_text(path, what="the delta-r file"), str(path))  # bounded (EXPRESS_MAX_FILE_MB), UTF-8 text


def parse_delta_r(text: str, file: str = "<delta_r>") -> DeltaR:
    """:func:`read_delta_r` on text already read."""
    problems: list[Problem] = []
    factors: tuple[float, float] | None = None
    rows: list[tuple[int, float, float]] = []
    bad = RowProblems(file)  # the file may not be the user's own: one short excerpt, 20 rows
    for number, raw in enumerate(text.splitlines(), start=1):
        line = raw.split("#", 1)[0].strip()
        if not line:
            continue
        fields = [field for field in _SPLIT.split(line) if field]
        if factors is None and not rows and not any(p.item == "header" for p in problems):
            factors = _header(fields, file, number, problems)
            bad.quoted = bool(problems)  # the header's problem quoted the file already
            if factors is not None or any(ch.isalpha() for ch in line):
                continue
        if len(fields) != 2:
            bad.add(number, "", f"expected 2 columns (y, delta_r), found {len(fields)}", line)
            continue
        values = row_numbers(fields, ("y", "delta_r"), number, bad)
        if values is not None:
            rows.append((number, values[0], values[1]))
    problems += bad.problems()
    if factors is None and not any(p.item == "header" for p in problems):
        problems.append(Problem(file, None, "header", "missing header: the first line must be y_m,delta_r_m"))
    if len(rows) < 2:
        problems.append(Problem(file, None, "", f"{len(rows)} data points: a delta-r function needs at least 2"))
    if problems:
        raise ModelError(problems)
    assert factors is not None
    lines = [row[0] for row in rows]
    y = np.array([row[1] for row in rows]) * factors[0]
    delta_r = np.array([row[2] for row in rows]) * factors[1]
    problems += _check_function(y, delta_r, lines, file, factors)
    if problems:
        raise ModelError(problems)
    return DeltaR(y, delta_r, file)


def _header(fields: list[str], file: str, number: int, problems: list[Problem]) -> tuple[float, float] | None:
    matches = [_HEADER.match(field) for field in fields]
    if len(fields) == 2 and all(matches) and [m.group(1).lower() for m in matches if m] == ["y", "delta_r"]:
        return tuple(_UNITS[m.group(2).lower()] for m in matches if m)  # type: ignore[return-value]
    shown = excerpt(",".join(fields))
    problems.append(Problem(file, number, "header", f"{shown}: expected the columns y_m,delta_r_m (or y_mm,delta_r_mm)"))
    return None


def _check_function(y, delta_r, lines, file, factors) -> list[Problem]:
    problems = []
    for i in np.flatnonzero(np.diff(y) <= 0)[:20] + 1:
        problems.append(Problem(file, lines[i], "y", f"y = {y[i] / factors[0]:g} does not increase (line {lines[i - 1]} "
                                f"has {y[i - 1] / factors[0]:g}); the points must be sorted by y without repeats"))
    for name, values, factor in (("y", y, factors[0]), ("delta_r", delta_r, factors[1])):
        worst = int(np.argmax(np.abs(values)))
        if abs(values[worst]) > 0.1:
            hint = " (the values look like mm: use the header y_mm,delta_r_mm)" if factor == 1.0 else ""
            problems.append(Problem(file, lines[worst], name, f"{values[worst] / factor:g} is {abs(values[worst]):g} m, "
                                    f"implausible for a wheelset{hint}"))
    if not problems and _centre(y, delta_r) is None:
        problems.append(Problem(file, None, "delta_r", "never rises through zero: there is no centred position "
                                "(delta_r = r_left - r_right must go from negative to positive)"))
    return problems


def parse_amplitudes(text: str) -> np.ndarray:
    """``"1:7.5:0.1 mm"`` -> amplitudes 1, 1.1, ..., 7.5 mm in metres (stop included
    within a tenth of a step); a single value is one amplitude; the unit defaults to mm."""
    body, _, unit = text.strip().partition(" ")
    unit = unit.strip() or "mm"
    if unit not in _UNITS:
        raise ArgumentError(f'amplitudes "{text}": the unit must be mm or m')
    try:
        parts = [float(part) for part in body.split(":")]
    except ValueError:
        raise ArgumentError(f'amplitudes "{text}": expected START:STOP:STEP [mm|m], e.g. 1:7.5:0.1 mm') from None
    if len(parts) == 1:
        values = np.array(parts)
    elif len(parts) == 3 and parts[2] > 0 and parts[1] >= parts[0]:
        count = math.floor((parts[1] - parts[0]) / parts[2] + 0.1) + 1
        values = parts[0] + parts[2] * np.arange(count)
    else:
        raise ArgumentError(f'amplitudes "{text}": expected START:STOP:STEP with STEP > 0 and STOP >= START')
    if not np.all(np.isfinite(values)) or np.any(values <= 0):
        raise ArgumentError(f'amplitudes "{text}": amplitudes must be positive')
    return values * _UNITS[unit]


# ----------------------------------------------------------------------- the method


def _centre(y: np.ndarray, delta_r: np.ndarray) -> tuple[float, float] | None:
    """The centred position: where delta_r rises through zero nearest y = 0, as the
    interval (left, right) of a dead band (equal ends for a single crossing)."""
    nonzero = np.flatnonzero(delta_r != 0.0)
    best = None
    for a, b in itertools.pairwise(nonzero):
        if not (delta_r[a] < 0.0 < delta_r[b]):
            continue
        if b == a + 1:
            left = right = y[a] - delta_r[a] * (y[b] - y[a]) / (delta_r[b] - delta_r[a])
        else:
            left, right = y[a + 1], y[b - 1]
        if best is None or abs(0.5 * (left + right)) < abs(0.5 * (best[0] + best[1])):
            best = (float(left), float(right))
    return best


@dataclass(frozen=True)
class _Branch:
    """One side of the oscillation: u >= 0 outward from the centre, restoring slope D(u)."""

    u: np.ndarray
    du: np.ndarray
    d: np.ndarray
    m: np.ndarray
    s: np.ndarray
    reach: np.ndarray  # highest S reached up to the end of each segment

    @staticmethod
    def build(u: np.ndarray, d: np.ndarray) -> _Branch:
        du = np.diff(u)
        m = np.diff(d) / du
        s = np.concatenate([[0.0], np.cumsum(0.5 * du * (d[:-1] + d[1:]))])
        peak = np.maximum(s[:-1], s[1:])
        with np.errstate(divide="ignore", invalid="ignore"):
            t = -d[:-1] / m
            inside = (m < 0) & (t > 0) & (t < du)
            t = np.where(inside, t, 0.0)
        vertex = s[:-1] + d[:-1] * t + 0.5 * m * t * t
        peak = np.where(inside, np.maximum(peak, vertex), peak)
        return _Branch(u, du, d, m, s, np.maximum.accumulate(peak))

    def crossing(self, energy: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Segment and offset where S first reaches ``energy`` (each <= reach[-1])."""
        j = np.minimum(np.searchsorted(self.reach, energy, side="left"), len(self.m) - 1)
        a = np.maximum(energy - self.s[j], 0.0)
        d, m = self.d[j], self.m[j]
        root = np.sqrt(np.maximum(d * d + 2.0 * m * a, 0.0))
        with np.errstate(divide="ignore", invalid="ignore"):
            t = np.where(d > 0, 2.0 * a / (d + root), (root - d) / m)
        t = np.where(np.isfinite(t), t, 0.0)
        return j, np.minimum(np.maximum(t, 0.0), self.du[j])

    def integral(self, j: np.ndarray, t: np.ndarray) -> np.ndarray:
        """Sum over the segments up to the turning point (segment j, offset t) of
        integral du / sqrt(C - S), with C = S there (one value per turning point)."""
        out = np.empty(len(j))
        _branch_integral(self.du, self.d, self.m, self.s, j.astype(np.int64), t.astype(float), out)
        return out


@njit(cache=True)
def _branch_integral(du, d, m, s, j, t, out):
    """:meth:`_Branch.integral`, compiled.  C - S is built from t at the turning point's
    own segment, so the square roots next to it carry no rounding residue of C - S_j."""
    for k in range(len(j)):
        jk, tk = j[k], t[k]
        last = max(d[jk] * tk + 0.5 * m[jk] * tk * tk, 0.0)  # C - S_j
        energy = s[jk] + last
        total = 0.0
        for i in range(jk + 1):
            dt = du[i] if i < jk else tk
            if dt <= 0.0:
                continue
            q0 = math.sqrt(last) if i == jk else math.sqrt(max(energy - s[i], 0.0))
            if i == jk:
                q1 = 0.0
            elif i == jk - 1:
                q1 = math.sqrt(last)
            else:
                q1 = math.sqrt(max(energy - s[i + 1], 0.0))
            total += _piece(dt, q0, q1, -0.5 * d[i], -0.5 * (d[i] + m[i] * dt), m[i])
        out[k] = total


@njit(cache=True)
def _piece(dt, q0, q1, p0, p1, m):
    """integral_0^dt dt / sqrt(Q) for Q = C - S quadratic with Q' / 2 = P, in closed form.

    q = sqrt(Q) and P = -delta_r / 2 at both ends; m is the slope of delta_r.  Rising
    delta_r (m > 0): the circle form atan2(k (q1 P0 - q0 P1), k^2 q0 q1 + P0 P1) / k with
    k = sqrt(m / 2); falling: the logarithm, written with log1p; m = 0: Q linear or
    constant.  Each form tends to the next without cancellation.
    """
    if m > 0.0:
        k = math.sqrt(0.5 * m)
        return math.atan2(k * (q1 * p0 - q0 * p1), k * k * q0 * q1 + p0 * p1) / k
    if m < 0.0:
        k = math.sqrt(-0.5 * m)
        if p0 >= 0.0:
            return math.log1p(k * (k * dt + q1 - q0) / (p0 + k * q0)) / k
        return -math.log1p((k * k * dt - k * (q1 - q0)) / (p0 - k * q0)) / k
    if p0 != 0.0:
        return (q1 - q0) / p0
    return dt / q0


#: |delta_r| at or below this is rounding and counts as 0 [m] (1 pm).
_ROUNDING = 1e-12


def equivalent_conicity(
    y: np.ndarray | DeltaR,
    delta_r: np.ndarray | None = None,
    amplitudes: np.ndarray | float = 3e-3,
) -> np.ndarray:
    """EN 15302 equivalent conicity tan(gamma_e) at each amplitude.

    Parameters
    ----------
    y, delta_r : array_like, shape (n,)
        Lateral displacement [m] (strictly increasing) and rolling radius difference
        r_left - r_right [m], piecewise linear in between; or a :class:`DeltaR` as ``y``.
        Values of at most 1 pm count as 0 (the rounding of a dead band).
    amplitudes : float or array_like
        Amplitudes of the wheelset's lateral oscillation [m] (half its peak-to-peak).

    Returns
    -------
    numpy.ndarray
        tan(gamma_e), one per amplitude (0 inside a dead band).

    Raises
    ------
    ModelError
        One problem per amplitude the function cannot support (its turning points would
        lie beyond the tabulated y, or between two wells of a non-monotonic delta_r), or
        no centred position.
    """
    source = "<delta_r>"
    if isinstance(y, DeltaR):
        source, y_values, delta_r = y.source, y.y, y.delta_r
    else:
        y_values = y
    y = np.asarray(y_values, dtype=float)
    delta_r = np.asarray(delta_r, dtype=float)
    scalar = np.ndim(amplitudes) == 0
    amplitudes = np.atleast_1d(np.asarray(amplitudes, dtype=float))
    if y.shape != delta_r.shape or y.ndim != 1 or len(y) < 2 or np.any(np.diff(y) <= 0):
        raise ArgumentError("y and delta_r must be 1-D, of one length >= 2, y strictly increasing")
    if not (np.all(np.isfinite(y)) and np.all(np.isfinite(delta_r))):
        raise ArgumentError("y and delta_r must be finite")
    if np.any(~np.isfinite(amplitudes) | (amplitudes <= 0)):
        raise ArgumentError("amplitudes must be positive")
    # a symmetric profile pair's dead band comes out of the geometry as +-1e-17 m of
    # rounding, which would count as many centred positions: below 1 pm it is zero
    delta_r = np.where(np.abs(delta_r) <= _ROUNDING, 0.0, delta_r)
    centre = _centre(y, delta_r)
    if centre is None:
        raise ModelError([Problem(source, None, "delta_r", "never rises through zero: no centred position")])
    result = _solve(y, delta_r, centre, amplitudes, source)
    return result[0] if scalar else result


def _branches(y, delta_r, centre) -> tuple[_Branch, _Branch]:
    left, right = centre
    keep = y > right
    u_right = np.concatenate([[0.0], y[keep] - right])
    d_right = np.concatenate([[0.0], delta_r[keep]])
    keep = y < left
    u_left = np.concatenate([[0.0], left - y[keep][::-1]])
    d_left = np.concatenate([[0.0], -delta_r[keep][::-1]])
    return _Branch.build(u_left, d_left), _Branch.build(u_right, d_right)


def _solve(y, delta_r, centre, amplitudes, source) -> np.ndarray:
    half_band = 0.5 * (centre[1] - centre[0])
    left, right = _branches(y, delta_r, centre)
    if len(left.m) == 0 or len(right.m) == 0:
        raise ModelError([Problem(source, None, "delta_r", "the centred position is at the end of the function")])
    top = min(left.reach[-1], right.reach[-1])

    def amplitude(energy):
        jl, tl = left.crossing(energy)
        jr, tr = right.crossing(energy)
        return half_band + 0.5 * (left.u[jl] + tl + right.u[jr] + tr), (jl, tl, jr, tr)

    largest, _ = amplitude(np.array([top]))
    energy = _solve_energy(lambda e: amplitude(e)[0], amplitudes, top)
    reached, (jl, tl, jr, tr) = amplitude(energy)
    problems = []
    beyond = amplitudes[amplitudes > largest[0] * (1 + 1e-12)]
    if len(beyond):
        item = (f"amplitude {beyond[0] * 1e3:g} mm" if len(beyond) == 1
                else f"amplitudes {beyond.min() * 1e3:g} .. {beyond.max() * 1e3:g} mm ({len(beyond)} of them)")
        problems.append(Problem(source, None, item,
                                f"needs delta_r beyond its range (y {y[0] * 1e3:g} .. {y[-1] * 1e3:g} mm); "
                                f"the largest amplitude it supports is {largest[0] * 1e3:.4g} mm"))
    for a, got in zip(amplitudes, reached, strict=True):
        if half_band < a <= largest[0] * (1 + 1e-12) and abs(got - a) > 1e-9 + 1e-9 * a:
            problems.append(Problem(source, None, f"amplitude {a * 1e3:g} mm",
                                    "no oscillation of this amplitude: delta_r has a second centred position "
                                    f"(amplitudes jump from {got * 1e3:.4g} mm)"))
    if problems:
        raise ModelError(problems)
    total = left.integral(jl, tl) + right.integral(jr, tr)
    with np.errstate(divide="ignore"):
        total = total + (centre[1] - centre[0]) / np.sqrt(energy)
        tan_gamma = np.pi**2 / total**2
    return np.where(amplitudes <= half_band, 0.0, tan_gamma)


def _solve_energy(amplitude, targets: np.ndarray, top: float) -> np.ndarray:
    """Energies C with amplitude(C) = targets, all at once: regula falsi (Illinois) in
    w = sqrt(C), where the amplitude is nearly linear; bracket [0, sqrt(top)]."""
    lo, hi = np.zeros_like(targets), np.full_like(targets, math.sqrt(top))
    f_lo = amplitude(lo * lo) - targets
    f_hi = amplitude(hi * hi) - targets
    side = np.zeros(len(targets))
    w = hi.copy()
    for _ in range(100):
        with np.errstate(divide="ignore", invalid="ignore"):
            w = np.where(f_hi != f_lo, hi - f_hi * (hi - lo) / (f_hi - f_lo), 0.5 * (lo + hi))
        w = np.where((w > lo) & (w < hi), w, 0.5 * (lo + hi))
        f = amplitude(w * w) - targets
        above = f >= 0.0
        # Illinois: halve the value kept at the end that stays, so the bracket closes
        f_lo = np.where(above, np.where(side < 0, 0.5 * f_lo, f_lo), f)
        f_hi = np.where(above, f, np.where(side > 0, 0.5 * f_hi, f_hi))
        lo, hi = np.where(above, lo, w), np.where(above, w, hi)
        side = np.where(above, -1.0, 1.0)
        if np.all((np.abs(f) < 1e-12) | (hi - lo <= 1e-15 * math.sqrt(top))):
            break
    return w * w


def conicity_from_profiles(
    wheel: Profile,
    rail: Profile,
    amplitudes: np.ndarray | float,
    setup: ContactSetup | None = None,
    *,
    wheel_right: Profile | None = None,
    rail_right: Profile | None = None,
    y_step: float = 0.01e-3,
    margin: float = 3e-3,
) -> tuple[np.ndarray, ContactTable]:
    """Equivalent conicity of a wheel/rail pair: Δr from :func:`contact_geometry` on
    ``y`` in ±(largest amplitude + ``margin``) every ``y_step``, then
    :func:`equivalent_conicity`.  Returns tan(gamma_e) per amplitude and the table."""
    amplitude_array = np.atleast_1d(np.asarray(amplitudes, dtype=float))
    reach = float(np.max(amplitude_array)) + margin
    count = math.ceil(reach / y_step)
    y = y_step * np.arange(-count, count + 1)
    table = contact_geometry(wheel, rail, y, setup, wheel_right=wheel_right, rail_right=rail_right)
    name = f"{wheel.name}/{rail.name}"
    tan_gamma = equivalent_conicity(DeltaR(table.y, table.delta_r, name), amplitudes=amplitude_array)
    return (tan_gamma[0] if np.ndim(amplitudes) == 0 else tan_gamma), table
