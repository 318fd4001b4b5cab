"""From a model to what a controller applies: the weighted corrections solver and the maps.
"""
