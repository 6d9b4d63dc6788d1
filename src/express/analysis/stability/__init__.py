"""Stability of the vehicle: the linear and the nonlinear critical speed, their options,
results and limit cycles.

- :mod:`~express.analysis.stability.stability`: eigenvalues against speed, the root
  locus, the linear critical speed and its sweep over the conicity;
- :mod:`~express.analysis.stability.critical_options`: every critical-speed search's
  options (``CriticalOptions``);
- :mod:`~express.analysis.stability.critical_result`: the linear critical speed's result
  record (``CriticalSpeed``);
- :mod:`~express.analysis.stability.nonlinear_stability`: the nonlinear critical speed by
  ramp-down, with the bifurcation diagram;
- :mod:`~express.analysis.stability.limit_cycles`: runs at one speed that tell whether a
  limit cycle lives there.
"""
