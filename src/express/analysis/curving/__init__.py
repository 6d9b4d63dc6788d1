"""Curving: the wheel/rail quantities engineers sign a vehicle off with, the steady state
of a vehicle in a constant curve, and the EN 14363 running-safety assessment.

* :mod:`~express.analysis.curving.outputs`: per wheel, per wheelset and per vehicle
  quantities (Q, Y, Y/Q, ΣY, angle of attack, ΔQ/Q0) with their names and units, shared
  by the steady state and the time march;
"""
