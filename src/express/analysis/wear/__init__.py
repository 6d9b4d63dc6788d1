"""Wheel-wear prediction over mileage: the route, the wear steps with their checkpoint,
and their figures (issue 37, items 3 and 4; ``docs/wear.md``).

Modules
-------
route
    The route file: curves, speeds, cant deficiencies and their shares of the distance.
cases
    The vehicle on a worn profile; the depth one case wears off the profile per metre.
prediction
    The steps, their outputs and the checkpoint that resumes them.
figures
    The quantities against mileage and the profiles.
"""
