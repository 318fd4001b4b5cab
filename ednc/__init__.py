"""EDNC control center: command line and the end-to-end demo."""

from server.version import __version__

__all__ = ["__version__"]
