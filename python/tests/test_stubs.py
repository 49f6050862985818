"""The type stubs (tmc/__init__.pyi, tmc/_tmc.pyi) say what runs: mypy's
stubtest compares every signature and exported name with the imported
package. The extension's stub lacked the series and segment arguments of
extract, extract_to and info, and neither stub had __all__."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

pytest.importorskip("mypy", reason="mypy (for mypy.stubtest) is not installed")


def test_stubs_match_the_package():
    package = Path(__file__).resolve().parents[1]
    result = subprocess.run(
        [sys.executable, "-m", "mypy.stubtest", "tmc"],
        cwd=package,
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert result.returncode == 0, result.stdout + result.stderr
