"""Analyses of the numerical vehicle: modes, linear and nonlinear critical speed, frequency
response, time simulation (with its divergence check), ride comfort, design studies and figures."""
