"""Calibration from Python: one round of a tiny calibration, its record and runs, and a bad
calibration file refused before anything runs. The loop's recovery of known parameters is
tested in Rust (crates/cli/tests/suite/calibration_loop.rs) and by the documented round trip."""

import subprocess

import pytest

import hopperflow as hf
from conftest import TINY

# The tiny hopper cut further for a calibration's five runs: 150 spheres through a 24 mm
# outlet (8 d: no arch), 0.3 s of discharge at most, no plots.
SMALL = """version = 1
seed = 11
[geometry]
width = 0.05
height = 0.1
outlet_width = 0.024
[particles]
count = 150
diameter = 0.003
[protocol]
settle_kinetic_energy = 1.0e-8
max_settle_time = 0.15
fill_bottom = 0.05
clog_timeout = 0.1
time_limit = 0.3
[output]
checkpoint_interval = 0.0
vtu_interval = 0.0
plots = false
"""

CALIBRATION = """version = 1
name = "tiny"
replicates = 1
max_rounds = 1
[[parameters]]
key = "contact.friction"
min = 0.2
max = 0.8
[[targets]]
case = "{case}"
measure = "discharge_rate"
value = 0.02
uncertainty = 0.002
"""


def test_a_calibration_round_writes_its_record_and_every_run(tmp_path, cli):
    case = tmp_path / "small.toml"
    case.write_text(SMALL)
    file = tmp_path / "cal.toml"
    file.write_text(CALIBRATION.format(case=case.as_posix()))
    reports: list[hf.Progress] = []
    result = hf.calibrate(file, out=tmp_path / "py", jobs=2, progress=reports.append)
    # One parameter: five design points, one run each, all finished with a rate.
    runs = result.runs
    assert len(runs["round"]) == 5 and set(runs["status"]) == {"finished"}
    assert all(w > 0 for w in runs["small:discharge_rate"])
    (key, (value, error)), = result.estimate.items()
    assert key == "contact.friction" and 0.2 <= value <= 0.8 and error > 0
    # One round cannot converge: convergence needs a second round that confirms the first.
    assert not result.converged and len(result.rounds) == 1
    assert reports and isinstance(reports[-1], hf.StudyProgress)
    # The command line continues the same folder: it reruns nothing and writes the same
    # record, bit for bit.
    before = (tmp_path / "py" / "calibration.json").read_bytes()
    again = subprocess.run(
        [str(cli), "calibrate", str(file), "--out", str(tmp_path / "py")],
        capture_output=True,
        text=True,
    )
    assert "5 of 5 runs already finished" in again.stdout, again.stdout + again.stderr
    assert (tmp_path / "py" / "calibration.json").read_bytes() == before
    assert repr(hf.load_calibration(tmp_path / "py")).startswith("Calibration(")


def test_a_bad_calibration_file_raises_case_error_naming_the_key(tmp_path):
    file = tmp_path / "cal.toml"
    file.write_text(CALIBRATION.format(case=TINY.as_posix()).replace("uncertainty = 0.002", "uncertainty = -1.0"))
    with pytest.raises(hf.CaseError) as error:
        hf.calibrate(file, out=tmp_path / "never", progress=False)
    assert error.value.key == "targets[0].uncertainty"
    assert not (tmp_path / "never").exists()
