"""The numerical vehicle: matrices compiled once per model and evaluated at parameter values,
and the state space (state, input and input-rate matrices at a speed)."""
