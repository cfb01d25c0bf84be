"""The integration engine of the nonlinear model: the step policy and its accuracy rule,
the compiled RK4 ensemble kernel, one-period maps, stability guards, coordinates, and the
adaptive reference integrator. It stands on ``model/`` (and ``errors``, ``units``) only;
the analyses above it (response, bifurcation, regime maps) call it.

Modules, from the bottom up:

* :mod:`.systems`: the state at rest, the forcing period, the structure an ensemble
  shares, the law discontinuities;
* :mod:`.coordinates`: rigid motion removed (:func:`~.coordinates.to_system`), static
  states, paper 004's dimensionless form;
* :mod:`.limits`: the step limits and the default accuracy, plain numbers;
* :mod:`.steps`: the stability-based count and the :class:`~.steps.Steps` policy that
  checks a run's step arguments;
* :mod:`.guards`: the linear stability check, state bounds, divergence messages, random
  starts;
* :mod:`.prepare`: an ensemble stacked for the kernel (:class:`~.prepare.Prepared`);
* :mod:`.kernel_laws`, :mod:`.kernel`: the compiled laws and RK4 ensemble kernel;
* :mod:`.accuracy`: the step count that meets a target error;
* :mod:`.lyapunov`, :mod:`.maps`, :mod:`.ensemble`: Lyapunov exponents, the one-period
  maps of drives in contact, and :func:`~.ensemble.ensemble`, the run itself;
* :mod:`.reference`: the event-driven DOP853 reference integrator.
"""
