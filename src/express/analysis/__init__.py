"""Analyses: state space, curving simulation, frequency response, stability."""
