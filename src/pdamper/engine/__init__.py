"""From a case to the kernels and back: :mod:`.build` turns a :class:`~pdamper.params.Case` into
the kernels' bundles; :mod:`.steppers` drives an integrator over a span of time (growing the
lists when they overflow, turning a failed step into a clear error). :class:`pdamper.Simulation`
composes them."""
