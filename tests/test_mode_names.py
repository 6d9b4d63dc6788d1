"""Mode names from energy (issue 25 item 1): hand-classified modes of every bundled vehicle.

Each table row is ``(frequency [Hz], real part [1/s], expected name)`` of one mode at the
vehicle's own speed; the frequency and real part only find the mode (they come from the
eigenvalues, not from a reference: identifiers, not a validation). The names were
assigned by hand from each mode's participation (the comment: the three largest DOF
shares) and checked against the rules of ``docs/analyses.md``: car body lower sway
below upper sway, hunting only for the kinematic lateral/yaw motion of the wheelsets,
wheelset vertical and roll on the contact springs (the issue's "hunting, both bogies"
at 200 Hz), and never a series element's stroke as the subject.
A ``*`` stands for the location (front / rear / both bogies) of a mode whose eigenvalue
lies within 2 % of another's: in a (nearly) degenerate pair the eigenvectors are any
combination of the two, so the location is arbitrary.
``forced-steering.exp`` and ``lever.exp`` carry no parameter values: the first is the
structure of ``forced-steering.toml`` (``tests/test_classic_reader.py``), the second is
checked here with the values of ``tests/test_lever_cases.py``.
"""

from __future__ import annotations

import fnmatch
from pathlib import Path

import numpy as np
import pytest

from express.analysis.modes.mode_names import kinematic_frequency, mode_energy
from express.analysis.stability.stability import eigen_analysis
from express.io import load_model, parse_toml_model, read_classic
from express.model.parameters import with_values
from express.numeric.statespace import vehicle_model

ROOT = Path(__file__).resolve().parents[1]

MODES = {
    "examples/conventional.toml": [
        (0.000, -0.61, "car body longitudinal, non-oscillatory"),  # CB.x 100%, T1.x 0%, T2.x 0%
        (0.000, -44.16, "wheelset creep, *, non-oscillatory"),  # W1.y 34%, W3.y 27%, T1.y 7%
        (0.000, -44.47, "wheelset creep, *, non-oscillatory"),  # W1.y 51%, T1.y 10%, W3.y 10%
        (0.000, -102.33, "car body longitudinal, non-oscillatory"),  # T1.x 45%, T2.x 45%, CB.x 10%
        (0.000, -202.36, "wheelset creep, *, non-oscillatory"),  # W1.y 15%, W1.rz 14%, W3.y 13%
        (0.000, -202.82, "wheelset creep, *, non-oscillatory"),  # W1.y 14%, W3.y 14%, W1.rz 13%
        (0.113, -316.46, "wheelset lateral, *"),  # W3.y 44%, W1.y 35%, W4.y 12%
        (0.114, -316.46, "wheelset lateral, *"),  # W3.y 60%, W1.y 19%, W4.y 16%
        (0.567, -0.41, "car body lower sway"),  # CB.y 72%, CB.rx 27%, T2.rx 0%
        (0.802, -1.80, "car body yaw"),  # CB.rz 86%, CB.rx 3%, W1.y 2%
        (0.965, -1.37, "car body upper sway"),  # CB.rx 68%, CB.y 30%, T1.rx 0%
        (1.503, -2.84, "hunting, both bogies"),  # W1.y 24%, T1.y 18%, W2.y 15%
        (1.522, -3.09, "hunting, both bogies"),  # W1.y 28%, T1.y 21%, W2.y 18%
        (7.362, -61.35, "car body longitudinal"),  # T1.x 42%, T2.x 42%, CB.x 16%
        (8.046, -19.45, "bogie frame roll, *"),  # T1.rx 49%, T2.rx 46%, T1.y 3%
        (8.057, -19.35, "bogie frame roll, *"),  # T1.rx 57%, T2.rx 37%, T1.y 3%
        (13.151, -13.78, "bogie frame lateral, *"),  # T1.y 54%, T2.y 31%, T1.rx 3%
        (13.156, -13.77, "bogie frame lateral, *"),  # T1.y 74%, T2.y 11%, T1.rx 5%
        (15.374, -96.15, "bogie frame longitudinal, both bogies"),  # T2.x 50%, T1.x 50%, CB.rz 0%
        (22.710, -135.91, "wheelset yaw, *"),  # W3.rz 32%, W4.rz 22%, W1.rz 19%
        (22.710, -135.91, "wheelset yaw, *"),  # W3.rz 30%, W1.rz 22%, W4.rz 20%
        (33.990, -117.45, "wheelset yaw, *"),  # W1.rz 16%, W3.rz 16%, W2.rz 16%
        (34.020, -117.39, "wheelset yaw, *"),  # W1.rz 17%, W2.rz 16%, W3.rz 16%
    ],
    "examples/conventional-yaw-bush.toml": [
        (0.000, -0.60, "car body longitudinal, non-oscillatory"),  # CB.x 100%, T1.x 0%, T2.x 0%
        (0.000, -28.64, "bogie frame longitudinal, both bogies, non-oscillatory"),  # T1.x 50%, T2.x 50%, W1.y 0%
        (0.000, -29.41, "wheelset creep, *, non-oscillatory"),  # W1.y 40%, W3.y 37%, T1.y 4%
        (0.000, -29.92, "wheelset creep, *, non-oscillatory"),  # W1.y 48%, W3.y 29%, T1.y 6%
        (0.095, -315.79, "wheelset lateral, *"),  # W3.y 31%, W1.y 30%, W4.y 20%
        (0.095, -315.79, "wheelset lateral, *"),  # W3.y 31%, W1.y 30%, W4.y 20%
        (0.567, -0.41, "car body lower sway"),  # CB.y 72%, CB.rx 27%, T2.rx 0%
        (0.814, -1.84, "car body yaw"),  # CB.rz 84%, CB.rx 4%, W1.y 3%
        (0.966, -1.37, "car body upper sway"),  # CB.rx 68%, CB.y 30%, T1.rx 0%
        (1.452, -3.14, "hunting, both bogies"),  # W1.y 22%, T1.y 18%, W3.y 15%
        (1.485, -3.40, "hunting, both bogies"),  # W1.y 27%, T1.y 21%, W2.y 18%
        (4.351, -13.59, "car body longitudinal"),  # CB.x 85%, T1.x 8%, T2.x 8%
        (8.046, -19.47, "bogie frame roll, *"),  # T1.rx 48%, T2.rx 46%, T1.y 3%
        (8.057, -19.36, "bogie frame roll, *"),  # T1.rx 54%, T2.rx 40%, T1.y 3%
        (11.474, -104.12, "wheelset yaw/lateral, *"),  # W3.rz 25%, W4.rz 23%, W3.y 16%
        (11.479, -104.06, "wheelset yaw/lateral, *"),  # W3.rz 17%, W4.rz 16%, W1.rz 14%
        (13.176, -14.01, "bogie frame lateral, *"),  # T1.y 45%, T2.y 39%, W1.y 3%
        (13.182, -13.99, "bogie frame lateral, *"),  # T1.y 55%, T2.y 29%, T1.rx 4%
        (22.710, -135.91, "wheelset yaw, *"),  # W3.rz 26%, W1.rz 25%, W4.rz 18%
        (22.710, -135.91, "wheelset yaw, *"),  # W3.rz 26%, W1.rz 26%, W4.rz 17%
        (25.619, -5.68, "bogie frame longitudinal, *"),  # T1.x 50%, T2.x 50%, CB.rx 0%
        (25.809, -6.11, "bogie frame longitudinal, *"),  # T2.x 50%, T1.x 50%, CB.x 0%
        (33.221, -45.69, "bogie frame yaw, *"),  # T2.rz 29%, T1.rz 24%, W3.rz 12%
        (33.223, -45.68, "bogie frame yaw, *"),  # T2.rz 27%, T1.rz 26%, W3.rz 11%
    ],
    "examples/forced-steering.toml": [
        (0.000, -3.79, "car body longitudinal, non-oscillatory"),  # CB.x 55%, L2.ry 11%, L4.ry 11%
        (0.000, -39.50, "wheelset creep, rear bogie, non-oscillatory"),  # W3.y 53%, T2.y 14%, W4.rz 9%
        (0.000, -49.26, "wheelset creep, front bogie, non-oscillatory"),  # W1.y 60%, W1.rz 14%, T1.y 8%
        (0.000, -69.19, "car body longitudinal, non-oscillatory"),  # T1.x 18%, T2.x 18%, CB.x 13%
        (0.000, -198.66, "wheelset creep, front bogie, non-oscillatory"),  # W1.rz 29%, W1.y 29%, T1.rz 16%
        (0.000, -203.41, "wheelset creep, rear bogie, non-oscillatory"),  # W4.rz 28%, W3.y 20%, T2.rz 18%
        (0.118, -316.52, "wheelset lateral, *"),  # W1.y 81%, W2.y 19%, T1.y 0%
        (0.155, -316.08, "wheelset lateral, *"),  # W3.y 70%, W4.y 30%, T2.y 0%
        (0.567, -0.41, "car body lower sway"),  # CB.y 72%, CB.rx 27%, T2.rx 0%
        (0.933, -1.87, "car body yaw"),  # CB.rz 44%, W1.y 16%, T1.y 10%
        (0.963, -1.41, "car body upper sway"),  # CB.rx 66%, CB.y 29%, CB.rz 2%
        (1.369, -1.89, "hunting, front bogie"),  # W1.y 40%, T1.y 28%, W2.y 22%
        (1.587, -4.59, "hunting, rear bogie"),  # W3.y 34%, T2.y 28%, W4.y 26%
        (7.455, -74.47, "car body longitudinal"),  # T1.x 26%, T2.x 26%, L4.ry 10%
        (8.046, -19.45, "bogie frame roll, *"),  # T1.rx 49%, T2.rx 45%, T1.y 3%
        (8.057, -19.35, "bogie frame roll, *"),  # T1.rx 56%, T2.rx 38%, T1.y 3%
        (13.150, -13.78, "bogie frame lateral, *"),  # T1.y 59%, T2.y 26%, T1.rx 4%
        (13.156, -13.78, "bogie frame lateral, *"),  # T1.y 71%, T2.y 14%, T1.rx 5%
        (15.795, -94.40, "bogie frame longitudinal, both bogies"),  # T2.x 35%, T1.x 35%, L4.ry 7%
        (19.932, -135.04, "wheelset yaw, *"),  # W2.rz 35%, W1.rz 31%, L2.ry 10%
        (20.012, -135.16, "wheelset yaw, *"),  # W3.rz 51%, W4.rz 17%, W3.y 10%
        (34.001, -116.42, "wheelset yaw, *"),  # W1.rz 35%, T1.rz 27%, W2.rz 21%
        (34.070, -116.51, "wheelset yaw, *"),  # W4.rz 34%, T2.rz 27%, W3.rz 21%
        (162.869, -0.30, "steering lever pitch, *"),  # L3.ry 25%, L2.ry 25%, L4.ry 25%
        (162.908, -0.40, "steering lever pitch, *"),  # L2.ry 25%, L3.ry 25%, L1.ry 25%
        (163.212, -0.89, "steering lever pitch, *"),  # L4.ry 26%, L3.ry 26%, L2.ry 24%
        (163.213, -0.89, "steering lever pitch, *"),  # L1.ry 26%, L2.ry 26%, L4.ry 24%
    ],
    "examples/forced-steering-yaw-bush.toml": [
        (0.000, -3.39, "car body longitudinal, non-oscillatory"),  # CB.x 55%, L1.ry 11%, L3.ry 11%
        (0.000, -28.59, "wheelset creep, *, non-oscillatory"),  # W3.y 74%, T2.y 11%, W3.rz 4%
        (0.000, -28.87, "bogie frame longitudinal, *, non-oscillatory"),  # T2.x 35%, T1.x 35%, L3.ry 7%
        (0.000, -31.05, "wheelset creep, front bogie, non-oscillatory"),  # W1.y 73%, W2.y 10%, T1.y 6%
        (0.092, -315.56, "wheelset lateral, *"),  # W4.y 51%, W3.y 49%, W4.rz 0%
        (0.103, -315.76, "wheelset lateral, *"),  # W1.y 59%, W2.y 40%, T1.y 0%
        (0.567, -0.41, "car body lower sway"),  # CB.y 72%, CB.rx 27%, T2.rx 0%
        (0.956, -1.86, "car body yaw"),  # CB.rz 41%, W1.y 16%, T1.y 10%
        (0.963, -1.42, "car body upper sway"),  # CB.rx 64%, CB.y 29%, CB.rz 3%
        (1.338, -2.24, "hunting, front bogie"),  # W1.y 39%, T1.y 27%, W2.y 22%
        (1.504, -4.84, "hunting, rear bogie"),  # W3.y 33%, T2.y 28%, W4.y 26%
        (4.372, -12.31, "car body longitudinal"),  # CB.x 57%, L1.ry 8%, L4.ry 8%
        (8.046, -19.47, "bogie frame roll, *"),  # T1.rx 48%, T2.rx 46%, T1.y 3%
        (8.057, -19.36, "bogie frame roll, *"),  # T1.rx 54%, T2.rx 40%, T1.y 3%
        (10.849, -103.11, "wheelset yaw/lateral, rear bogie"),  # W4.rz 36%, W3.rz 19%, W3.y 14%
        (11.717, -104.96, "wheelset yaw/lateral, front bogie"),  # W1.rz 39%, W1.y 23%, W2.rz 15%
        (13.174, -14.00, "bogie frame lateral, *"),  # T1.y 67%, T2.y 18%, W1.y 4%
        (13.181, -13.99, "bogie frame lateral, *"),  # T2.y 51%, T1.y 34%, T2.rx 3%
        (19.934, -135.00, "wheelset yaw, *"),  # W2.rz 36%, W1.rz 31%, L2.ry 10%
        (20.035, -135.05, "wheelset yaw, *"),  # W3.rz 54%, W4.rz 14%, W3.y 11%
        (25.642, -5.56, "bogie frame longitudinal, *"),  # T2.x 35%, T1.x 35%, L3.ry 8%
        (25.851, -6.00, "bogie frame longitudinal, *"),  # T2.x 34%, T1.x 34%, L3.ry 8%
        (33.183, -45.51, "bogie frame yaw, *"),  # T1.rz 43%, W1.rz 24%, W2.rz 13%
        (33.218, -46.06, "bogie frame yaw, *"),  # T2.rz 43%, W4.rz 23%, W3.rz 14%
        (162.879, -0.00, "steering lever pitch, *"),  # L3.ry 25%, L4.ry 25%, L1.ry 25%
        (162.925, -0.00, "steering lever pitch, *"),  # L3.ry 25%, L4.ry 25%, L1.ry 25%
        (163.223, -0.59, "steering lever pitch, *"),  # L4.ry 26%, L3.ry 26%, L2.ry 24%
        (163.224, -0.59, "steering lever pitch, *"),  # L1.ry 26%, L2.ry 26%, L4.ry 24%
    ],
    "examples/manchester.toml": [
        (0.582, -0.83, "car body lower sway"),  # CB.y 80%, CB.rx 19%, T2.rx 1%
        (0.732, -2.82, "car body yaw"),  # CB.rz 100%, T1.y 0%, T2.y 0%
        (1.111, -2.79, "car body upper sway"),  # CB.rx 60%, CB.y 36%, T1.rx 2%
        (1.070, -0.91, "car body bounce"),  # CB.z 95%, T1.z 2%, T2.z 2%
        (1.295, -1.34, "car body pitch"),  # CB.ry 93%, T2.z 3%, T1.z 3%
        (1.397, -144.08, "wheelset lateral, *"),  # W1.y 38%, W3.y 34%, W2.y 12%
        (1.397, -144.08, "wheelset lateral, *"),  # W1.y 37%, W3.y 35%, W2.y 12%
        (3.473, -3.41, "hunting, *"),  # W1.y 26%, T1.y 20%, W2.y 13%
        (3.474, -3.33, "hunting, *"),  # W1.y 21%, W3.y 17%, T1.y 17%
        (7.191, -11.20, "bogie frame bounce, *"),  # T2.z 50%, T1.z 50%, CB.ry 0%
        (7.213, -11.04, "bogie frame bounce, *"),  # T1.z 50%, T2.z 50%, CB.z 0%
        (8.383, -63.87, "wheelset lateral/yaw, *"),  # W1.y 37%, W3.y 16%, T1.y 9%
        (8.385, -63.87, "wheelset lateral/yaw, *"),  # W1.y 29%, W3.y 23%, T1.y 7%
        (9.363, -19.01, "bogie frame roll, *"),  # T1.rx 46%, T2.rx 45%, T1.y 3%
        (9.384, -19.01, "bogie frame roll, *"),  # T1.rx 46%, T2.rx 46%, T1.y 3%
        (13.281, -9.26, "bogie frame pitch, *"),  # T2.ry 50%, T1.ry 50%, W3.z 0%
        (13.281, -9.26, "bogie frame pitch, *"),  # T1.ry 50%, T2.ry 50%, W2.z 0%
        (13.750, -21.61, "bogie frame lateral, *"),  # T2.y 35%, T1.y 35%, W3.y 5%
        (13.763, -21.49, "bogie frame lateral, *"),  # T2.y 35%, T1.y 34%, W3.y 5%
        (33.805, -100.87, "wheelset yaw, *"),  # W1.rz 25%, W3.rz 25%, W2.rz 22%
        (33.805, -100.87, "wheelset yaw, *"),  # W1.rz 25%, W3.rz 25%, W2.rz 22%
        (47.181, -66.82, "wheelset yaw, *"),  # T2.rz 21%, T1.rz 19%, W3.rz 16%
        (47.181, -66.82, "wheelset yaw, *"),  # T2.rz 20%, T1.rz 19%, W3.rz 15%
        (174.887, -3.59, "wheelset roll, *"),  # W1.rx 25%, W2.rx 25%, W3.rx 25%
        (174.887, -3.59, "wheelset roll, *"),  # W4.rx 25%, W3.rx 25%, W1.rx 25%
        (174.891, -3.57, "wheelset roll, *"),  # W2.rx 33%, W1.rx 33%, W3.rx 17%
        (174.891, -3.57, "wheelset roll, *"),  # W2.rx 35%, W1.rx 35%, W3.rx 15%
        (183.204, -2.22, "wheelset vertical, *"),  # W3.z 49%, W4.z 49%, W1.z 1%
        (183.204, -2.22, "wheelset vertical, *"),  # W2.z 49%, W1.z 49%, W4.z 1%
        (183.207, -2.21, "wheelset vertical, *"),  # W3.z 25%, W4.z 25%, W2.z 25%
        (183.207, -2.21, "wheelset vertical, *"),  # W1.z 25%, W2.z 25%, W4.z 25%
    ],
    "examples/manchester-s1002.toml": [
        (0.000, -62.37, "wheelset creep, *, non-oscillatory"),  # W1.y 55%, W3.y 14%, T1.y 9%
        (0.000, -62.39, "wheelset creep, *, non-oscillatory"),  # W1.y 43%, W3.y 27%, T1.y 7%
        (0.000, -119.67, "wheelset creep, *, non-oscillatory"),  # W1.y 37%, W3.y 28%, W1.rz 6%
        (0.000, -119.68, "wheelset creep, *, non-oscillatory"),  # W1.y 45%, W3.y 20%, W1.rz 7%
        (0.582, -0.83, "car body lower sway"),  # CB.y 80%, CB.rx 19%, T2.rx 1%
        (0.731, -2.82, "car body yaw"),  # CB.rz 100%, T1.y 0%, T2.y 0%
        (0.969, -168.28, "wheelset lateral, *"),  # W1.y 47%, W3.y 38%, W2.y 5%
        (0.970, -168.28, "wheelset lateral, *"),  # W1.y 44%, W3.y 41%, W2.y 5%
        (1.111, -2.77, "car body upper sway"),  # CB.rx 61%, CB.y 36%, T1.rx 2%
        (1.070, -0.91, "car body bounce"),  # CB.z 95%, T2.z 2%, T1.z 2%
        (1.295, -1.34, "car body pitch"),  # CB.ry 93%, T1.z 3%, T2.z 3%
        (4.440, -4.56, "hunting, *"),  # W1.y 20%, W3.y 17%, T1.y 17%
        (4.441, -4.63, "hunting, *"),  # W1.y 23%, T1.y 19%, W3.y 14%
        (7.191, -11.20, "bogie frame bounce, *"),  # T1.z 50%, T2.z 50%, CB.ry 0%
        (7.213, -11.04, "bogie frame bounce, *"),  # T2.z 50%, T1.z 50%, CB.z 0%
        (9.343, -19.04, "bogie frame roll, *"),  # T1.rx 46%, T2.rx 45%, T1.y 3%
        (9.365, -19.03, "bogie frame roll, *"),  # T1.rx 46%, T2.rx 45%, T1.y 3%
        (13.281, -9.26, "bogie frame pitch, *"),  # T1.ry 50%, T2.ry 50%, W1.z 0%
        (13.281, -9.26, "bogie frame pitch, *"),  # T2.ry 50%, T1.ry 50%, W3.z 0%
        (13.535, -20.96, "bogie frame lateral, *"),  # T2.y 36%, T1.y 36%, T2.rx 5%
        (13.550, -20.83, "bogie frame lateral, *"),  # T2.y 36%, T1.y 35%, T2.rx 5%
        (31.006, -129.50, "wheelset yaw, *"),  # W1.rz 24%, W3.rz 24%, W2.rz 21%
        (31.006, -129.50, "wheelset yaw, *"),  # W1.rz 24%, W3.rz 24%, W2.rz 21%
        (45.036, -75.71, "bogie frame yaw, *"),  # T1.rz 22%, T2.rz 20%, W1.rz 15%
        (45.036, -75.71, "bogie frame yaw, *"),  # T1.rz 22%, T2.rz 21%, W1.rz 15%
        (174.682, -53.79, "wheelset roll, *"),  # W4.rx 25%, W3.rx 25%, W1.rx 25%
        (174.682, -53.79, "wheelset roll, *"),  # W4.rx 25%, W2.rx 25%, W3.rx 25%
        (174.678, -53.81, "wheelset roll, *"),  # W3.rx 50%, W4.rx 50%, W2.rx 0%
        (174.678, -53.81, "wheelset roll, *"),  # W2.rx 49%, W1.rx 49%, W4.rx 1%
        (182.980, -57.37, "wheelset vertical, *"),  # W2.z 48%, W1.z 48%, W4.z 2%
        (182.980, -57.37, "wheelset vertical, *"),  # W3.z 48%, W4.z 48%, W1.z 2%
        (182.977, -57.38, "wheelset vertical, *"),  # W1.z 25%, W2.z 25%, W4.z 25%
        (182.977, -57.38, "wheelset vertical, *"),  # W4.z 25%, W3.z 25%, W1.z 25%
    ],
    "tests/data/coach-series-dampers.toml": [
        (0.000, -29.83, "car body pitch, non-oscillatory"),  # T1.ry 43%, T2.ry 43%, CB.ry 14%
        (0.000, -30.45, "bogie frame pitch, both bogies, non-oscillatory"),  # T2.ry 50%, T1.ry 50%, W3.z 0%
        (0.000, -34.16, "wheelset creep, *, non-oscillatory"),  # W4.y 34%, W2.y 26%, W1.y 20%
        (0.000, -34.64, "wheelset creep, *, non-oscillatory"),  # W4.y 38%, W3.y 26%, W2.y 21%
        (0.000, -78.87, "wheelset creep, *, non-oscillatory"),  # W3.y 37%, W1.y 26%, W4.y 14%
        (0.000, -80.07, "wheelset creep, *, non-oscillatory"),  # W3.y 54%, W4.y 19%, W1.y 10%
        (0.591, -0.70, "car body lower sway"),  # CB.y 78%, CB.rx 21%, T2.rx 1%
        (0.710, -3.49, "car body yaw"),  # CB.rz 97%, CB.y 1%, T1.y 1%
        (1.101, -3.68, "car body upper sway"),  # CB.rx 55%, CB.y 41%, T1.rx 1%
        (1.070, -0.91, "car body bounce"),  # CB.z 95%, T1.z 2%, T2.z 2%
        (1.121, -142.08, "wheelset lateral, *"),  # W3.y 43%, W1.y 31%, W4.y 14%
        (1.123, -142.10, "wheelset lateral, *"),  # W3.y 41%, W1.y 33%, W4.y 13%
        (1.300, -1.64, "car body pitch"),  # CB.ry 93%, T2.z 3%, T1.z 3%
        (2.667, -3.62, "hunting, both bogies"),  # W1.y 20%, W3.y 17%, T1.y 17%
        (2.713, -4.17, "hunting, both bogies"),  # W1.y 21%, T1.y 17%, W3.y 16%
        (7.190, -11.20, "bogie frame bounce, *"),  # T2.z 50%, T1.z 50%, CB.ry 0%
        (7.213, -11.04, "bogie frame bounce, *"),  # T2.z 50%, T1.z 50%, CB.z 0%
        (9.524, -16.63, "bogie frame roll, *"),  # T2.rx 48%, T1.rx 46%, T2.y 3%
        (9.537, -16.58, "bogie frame roll, *"),  # T2.rx 50%, T1.rx 44%, T2.y 3%
        (12.223, -63.29, "wheelset lateral/yaw, *"),  # W1.y 21%, W3.y 21%, W1.rz 8%
        (12.239, -63.17, "wheelset lateral/yaw, *"),  # W3.y 21%, W1.y 21%, W1.rz 8%
        (13.876, -10.70, "bogie frame pitch, *"),  # T2.ry 50%, T1.ry 50%, W4.z 0%
        (13.877, -10.71, "bogie frame pitch, *"),  # T1.ry 50%, T2.ry 50%, CB.ry 0%
        (14.930, -18.52, "bogie frame lateral, *"),  # T2.y 43%, T1.y 35%, W3.y 6%
        (14.939, -18.69, "bogie frame lateral, *"),  # T2.y 40%, T1.y 37%, W3.y 5%
        (33.805, -100.87, "wheelset yaw, *"),  # W3.rz 25%, W1.rz 25%, W4.rz 22%
        (33.805, -100.87, "wheelset yaw, *"),  # W3.rz 25%, W1.rz 25%, W4.rz 22%
        (48.059, -64.01, "bogie frame yaw, *"),  # T1.rz 22%, T2.rz 21%, W1.rz 15%
        (48.059, -64.01, "bogie frame yaw, *"),  # T1.rz 22%, T2.rz 21%, W1.rz 14%
        (174.887, -3.59, "wheelset roll, *"),  # W2.rx 25%, W1.rx 25%, W4.rx 25%
        (174.887, -3.59, "wheelset roll, *"),  # W2.rx 25%, W4.rx 25%, W3.rx 25%
        (174.891, -3.57, "wheelset roll, *"),  # W1.rx 38%, W2.rx 38%, W4.rx 12%
        (174.891, -3.57, "wheelset roll, *"),  # W3.rx 41%, W4.rx 41%, W2.rx 9%
        (183.204, -2.22, "wheelset vertical, *"),  # W4.z 25%, W3.z 25%, W1.z 25%
        (183.204, -2.22, "wheelset vertical, *"),  # W1.z 25%, W2.z 25%, W3.z 25%
        (183.207, -2.21, "wheelset vertical, *"),  # W4.z 25%, W3.z 25%, W2.z 25%
        (183.207, -2.21, "wheelset vertical, *"),  # W2.z 25%, W1.z 25%, W3.z 25%
    ],
}


def _matches(modes, expected):
    """Pair every expected row with one mode (eigenvalue within 0.5 %, name matching)."""
    left = list(modes)
    wrong = []
    for frequency, real, name in expected:
        target = complex(real, 2 * np.pi * frequency)
        near = [m for m in left if abs(m.eigenvalue - target) <= 5e-3 * abs(target) + 0.02]
        hit = next((m for m in near if fnmatch.fnmatchcase(m.kind, name)), None)
        if hit is None:
            wrong.append((frequency, real, name, [m.kind for m in near]))
        else:
            left.remove(hit)
    return wrong, left


@pytest.mark.slow
@pytest.mark.parametrize("path", sorted(MODES))
def test_every_mode_of_the_bundled_vehicles_has_its_hand_given_name(path):
    modes = eigen_analysis(vehicle_model(load_model(ROOT / path))).modes
    wrong, unmatched = _matches(modes, MODES[path])
    assert not wrong, wrong
    assert not unmatched, [(m.frequency_hz, m.real, m.kind) for m in unmatched]


def test_series_strokes_are_never_dominant_and_are_shown_against_their_element():
    modes = eigen_analysis(vehicle_model(load_model(ROOT / "tests/data/coach-series-dampers.toml"))).modes
    assert all(not dof.endswith(".stroke") for mode in modes for dof, _ in mode.dominant)
    assert all("stroke" not in mode.kind and "stroke" not in mode.describe() for mode in modes)
    sway = next(m for m in modes if m.kind == "car body lower sway")
    # the lateral dampers dissipate most of the car body's sway; the yaw dampers nothing
    shares = dict(sway.series)
    assert shares["T1_latdamp"] + shares["T2_latdamp"] > 0.8
    assert shares["T1_yawL"] < 0.01
    assert "series dampers T" in sway.describe()
    assert sum(shares.values()) <= 1 + 1e-12


def test_a_model_without_rail_data_is_named_by_body():
    model = with_values(read_classic(ROOT / "examples/lever.exp"), {
        "lLU": 0.3, "lLL": 0.06, "kLU": 1e6, "kLL": 5e6, "b": 0.5, "J1": 10, "J2": 0.5, "m": 20, "c": 1000,
        "kinf": 1e9})
    kinds = sorted(m.kind for m in eigen_analysis(vehicle_model(model)).modes)
    assert kinds == ["B1 yaw", "B2 pitch"]


CHAIN = """
[parameters]
m = 2.0
k = 50.0

[bodies.A]
mass = "m"
dofs = ["x"]

[bodies.B]
mass = "m"
dofs = ["x"]

[grounds.G]

[points]
PA = { body = "A" }
PB = { body = "B" }
PG = { body = "G" }

[elements]
ground = { from = "PA", to = "PG", direction = "x", stiffness = "k" }
link = { from = "PA", to = "PB", direction = "x", stiffness = "k" }
"""


def test_kinetic_energy_of_a_two_mass_chain_is_split_as_its_closed_form():
    """Ground-k-m-k-m: the modes are (1, phi) with phi = (1 +- sqrt 5) / 2, so the kinetic
    shares are 1 / (1 + phi^2) and phi^2 / (1 + phi^2), and T / V = 1 (undamped)."""
    vehicle = vehicle_model(parse_toml_model(CHAIN, "chain.toml"))
    values, vectors = np.linalg.eig(vehicle.state_matrix(1.0))
    golden = {(1 + 5**0.5) / 2, (1 - 5**0.5) / 2}
    seen = set()
    for k in np.flatnonzero(values.imag > 0):
        phi = vectors[:2, k]
        energy = mode_energy(phi, values[k], vehicle.dofs, vehicle.mass, vehicle.damping_base, vehicle.stiffness)
        ratio = float(np.real(phi[1] / phi[0]))
        expected = min(golden, key=lambda g: abs(g - ratio))
        seen.add(expected)
        assert energy.kinetic[("A", "x")] == pytest.approx(1 / (1 + expected**2), rel=1e-12)
        assert energy.kinetic[("B", "x")] == pytest.approx(expected**2 / (1 + expected**2), rel=1e-12)
        assert energy.kinetic_to_strain == pytest.approx(1.0, rel=1e-12)
    assert seen == golden


def test_kinematic_frequency_is_klingels():
    # v / (2 pi) sqrt(lambda / (r0 b)) by hand: 55 / 6.2832 * sqrt(0.15 / 0.345) = 5.7719 Hz
    assert kinematic_frequency(55.0, 0.15, 0.46, 0.75) == pytest.approx(5.77190, abs=1e-5)
    assert np.isnan(kinematic_frequency(0.0, 0.15, 0.46, 0.75))


def test_sway_centres_lie_below_and_above_the_centre_of_gravity():
    """Lower sway rolls about a line below the car body's centre of gravity, upper sway above."""
    vehicle = vehicle_model(load_model(ROOT / "examples/manchester.toml"))
    values, vectors = np.linalg.eig(vehicle.state_matrix(vehicle.speed))
    heights = {}
    for k in np.flatnonzero(values.imag > 0):
        energy = mode_energy(vectors[:vehicle.n, k], values[k], vehicle.dofs, vehicle.mass,
                             vehicle.damping(vehicle.speed), vehicle.stiffness)
        body = sum(s for (b, _), s in energy.kinetic.items() if b == "CB")
        if body > 0.9 and energy.kinetic.get(("CB", "rx"), 0) > 0.1:
            heights[round(values[k].imag / (2 * np.pi), 2)] = energy.roll_centre["CB"]
    assert sorted(heights) == [0.58, 1.11]
    assert heights[0.58] < 0 < heights[1.11]
