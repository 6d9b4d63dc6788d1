"""The modes of the linear vehicle: eigenvalues and mode shapes, their energies and
their names.

- :mod:`~express.analysis.modes.modes`: the modes at a speed, their frequencies, damping
  and shapes (:class:`~express.analysis.modes.modes.EigenResult`);
- :mod:`~express.analysis.modes.mode_energies`: the participation and energies of many
  modes at once, summed by body, direction and role;
- :mod:`~express.analysis.modes.mode_names`: a mode's name from its energy.
"""
