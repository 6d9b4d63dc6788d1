"""Rail modules: wheel/rail contact, curves, tracks and the rail inputs (paper 4.2)."""
