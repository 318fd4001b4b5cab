"""Standard evaluations of measured or simulated tests: ISO 230-2 positioning and ISO 230-6
body and face diagonals.
"""
