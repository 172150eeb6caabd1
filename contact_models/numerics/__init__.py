"""Numerics both packages use: ``contact_models`` and ``hbm`` import them from here.

- :mod:`~contact_models.numerics.checks`: input checks that raise ``ValueError`` naming the
  parameter and the value it got.
- :mod:`~contact_models.numerics.roots`: Brent's method on a bracket (scipy's algorithm, without
  importing ``scipy.optimize``).
- :mod:`~contact_models.numerics.masing`: alternating frequency-time (AFT) transforms and the
  periodic state of a Masing (rate-independent hysteretic) element.
- :mod:`~contact_models.numerics.jenkins`: the Jenkins element's harmonics and their Jacobian in
  closed form (no samples).
- :mod:`~contact_models.numerics.genalpha` and :mod:`~contact_models.numerics.stepping`: the
  generalized-alpha integrator and the discretised bar's return map, for time-domain references.
"""
