"""Calibration: finding material parameters from lab targets, as ``hopperflow calibrate``."""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any, Dict, List, Optional, Tuple

from . import _native
from ._progress import ProgressArg, StudyProgress, _receiver
from ._tables import PathLike, Table, read_table


class Calibration:
    """A calibration folder: calibration.json (the estimate and each round's fits), runs.csv
    (every run) and rounds/round-NN/ (each round's study)."""

    def __init__(self, path: PathLike) -> None:
        self.path = Path(path)

    @property
    def record(self) -> Dict[str, Any]:
        """calibration.json as a dict (docs/user-guide.md, "Calibration")."""
        with open(self.path / "calibration.json", encoding="utf-8") as f:
            record: Dict[str, Any] = json.load(f)
        return record

    @property
    def estimate(self) -> Dict[str, Tuple[float, float]]:
        """Each parameter's case key: (value, one-sigma standard error), in the key's unit."""
        return {e["key"]: (e["value"], e["standard_error"]) for e in self.record["estimate"]}

    @property
    def converged(self) -> bool:
        """Whether the last round's estimate moved less than its standard error."""
        return bool(self.record["converged"])

    @property
    def targets_met(self) -> bool:
        """Whether every target is met at the estimate, within twice its combined error."""
        return bool(self.record["targets_met"])

    @property
    def rounds(self) -> List[Dict[str, Any]]:
        """Each round's region, runs, estimate and fitted surfaces."""
        rounds: List[Dict[str, Any]] = self.record["rounds"]
        return rounds

    @property
    def runs(self) -> Table:
        """runs.csv: one row per run (a DataFrame, or a dict of numpy arrays)."""
        return read_table(self.path / "runs.csv")

    def __repr__(self) -> str:
        shown = ", ".join(f"{k} = {v:.4g} ± {s:.2g}" for k, (v, s) in self.estimate.items())
        return f"Calibration({str(self.path)!r}, {shown})"


def calibrate(
    file: PathLike,
    out: Optional[PathLike] = None,
    jobs: Optional[int] = None,
    progress: ProgressArg[StudyProgress] = True,
) -> Calibration:
    """Runs (or continues) a calibration file, as ``hopperflow calibrate FILE``.

    ``out`` defaults to ``calibration-<file stem>``; an existing calibration folder of the
    same file is continued, one of another is refused (ValueError). ``jobs`` is the number
    of runs at once (default one per core). A bad calibration file or test case raises
    CaseError naming the key, before anything runs. ``progress`` is True, False or a
    callable taking a ``StudyProgress`` (runs of the current round). Ctrl-C checkpoints the
    running cases and raises KeyboardInterrupt; calling again continues.
    """
    file = os.fspath(file)
    if out is None:
        out = f"calibration-{Path(file).stem}"
    receive, bar = _receiver(progress, f"calibrate {file}")

    def report(done: int, total: int, line: str) -> None:
        assert receive is not None
        fraction = done / total if total else 1.0
        receive(StudyProgress(fraction, f"{done}/{total} runs; {line}", done, total))

    try:
        _native.run_calibration_file(
            file,
            os.fspath(out),
            jobs=0 if jobs is None else jobs,
            progress=None if receive is None else report,
        )
    finally:
        if bar is not None:
            bar.close()
    return Calibration(out)


def load_calibration(path: PathLike) -> Calibration:
    """A calibration folder (one with calibration.json)."""
    path = Path(path)
    if not (path / "calibration.json").is_file():
        raise FileNotFoundError(f"{path}: no calibration.json; not a calibration folder")
    return Calibration(path)
