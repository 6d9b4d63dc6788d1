"""The time domain: runs of the nonlinear vehicle along a track.

The state space ``x' = A x + e(t) + G z(x, t)`` is marched with the linear part exact
(:mod:`~express.analysis.time.integrator`; large sparse models by
:mod:`~express.analysis.time.sparse_march`), driven by the track's inputs at every station
(:mod:`~express.analysis.time.track_inputs`), with the nonlinear forces of the force
elements (:mod:`express.forces`, chosen for a run by
:mod:`~express.analysis.time.force_elements`); :mod:`~express.analysis.time.simulate` is
the run and its result, :mod:`~express.analysis.time.contact_march` the contact's record,
:mod:`~express.analysis.time.divergence` where a run left the model's range.
"""
