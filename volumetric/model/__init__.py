"""The machine and its errors: kinematic chains (type numbers), ISO 230-1 component errors,
the rigid-body algebra and the exact and first-order volumetric error.
"""
