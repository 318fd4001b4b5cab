"""Measurements in: the formats.md measurement CSV and per-axis component tables.
"""
