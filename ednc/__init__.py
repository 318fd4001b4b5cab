"""EDNC control center: command line and the end-to-end demo."""

__version__ = "0.1.0"
