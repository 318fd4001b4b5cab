"""The numeric core: kinematic chains, component errors, volumetric error, identification,
ISO 230 evaluation, compensation and error maps. Pure and synchronous: no I/O but the
explicit readers and writers, no asyncio.
"""
