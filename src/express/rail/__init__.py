"""The rail modules: wheel/rail creep and flange terms, curves and cant (paper 4.2), Hertz and
Kalker contact, profiles, contact geometry, conicity, nonlinear contact forces and tracks."""
