"""The errors of EXPRESS's creep laws against CONTACT's exact results on the validation
cases (``tests/data/contact_exact/validation.csv``), per regime: the table of
``docs/validation.md``.

    python tools/creep_validation_report.py [CSV]

The error of a case is ``|F - F_exact| / |F_exact|``, ``F = (Fx, Fy)`` the tangential
force; ``|F - F_exact| / (mu N)`` is shown beside it, and the spin moment's
``|Mz - Mz_exact| / max(|Mz_exact|, 0.1 mu N c)`` for the table.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "src"))

from express.rail.creep_law import fastsim, polach  # noqa: E402
from express.rail.creep_table import tabulated_with_moment  # noqa: E402
from express.rail.kalker import kalker_coefficients  # noqa: E402

REGIMES = ("linear", "partial", "full", "spin", "flange", "slender")
POISSON = 0.3


def load(path: Path) -> tuple[np.ndarray, np.ndarray]:
    """Regime labels and the numeric columns (``tools/contact_creep_runs.py``'s, then FX, FY, MZ)."""
    labels = np.loadtxt(path, delimiter=",", skiprows=1, usecols=0, dtype=str)
    return labels, np.loadtxt(path, delimiter=",", skiprows=1, usecols=range(1, 12))


def errors(rows: np.ndarray, law) -> tuple[np.ndarray, np.ndarray]:
    """Relative and ``mu N``-relative errors of ``law``'s force on each case."""
    rel, abs_ = [], []
    for aa, bb, fn, mu, gg, cksi, ceta, cphi, fx, fy, _ in rows:
        a, b = aa * 1e-3, bb * 1e-3
        c11, c22, c23, _ = kalker_coefficients(a, b, POISSON)
        got = law(fn, mu, a, b, gg * 1e6, c11, c22, c23, cksi, ceta, cphi * 1e3)
        miss = float(np.hypot(got[0] - fx, got[1] - fy))
        rel.append(miss / np.hypot(fx, fy))
        abs_.append(miss / (mu * fn))
    return np.array(rel), np.array(abs_)


def moment_errors(rows: np.ndarray) -> np.ndarray:
    """The table's spin-moment errors, relative to ``max(|Mz_exact|, 0.1 mu N c)``."""
    out = []
    for aa, bb, fn, mu, gg, cksi, ceta, cphi, _, _, mz in rows:
        a, b = aa * 1e-3, bb * 1e-3
        c11, c22, c23, _ = kalker_coefficients(a, b, POISSON)
        got = tabulated_with_moment(fn, mu, a, b, gg * 1e6, c11, c22, c23, cksi, ceta, cphi * 1e3)[2]
        out.append(abs(got - mz * 1e-3) / max(abs(mz * 1e-3), 0.1 * mu * fn * np.sqrt(a * b)))
    return np.array(out)


def stats(values: np.ndarray) -> str:
    return " / ".join(f"{100 * v:.2g}" if v < 0.1 else f"{100 * v:.0f}"
                      for v in (np.median(values), np.percentile(values, 90), values.max())) + " %"


def main() -> None:
    path = Path(sys.argv[1]) if len(sys.argv) > 1 else ROOT / "tests/data/contact_exact/validation.csv"
    labels, rows = load(path)
    laws = (("table", tabulated_with_moment), ("FASTSIM 3 x 5", fastsim), ("Polach", polach))
    print("| regime (cases) | " + " | ".join(f"{name} median / p90 / max" for name, _ in laws)
          + " | table: max of mu N | table Mz median / p90 / max |")
    print("|---" * (len(laws) + 3) + "|")
    for regime in REGIMES:
        part = rows[labels == regime]
        cells = []
        for name, law in laws:
            rel, abs_ = errors(part, law)
            cells.append(stats(rel))
            if name == "table":
                worst = f"{100 * abs_.max():.2g} %"
        print(f"| {regime} ({len(part)}) | " + " | ".join(cells) + f" | {worst} | {stats(moment_errors(part))} |")


if __name__ == "__main__":
    main()
