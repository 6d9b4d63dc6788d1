"""Assembly of the exact symbolic equations: kinematics, polynomial algebra, the generator of
M, C, K, P, Pd with pinned joints eliminated, series elements, gravity and clearances."""
