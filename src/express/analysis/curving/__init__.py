"""Curving: the wheel/rail quantities engineers sign a vehicle off with, the steady state
of a vehicle in a constant curve, and the EN 14363 running-safety assessment.

* :mod:`~express.analysis.curving.outputs`: per wheel, per wheelset and per vehicle
  quantities (Q, Y, Y/Q, ΣY, angle of attack, ΔQ/Q0) with their names and units, shared
  by the steady state and the time march;
* :mod:`~express.analysis.curving.measure`: those quantities from vehicle states on a
  track (contact tables or the dead-band model; quasi-static wheel loads);
* :mod:`~express.analysis.curving.steady`: the steady state in a constant curve, solved
  directly from the equations the time march integrates;
* :mod:`~express.analysis.curving.assessment`: the EN 14363 running-safety quantities
  of a run or a steady state against their limits (``docs/curving.md``).
"""
