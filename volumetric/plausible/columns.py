"""Column names and option names that carry their unit (``x_mm``, ``T_spindle_C``,
``EAX_urad``): a header that names another unit (``x_in``, ``T_spindle_F``,
``EAX_arcsec``, ``time_ms``) says its slip itself, where the numbers alone cannot
(31.5 in is a plausible 31.5 mm, 4 arcsec a plausible 4 µrad).
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Mapping

__all__ = ["OTHER_UNITS", "unit_column_problem"]

# per unit the format uses, the units people write instead: (their name, how to convert)
OTHER_UNITS: Mapping[str, Mapping[str, str]] = {
    "mm": {"um": "µm: divide by 1000", "µm": "µm: divide by 1000", "m": "metres: multiply "
           "by 1000", "cm": "centimetres: multiply by 10", "in": "inches: multiply by 25.4",
           "inch": "inches: multiply by 25.4", "nm": "nm: divide by 1e6"},
    "um": {"mm": "mm: multiply by 1000", "nm": "nm: divide by 1000", "m": "metres: "
           "multiply by 1e6", "in": "inches: multiply by 25 400", "uin": "µin: multiply "
           "by 0.0254", "µin": "µin: multiply by 0.0254"},
    "urad": {"arcsec": "arcseconds: multiply by 4.848", "asec": "arcseconds: multiply by "
             "4.848", "mrad": "mrad: multiply by 1000", "rad": "radians: multiply by 1e6",
             "deg": "degrees: multiply by 17 453", "nrad": "nrad: divide by 1000",
             "mmm": "mm/m: multiply by 1000", "umm": "µm/m: the same number (1 µm/m = 1 "
             "µrad)"},
    "deg": {"rad": "radians: multiply by 57.296", "arcsec": "arcseconds: divide by 3600",
            "grad": "gon: multiply by 0.9", "gon": "gon: multiply by 0.9"},
    "s": {"ms": "milliseconds: divide by 1000", "us": "microseconds: divide by 1e6",
          "min": "minutes: multiply by 60", "h": "hours: multiply by 3600"},
    "C": {"F": "°F: °C = (°F - 32) / 1.8", "K": "kelvin: subtract 273.15",
          "degF": "°F: °C = (°F - 32) / 1.8", "degC": "°C already: name it _C"},
}
_NAMES = {"mm": "mm", "um": "µm", "urad": "µrad", "deg": "degrees", "s": "seconds",
          "C": "°C"}
_T = re.compile(r"^T_(.+)_([A-Za-z]+)$")


def unit_column_problem(header: Iterable[str], wanted: Mapping[str, str]) -> str | None:
    """The first column that names another unit than the format's, or None.

    Parameters
    ----------
    header : iterable of str
        The file's column names.
    wanted : mapping of str to str
        The format's columns by stem and unit (``{"x": "mm", "time": "s", "value": "um",
        "T": "C"}``; ``"T"`` stands for every ``T_<sensor>_<unit>``). A bare column the
        format names without a unit (``value``) is matched as ``value_<unit>``.
    """
    cells = [c.strip() for c in header]
    present = set(cells)
    for col in cells:
        stem, unit = _split(col)
        if stem is None or unit is None:
            continue
        ours = wanted.get("T" if col.startswith("T_") and "T" in wanted else stem)
        if ours == "um" and stem == "value" and unit in OTHER_UNITS["urad"]:
            ours = "urad"  # the value of an angle reading
        if ours is None or unit == ours or unit not in OTHER_UNITS.get(ours, {}):
            continue
        good = col[: -len(unit)] + ours if stem != "value" else "value"
        if good in present:
            continue  # both given: the other is an extra column, kept and ignored
        how = OTHER_UNITS[ours][unit]
        return (f"column {col!r} is in {how.split(':')[0]}; the format wants {good!r} in "
                f"{_NAMES[ours]} ({how.split(': ', 1)[1]})")
    return None


def _split(col: str) -> tuple[str | None, str | None]:
    m = _T.match(col)
    if m:
        return "T", m.group(2)
    stem, sep, unit = col.rpartition("_")
    return (stem, unit) if sep and stem else (None, None)
