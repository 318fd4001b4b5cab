"""The numeric core, pure and synchronous (no I/O but explicit readers and writers, no asyncio).

The flow runs one way, a sub-package per step::

    model/       machine chains, component errors, exact and first-order volumetric error
    measure/     measurement CSV and component tables in
    identify/    fit the model to measurements
    verify/      ISO 230-2 and ISO 230-6 evaluations
    diagnose/    what the model gets wrong, judged on held-out readings
    compensate/  corrections and the compensation maps a controller applies

A later step imports earlier ones, never the reverse; ``errors.py`` holds the exception
types every step shares.
"""
