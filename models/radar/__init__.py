"""The radar's shared vocabulary: conventions (bins, beams, modes, range/Doppler folding),
parameter and port declarations, the unit contract, geometry, antenna pattern and trajectories.
Every other package of :mod:`axir.models` builds on this one; it imports none of them."""
