"""The integration engine of the nonlinear model: the step policy and its accuracy rule,
the compiled RK4 ensemble kernel, one-period maps, stability guards, coordinates, and the
adaptive reference integrator. It stands on ``model/`` (and ``errors``, ``units``) only;
the analyses above it (response, bifurcation, regime maps) call it."""
