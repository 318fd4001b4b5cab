import subprocess
import sys
from pathlib import Path

from ednc import __version__


def test_console_command_prints_version() -> None:
    ednc = Path(sys.executable).parent / "ednc"
    out = subprocess.run([str(ednc), "version"], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == __version__
