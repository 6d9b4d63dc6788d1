"""The validation cases of :mod:`express.rail.creep_table`: Hertzian contacts off the
table's grid, in five regimes, as rows of ``tools/contact_creep_runs.py``'s
:data:`COLUMNS` (physical units of CONTACT: mm, N, N/mm^2, rad/mm), seeded.

    python tools/creep_validation_cases.py OUT.csv

Regimes, with ``u`` the normalised creepage (``docs/contact.md``) and ``a/b``
log-uniform over 0.2...5 (``c = 6 mm``, ``N = 80 kN``, ``mu = 0.3``, ``G = 82 GPa``
except in flange contact):

* ``linear``: ``|u|`` 0.005...0.06, any direction;
* ``partial``: ``|u|`` 0.15...0.9, spin at most half the translational part;
* ``full``: ``|u|`` 1.2...30, spin at most half the translational part;
* ``spin``: ``|u|`` 0.1...30, spin at least twice the translational part;
* ``flange``: ``xi = 1e-3``, ``eta`` 5e-3...1e-2, spin 2...6 1/m, the signs of ``eta``
  and the spin independent (they oppose in half the cases), ``N`` 20...120 kN,
  ``sqrt(ab)`` 4...8 mm, ``mu`` 0.25...0.4, ``G = 80.8 GPa``;
* ``slender`` (30 cases, seed 34, after the others): the flange's creepages on the long,
  narrow ellipses of a flange root, ``a/b`` 5...25, ``sqrt(ab)`` 1.5...3 mm, ``N``
  10...60 kN.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from contact_creep_runs import COLUMNS, physical

PER_REGIME = 50
SEED = 33


def _normalised(rng: np.random.Generator, size: tuple[float, float], spin: tuple[float, float]) -> np.ndarray:
    """A normalised case ``(a/b, u_x, u_y, u_phi)``: ``|u|`` log-uniform in ``size``, the
    spin's share of it (``u_phi / |u_t|``) log-uniform in ``spin``, random signs."""
    ratio = math.exp(rng.uniform(math.log(0.2), math.log(5.0)))
    magnitude = math.exp(rng.uniform(*np.log(size)))
    share = math.exp(rng.uniform(*np.log(spin)))
    azimuth = rng.uniform(0.0, 2.0 * math.pi)
    trans = np.array([math.cos(azimuth), math.sin(azimuth), share * rng.choice((-1.0, 1.0))])
    return np.array([ratio, *(magnitude * trans / np.linalg.norm(trans))])


def _flange(rng: np.random.Generator) -> tuple[float, ...]:
    """A flange-like physical case (rows of :data:`COLUMNS`)."""
    ratio = math.exp(rng.uniform(math.log(0.2), math.log(5.0)))
    size = rng.uniform(4.0, 8.0)
    aa, bb = size * math.sqrt(ratio), size / math.sqrt(ratio)
    eta = rng.uniform(5e-3, 1e-2) * rng.choice((-1.0, 1.0))
    phi = rng.uniform(2.0, 6.0) * rng.choice((-1.0, 1.0)) * 1e-3  # rad/mm
    return (aa, bb, rng.uniform(2e4, 1.2e5), rng.uniform(0.25, 0.4), 80800.0, 1e-3, eta, phi)


def _slender(rng: np.random.Generator) -> tuple[float, ...]:
    """A flange-root case: the flange's creepages on an ellipse long in the rolling direction."""
    ratio = math.exp(rng.uniform(math.log(5.0), math.log(25.0)))
    size = rng.uniform(1.5, 3.0)
    aa, bb = size * math.sqrt(ratio), size / math.sqrt(ratio)
    eta = rng.uniform(5e-3, 1e-2) * rng.choice((-1.0, 1.0))
    phi = rng.uniform(2.0, 6.0) * rng.choice((-1.0, 1.0)) * 1e-3  # rad/mm
    return (aa, bb, rng.uniform(1e4, 6e4), rng.uniform(0.25, 0.4), 80800.0, 1e-3, eta, phi)


def cases() -> list[tuple[str, np.ndarray]]:
    """``(regime, row of COLUMNS)`` of every validation case."""
    rng = np.random.default_rng(SEED)
    out = []
    for regime, size, spin in (("linear", (0.005, 0.06), (0.05, 5.0)), ("partial", (0.15, 0.9), (0.02, 0.5)),
                               ("full", (1.2, 30.0), (0.02, 0.5)), ("spin", (0.1, 30.0), (2.0, 50.0))):
        rows = physical(np.array([_normalised(rng, size, spin) for _ in range(PER_REGIME)]))
        out += [(regime, row) for row in rows]
    out += [("flange", np.array(_flange(rng))) for _ in range(PER_REGIME)]
    slender = np.random.default_rng(SEED + 1)
    out += [("slender", np.array(_slender(slender))) for _ in range(30)]
    return out


def main() -> None:
    with open(sys.argv[1], "w") as out:
        out.write(",".join(("regime", *COLUMNS)) + "\n")
        for regime, row in cases():
            out.write(",".join([regime, *(f"{v:.9g}" for v in row)]) + "\n")


if __name__ == "__main__":
    main()
