"""Drawings of a model and of its mode shapes (plan, side and end views).

:mod:`.geometry` turns a model into numbers (positions of bodies, points, elements) and
moves them by DOF values; :mod:`.views` draws them with the usual symbols;
:mod:`.modes` builds mode-shape figures and animations from an eigen-analysis.
"""
