"""The EDNC version, defined once: the ``version`` of ``pyproject.toml``, read from the
installed distribution's metadata.

It lives here, in the lowest layer that reports it (the REST API, the dashboard), so the
server never imports the command line (``ednc``) above it; ``ednc.__version__`` is this
same value.
"""

from __future__ import annotations

from importlib.metadata import PackageNotFoundError, version

try:
    __version__ = version("ednc")
except PackageNotFoundError:  # a source tree used without `pip install -e .`
    __version__ = "0+unknown"
