"""From measurements to a model: the design matrix, the fit of component errors and the
thermal (lagged-temperature) refinement.
"""
