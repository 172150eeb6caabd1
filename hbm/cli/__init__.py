"""The command line: ``python3 -m hbm`` and the ``frictiondamp`` console script.

- :mod:`~hbm.cli.main`: the parser, the subcommands (``default``, ``run``, ``new``, ``models``,
  ``keys``) and ``main``, the entry point;
- :mod:`~hbm.cli.progress`: the progress line drawn while a scene or a study runs;
- :mod:`~hbm.cli.cases`: the built-in default case (a blade with a two-region microslip damper).

It prints; the library does not (``hbm.scenes`` and ``hbm.study`` return lines and results).
"""
