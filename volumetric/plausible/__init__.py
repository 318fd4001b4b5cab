"""Physical plausibility: one home for the limits of every quantity, used by every way a
number comes in (the ``ednc`` commands, the REST API, the CSV and JSON readers, fleet
files, MQTT and the machines' Telemetry).

A number can be finite and parse and still be nonsense: a reading of 1e9 µm, a
temperature of 293 (kelvin), a travel of 0.8 (metres). Each module below holds one
quantity's limits and the unit slips that explain a number outside them, so that a
refusal says its likely cause ("it looks like kelvin; this is °C"); where real data
could look like a slip (a hot spindle at 72 °C, or 72 °F?), the callers warn on stderr
(or in the log) instead of refusing. The limits are documented in docs/formats.md, "Limits".

=================== ============================== ===========================================
quantity            refused outside                warned about
=================== ============================== ===========================================
linear position,    ±100 000 mm (µm named)         every linear travel <= 2 mm: refused as
travel, pivot                                      metres; one < 10 mm: warned
tool length         0..10 000 mm
rotary position     ±36 000° (100 turns)           a travel within ±2π: radians
displacement        ±10 000 µm (nm named)          largest |value| < 0.05 µm: mm or m
angle               ±100 000 µrad (nrad named)     largest |angle| < 0.05 µrad: ° or rad
temperature         -20..100 °C (K, m°C named)     every value >= 50 °C: °F
campaign time       ±3.2e9 s                       spans > 60 days: milliseconds
reading time stamp  2000-01-01 .. now + 1 day
                    (ms, µs, ns, s named)
output size         1 GiB, before any work
unit in a name      ``x_in``, ``T_s_F``, ``EAX_arcsec``, ``time_ms``: refused with the factor
file kind           UTF-16 read; ``;``/tab separators and decimal commas refused; a CEC,
                    Fanuc, map, model or description file for another: named
=================== ============================== ===========================================
"""

from .angles import ANGLE, ARCSEC_URAD, ROTARY_POSITION
from .displacements import DISPLACEMENT
from .lengths import LINEAR_POSITION, TOOL_LENGTH
from .limit import Implausible, Limit
from .temperatures import TEMPERATURE, check_temperature, temperature_problem
from .times import CAMPAIGN_TIME

__all__ = ["ANGLE", "ARCSEC_URAD", "CAMPAIGN_TIME", "DISPLACEMENT", "LINEAR_POSITION",
           "ROTARY_POSITION", "TEMPERATURE", "TOOL_LENGTH", "Implausible", "Limit",
           "check_temperature", "temperature_problem"]
