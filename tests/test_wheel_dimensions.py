"""EN 15313's flange dimensions of worn profiles (``express.rail.wheel_dimensions``)
against closed forms on a profile with a straight flank.

The measuring point of Sd is 10 mm from the tread datum toward the flange tip, and the
datum moves with the tread's wear: tread wear alone raises the measuring point toward
the flange root, where the flange is thicker, so Sd *grows* by ``d / tan(gamma)``
(``gamma`` the flank angle) as Sh grows by ``d``; wear of the flank alone thins it by the
same ``d / tan(gamma)``.  This is why a route of mostly large-radius curves, wearing the
tread more than the flank, shows Sd rising slightly (``docs/wear.md``).
"""

from __future__ import annotations

import numpy as np
import pytest

from express.rail.wheel_dimensions import flange_dimensions

#: A synthetic wheel: inner face 70 mm inward of the taping line, the flange tip at
#: y = -50 mm, 28 mm below the tread; a straight flank up to the flat tread at y = -25 mm.
CORNERS = np.array([[-0.066, -0.015], [-0.060, -0.025], [-0.050, -0.028], [-0.025, 0.0], [0.060, 0.0]])
TAN_GAMMA = 0.028 / 0.025  # the flank's slope dz/dy
Y = np.linspace(-0.066, 0.060, 12601)  # 0.01 mm spacing
Z = np.interp(Y, CORNERS[:, 0], CORNERS[:, 1])


def test_the_new_profile_against_hand_computation():
    """Sd: the flank reaches the datum - 10 mm at y = -50 + 18 / 1.12 mm; Sh 28 mm."""
    dims = flange_dimensions(Y, Z)
    assert dims.thickness == pytest.approx(0.070 - 0.050 + 0.018 / TAN_GAMMA, abs=1e-9)
    assert dims.height == pytest.approx(0.028, abs=1e-12)


@pytest.mark.parametrize("where, depth, d_thickness, d_height", [
    ("tread", 0.5e-3, +0.5e-3 / TAN_GAMMA, 0.5e-3),   # the datum and the measuring point rise
    ("tread", 2.0e-3, +2.0e-3 / TAN_GAMMA, 2.0e-3),
    ("flank", 0.5e-3, -0.5e-3 / TAN_GAMMA, 0.0),      # the flank moves toward the back
    ("flank", 1.0e-3, -1.0e-3 / TAN_GAMMA, 0.0),
    ("both", 1.0e-3, 0.0, 0.0),                       # a uniform depth: the same flange
])
def test_worn_profiles_move_sd_and_sh_as_the_closed_form(where, depth, d_thickness, d_height):
    """Achieved: 1e-12 m or better (the straight flank is linear between the grid's
    points), asserted 1e-9 m."""
    band = {"tread": Y >= -0.020, "flank": (Y > -0.047) & (Y < -0.028), "both": np.ones_like(Y, dtype=bool)}[where]
    new, worn = flange_dimensions(Y, Z), flange_dimensions(Y, Z + depth * band)
    assert worn.thickness - new.thickness == pytest.approx(d_thickness, abs=1e-9)
    assert worn.height - new.height == pytest.approx(d_height, abs=1e-9)
