"""hopperflow from Python: cases, runs, studies and the DEM engine.

    >>> import hopperflow as hf
    >>> case = hf.Case.paper()
    >>> case["geometry.outlet_width"] = 0.045
    >>> run = hf.run(case, out="out/d45")
    >>> run.summary["discharge_rate"], run.flow

The simulation is the Rust core of the ``hopperflow`` command line; a run from Python
writes the same files, with the same bits, as ``hopperflow run``. Tables are pandas
DataFrames when pandas is installed and dicts of numpy arrays otherwise.

The package is split by job, and this module only gathers its public names: ``_native``
(the Rust extension: cases, the engine, running), ``_tables`` (reading CSV tables),
``_progress`` (what a progress callable receives, the built-in bar), ``_runs`` (``run``,
``estimate`` and ``Run``), ``_studies`` (``study`` and ``Study``) and ``_calibration`` (``calibrate``
and ``Calibration``).
"""

from ._calibration import Calibration, calibrate, load_calibration
from ._native import Case, CaseError, RunError, Simulation, __version__
from ._progress import Progress, RunProgress, StudyProgress
from ._runs import CaseLike, Run, estimate, load_run, run
from ._studies import Study, StudyOutcome, builtin_sweeps, load_study, study
from ._tables import RUN_TABLES, PathLike, Table, read_table

__all__ = [
    "Calibration",
    "Case",
    "CaseError",
    "CaseLike",
    "PathLike",
    "Progress",
    "RUN_TABLES",
    "Run",
    "RunError",
    "RunProgress",
    "Simulation",
    "Study",
    "StudyOutcome",
    "StudyProgress",
    "Table",
    "__version__",
    "builtin_sweeps",
    "calibrate",
    "estimate",
    "load_calibration",
    "load_run",
    "load_study",
    "read_table",
    "run",
    "study",
]
