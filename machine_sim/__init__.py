"""Simulated Fanuc-style and Siemens-style machine tools with a physics the center does not know.

Physics and instruments (offline, synchronous):

* :mod:`~machine_sim.truth`: a random, smooth, realistic true geometry (ISO 230-1 errors);
* :mod:`~machine_sim.effects`: effects outside the rigid model (thermal expansion and
  drift, backlash, ballscrew periodic error, instrument noise), formulas in its docstring;
* :mod:`~machine_sim.thermal`: structure temperatures and lagged, noisy PT100 readings;
* :mod:`~machine_sim.program`: a motion executor (time, positions, last directions);
* :mod:`~machine_sim.testprograms`: laser positioning, straightness, angular, ISO 230-6
  diagonals, rotary positioning and R-tests as programs;
* :mod:`~machine_sim.instruments`: :class:`SimulatedMachine`, the true error and readings;
* :mod:`~machine_sim.campaign`: campaigns to :class:`volumetric.measure.measurement.Measurements`.

Controllers (per cycle, synchronous): :mod:`~machine_sim.lookup` (map interpolation, the
fleet's vectorised ladder), :mod:`~machine_sim.mapstore` (the swap rule),
:mod:`~machine_sim.controller` (what both personalities share), :mod:`~machine_sim.fanuc`
(PMC R memory, EMZPS), :mod:`~machine_sim.siemens` (MD32750, SD43900, MD32760).

Network (asyncio): :mod:`~machine_sim.runtime` (motion, temperatures and controller of a
running machine), :mod:`~machine_sim.link` (the protocol over TCP, MQTT temperatures),
:mod:`~machine_sim.fleet` (fleet files, many machines); ``ednc sim`` drives them.
"""
