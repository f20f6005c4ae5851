"""Training losses of the generators, as pure jittable functions."""
