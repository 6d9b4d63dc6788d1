"""Analyses of the numerical vehicle: modes, linear and nonlinear critical speed, frequency
response, time simulation (with its divergence check), ride comfort, design studies and figures.

One subpackage per subject: :mod:`~express.analysis.modes`, :mod:`~express.analysis.stability`,
:mod:`~express.analysis.frequency`, :mod:`~express.analysis.time`,
:mod:`~express.analysis.curving`, :mod:`~express.analysis.twist`,
:mod:`~express.analysis.ride`, :mod:`~express.analysis.wear`, :mod:`~express.analysis.study`
and :mod:`~express.analysis.plots`; :mod:`~express.analysis.result_data` holds the larger
result records as :class:`xarray.Dataset`.
"""
