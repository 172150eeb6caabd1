"""Time-domain references of the harmonic balance: the true periodic response, integrated in time.

- :mod:`~hbm.reference.shooting`: the periodic steady response of a structure with Jenkins
  contacts and cubic springs by time integration and shooting (``periodic_response``,
  ``periodic_peak``), with its Floquet multipliers;
- :mod:`~hbm.reference.system`: the structure and its contacts as the integrators' model;
- :mod:`~hbm.reference.piecewise`: the event-driven stick/slip integrator (exact between events);
- :mod:`~hbm.reference.newmark`: the fixed-step Newmark integrator, the event integrator's cross-check;
- :mod:`~hbm.reference.transient`: the blade and the discretised microslip bar integrated together
  from rest to the periodic steady state (``simulate_blade``).

Nothing here uses the balance: these are the independent checks it is measured against.
"""
