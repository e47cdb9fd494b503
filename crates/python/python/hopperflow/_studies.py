"""Studies: running a sweep as ``hopperflow study`` does, and reading a study folder."""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any, Dict, List, Mapping, Optional, Tuple, TypedDict

from . import _native
from ._progress import ProgressArg, StudyProgress, _receiver
from ._runs import Run
from ._tables import PathLike, Table, read_table

class StudyOutcome(TypedDict):
    """What one call of ``study`` did."""

    #: Cases run by this call.
    ran: int
    #: Cases finished by an earlier call and reused.
    reused: int
    #: The cases that failed: (id, reason).
    failed: List[Tuple[str, str]]
    #: The grid points the sweep skips: (id, reasons).
    skipped: List[Tuple[str, str]]


def builtin_sweeps() -> List[str]:
    """The names of the built-in sweeps (``hopperflow study NAME``)."""
    return list(_native.builtin_sweeps())


class Study:
    """A study folder: results.csv, the case folders and the report."""

    def __init__(self, path: PathLike, outcome: Optional[StudyOutcome] = None) -> None:
        self.path = Path(path)
        #: What the call that ran it did (ran, reused, failed, skipped); None when loaded.
        self.outcome = outcome

    @property
    def results(self) -> Table:
        """results.csv: one row per case (a DataFrame, or a dict of numpy arrays)."""
        return read_table(self.path / "results.csv")

    @property
    def cases(self) -> Dict[str, Run]:
        """The finished cases by id, each a Run."""
        root = self.path / "cases"
        if not root.is_dir():
            return {}
        return {p.name: Run(p) for p in sorted(root.iterdir()) if (p / "summary.json").is_file()}

    def report(self) -> Path:
        """Builds the report (``hopperflow report``); returns the path of report.html."""
        files = _native.study_report(os.fspath(self.path))
        return Path(files[1])

    def __repr__(self) -> str:
        return f"Study({str(self.path)!r}, {len(self.cases)} finished cases)"


def study(
    sweep: PathLike,
    out: Optional[PathLike] = None,
    jobs: Optional[int] = None,
    replicas: Optional[int] = None,
    overrides: Optional[Mapping[str, Any]] = None,
    case_threads: int = 1,
    pictures: bool = False,
    progress: ProgressArg[StudyProgress] = True,
    from_bed: Optional[PathLike] = None,
) -> Study:
    """Runs a built-in sweep (``builtin_sweeps()``) or a sweep file, as ``hopperflow study``.

    ``out`` defaults to ``study-<name>``; an existing study folder is resumed. ``jobs`` is
    the number of cases run at once (default one per core), ``replicas`` overrides the
    sweep's, and ``overrides`` sets keys of the base case (``{"protocol.time_limit": 5}``).
    ``from_bed`` starts every case from one bed saved by ``run(..., save_bed=DIR)``, as
    ``hopperflow study --from-bed DIR``: the cases may differ from the bed only in the
    outlet, the discharge rules and [measure]/[output] keys, each takes the bed's seed, and
    replicas are refused (ValueError, before anything is written).
    ``progress`` is True (a bar in Jupyter or on a terminal), False, or a callable
    ``progress(p)`` called with a ``StudyProgress`` when it starts and as cases end; an
    exception it raises stops the study as Ctrl-C does.
    Ctrl-C checkpoints the running cases and raises KeyboardInterrupt; calling again
    continues.
    """
    sweep = os.fspath(sweep)
    if out is None:
        out = f"study-{Path(sweep).stem}"
    # Written as `--set key=value` lines; the sweep reader validates them against its base
    # case, and a bad one raises CaseError naming its key before anything runs.
    sets = _native.overrides_of(overrides) if overrides else []
    receive, bar = _receiver(progress, f"study {sweep}")

    def report(done: int, total: int, line: str) -> None:
        assert receive is not None
        fraction = done / total if total else 1.0
        receive(StudyProgress(fraction, f"{done}/{total} cases; {line}", done, total))

    try:
        outcome = _native.run_study(
            sweep,
            os.fspath(out),
            jobs=0 if jobs is None else jobs,
            replicas=replicas,
            sets=sets,
            case_threads=case_threads,
            pictures=pictures,
            progress=None if receive is None else report,
            from_bed=None if from_bed is None else os.fspath(from_bed),
        )
    finally:
        if bar is not None:
            bar.close()
    return Study(out, outcome)


def load_study(path: PathLike) -> Study:
    """A study folder (one with results.csv)."""
    path = Path(path)
    if not (path / "results.csv").is_file():
        raise FileNotFoundError(f"{path}: no results.csv, so no hopperflow study")
    return Study(path)
