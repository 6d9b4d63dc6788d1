"""The frequency domain: the vehicle's steady response to track irregularity, frequency
by frequency.

- :mod:`~express.analysis.frequency.frequency`: the frequency response to a sinusoidal
  track irregularity (paper Fig. 10);
- :mod:`~express.analysis.frequency.track_response`: the frequency response to each kind
  of track irregularity;
- :mod:`~express.analysis.frequency.banded`: banded solves of the dynamic stiffness, the
  route of long trains.
"""
