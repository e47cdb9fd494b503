"""The quick-start example runs (its small variant) and writes its figures."""

import re
import subprocess
import sys

from conftest import REPO


def test_quickstart_runs_and_writes_its_figures(tmp_path):
    proc = subprocess.run(
        [sys.executable, str(REPO / "examples" / "quickstart.py"), "--small", "--out", str(tmp_path)],
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert proc.returncode == 0, proc.stderr
    for name in ["base.png", "beverloo.png"]:
        # A PNG file, not an empty one.
        assert (tmp_path / name).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    fit = re.search(r"k = (-?[0-9.]+)", proc.stdout)
    assert fit is not None, proc.stdout
    k = float(fit.group(1))
    # Beverloo's k is of order one to two particle diameters for spheres of this size;
    # 0.5..4 only refuses a fit gone wrong (a sign error, a mixed-up unit), not the physics.
    assert 0.5 < k < 4, proc.stdout
