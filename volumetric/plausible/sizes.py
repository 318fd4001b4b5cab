"""Sizes of outputs: what a command would write, estimated and refused before any work.

A command whose options ask for more than :data:`MAX_OUTPUT_BYTES` (a typo of a count,
an extra zero) is refused at once with the estimate, rather than filling the disk after
minutes of work.
"""

from __future__ import annotations

from .limit import Implausible

__all__ = ["MAX_OUTPUT_BYTES", "check_output_size", "human_bytes"]

MAX_OUTPUT_BYTES = 1 << 30
"""1 GiB: far beyond any compensation table, map or campaign a machine needs."""


def human_bytes(n: float) -> str:
    for unit in ("bytes", "kB", "MB", "GB", "TB"):
        if n < 1000 or unit == "TB":
            return f"{n:.0f} {unit}" if unit == "bytes" else f"{n:.3g} {unit}"
        n /= 1000
    return f"{n:.3g} TB"  # pragma: no cover


def check_output_size(estimate: float, what: str, shrink: str,
                      limit: int = MAX_OUTPUT_BYTES) -> None:
    """:class:`Implausible` when ``estimate`` bytes exceed ``limit``.

    Parameters
    ----------
    estimate : float
        Bytes the output would take.
    what : str
        The output, for the message (``"--out tables"``).
    shrink : str
        What to change to make it smaller (``"fewer --points"``).
    """
    if estimate > limit:
        raise Implausible(f"{what} would take about {human_bytes(estimate)}, over the "
                          f"limit of {human_bytes(limit)}; {shrink}")
