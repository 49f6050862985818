"""The type stubs (tmc/__init__.pyi, tmc/_tmc.pyi) say what runs: mypy's
stubtest compares every signature and exported name with the imported
package. The extension's stub lacked the series and segment arguments of
extract, extract_to and info, and neither stub had __all__."""

from __future__ import annotations

import subprocess
import sys

import pytest

pytest.importorskip("mypy", reason="mypy (for mypy.stubtest) is not installed")


def test_stubs_match_the_package(tmp_path):
    # Run from an empty directory: from python/ (or the repository root,
    # whose python/ is no package) `import tmc` would find the source
    # package without its compiled _tmc and report every name of the
    # extension missing; the installed package (or maturin develop's
    # editable one) is what is checked.
    result = subprocess.run(
        [sys.executable, "-m", "mypy.stubtest", "tmc"],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert result.returncode == 0, result.stdout + result.stderr
