"""The nonlinear force elements of the time domain: one stage between the state space
(:mod:`express.numeric`) and the analyses.

Every nonlinear force that the time march, the steady-curving solver and the nonlinear
critical speed feed back goes through one interface, :class:`~express.forces.element.ForceElement`:
what it reads of the state, where it acts (its columns of the feedback input matrix
``G`` of ``x' = A x + e(t) + G z(x, t)``), its internal states, its typed parameters (a
NamedTuple whose type selects its compiled law, :func:`~express.forces.law.force_law`),
its linearisation (``dz/dx``) and its outputs with units.  The analyses see only the
stacked set, :class:`~express.forces.element.ForceSet`.

A new kind of element is one module here:

- :mod:`express.forces.bump_stops` — clearance elements (bump stops);
- :mod:`express.forces.deadband` — the paper's dead-band flange spring and creep saturation;
- :mod:`express.forces.contact` — the wheel/rail contact from profile tables, with the
  vertical wheel loads it is pressed by;
- :mod:`express.forces.friction` — friction elements (a pre-slip spring and a slider);
- :mod:`express.forces.characteristic` — nonlinear characteristics (tables and shapes);
- :mod:`express.forces.wheelsets` — where the wheelsets are in the state (shared by the
  two wheel/rail kinds).

How the linear analyses see the nonlinear elements: :mod:`express.forces.linearisation`
(the choice itself :mod:`express.forces.linearisation_choice`, the closed forms
:mod:`express.forces.describing`).
"""
