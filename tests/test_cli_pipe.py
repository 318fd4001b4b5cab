"""Output to a pipe is plain and complete (issue 25: rich wrapped the demo's fleet table at
80 columns when piped, cutting cells to "mac…", "con…")."""

from __future__ import annotations

import io

from ednc.commands.demo import demo_console
from ednc.demo import MachineResult, summary_table


def test_the_fleet_table_is_complete_on_a_pipe() -> None:
    results = [MachineResult(f"machine-with-a-long-name-{k}", "siemens", "w C A X b Y Z t",
                             readings=123_456, fit_rms_um=1.23, effect="thermal_drift",
                             map_kind="tables", map_bytes=12_345, map_worst_um=0.41,
                             before_um=88.1, after_um=1.2) for k in range(6)]
    out = io.StringIO()
    console = demo_console(out)
    console.print(summary_table(results))
    text = out.getvalue()
    assert "…" not in text and "\x1b[" not in text
    for r in results:
        line = next(x for x in text.splitlines() if r.name in x)  # one row, one line
        for cell in (r.controller, r.chain, "123456", "thermal_drift", "12,345", "99 %"):
            assert cell in line, line


def test_a_rule_on_a_pipe_is_its_title() -> None:
    out = io.StringIO()
    demo_console(out).rule("EDNC control center demo")
    assert out.getvalue() == "EDNC control center demo\n"
