"""hopperflow from Python: cases, runs, studies and the DEM engine.

    >>> import hopperflow as hf
    >>> case = hf.Case.paper()
    >>> case["geometry.outlet_width"] = 0.045
    >>> run = hf.run(case, out="out/d45")
    >>> run.summary["discharge_rate"], run.flow

The simulation is the Rust core of the ``hopperflow`` command line; a run from Python
writes the same files, with the same bits, as ``hopperflow run``. Tables are pandas
DataFrames when pandas is installed and dicts of numpy arrays otherwise.
"""

from __future__ import annotations

import base64
import csv
import html
import json
import os
import sys
import tempfile
from pathlib import Path
from typing import Any, Callable, Dict, List, Optional, Union

import numpy as np

from ._native import Case, CaseError, RunError, Simulation, __version__
from . import _native

__all__ = [
    "Case",
    "CaseError",
    "RunError",
    "Run",
    "Simulation",
    "Study",
    "load_run",
    "load_study",
    "run",
    "study",
    "builtin_sweeps",
    "read_table",
    "__version__",
]

PathLike = Union[str, "os.PathLike[str]"]

#: The tables of a run, by attribute name: a finished run writes flow.csv, profiles.csv,
#: crossings.csv, remaining.csv (the particles left in the container against time),
#: wall_forces.csv (the mean loads on the walls, by window of the run), field.csv (a slab's,
#: when its steady window was found), wall_pressure.csv (a cylindrical silo's wall pressure
#: by zone of height) and, for a mixture, composition.csv (the outflow by component); asking
#: for a table the run folder does not hold raises FileNotFoundError.
RUN_TABLES = {
    "flow": "flow.csv",
    "profiles": "profiles.csv",
    "field": "field.csv",
    "crossings": "crossings.csv",
    "remaining": "remaining.csv",
    "wall_forces": "wall_forces.csv",
    "wall_pressure": "wall_pressure.csv",
    "composition": "composition.csv",
}


def _pandas():
    """pandas, or None when it is not installed or HOPPERFLOW_NO_PANDAS=1 asks for the
    numpy tables (the tests use it to check both forms)."""
    if os.environ.get("HOPPERFLOW_NO_PANDAS") == "1":
        return None
    try:
        import pandas  # noqa: PLC0415 (optional dependency)
    except ImportError:
        return None
    return pandas


def _column(values: List[str]) -> np.ndarray:
    """A CSV column as float64 where every cell is a number, else as str."""
    try:
        return np.array([float(v) if v != "" else np.nan for v in values], dtype=np.float64)
    except ValueError:
        return np.array(values, dtype=str)


def read_table(path: PathLike):
    """A CSV file of hopperflow as a DataFrame, or a dict of numpy arrays without pandas.

    Numbers are parsed as Python parses them (shortest round-trip text, so the same bits
    as the writer's), in both forms.
    """
    path = Path(path)
    with open(path, newline="", encoding="utf-8") as f:
        rows = list(csv.reader(f))
    if not rows:
        raise ValueError(f"{path}: empty file, expected a header line")
    header, body = rows[0], rows[1:]
    columns = {name: _column([r[i] if i < len(r) else "" for r in body]) for i, name in enumerate(header)}
    pandas = _pandas()
    if pandas is None:
        return columns
    return pandas.DataFrame(columns)


class _Progress:
    """A progress display: an HTML bar updated in place in Jupyter, a line on a terminal's
    stderr, nothing elsewhere (logs of scripts stay clean)."""

    def __init__(self, title: str):
        self.title = title
        self.handle = None
        self.terminal = False
        try:
            from IPython import get_ipython  # noqa: PLC0415

            shell = get_ipython()
            notebook = shell is not None and shell.__class__.__name__ == "ZMQInteractiveShell"
        except ImportError:
            notebook = False
        if notebook:
            from IPython.display import HTML, display  # noqa: PLC0415

            self._html = HTML
            self.handle = display(HTML(self._bar(0.0, "starting")), display_id=True)
        else:
            self.terminal = sys.stderr.isatty()

    def _bar(self, fraction: float, text: str) -> str:
        pct = max(0.0, min(1.0, fraction)) * 100
        return (
            f"<div><b>{html.escape(self.title)}</b> "
            f"<progress value='{pct:.1f}' max='100' style='width:40%'></progress> "
            f"{pct:.0f}% <span style='font-family:monospace'>{html.escape(text)}</span></div>"
        )

    def update(self, fraction: float, text: str) -> None:
        if self.handle is not None:
            self.handle.update(self._html(self._bar(fraction, text)))
        elif self.terminal:
            filled = int(30 * max(0.0, min(1.0, fraction)))
            sys.stderr.write(f"\r{self.title} [{'=' * filled}{' ' * (30 - filled)}] {text}\033[K")
            sys.stderr.flush()

    def close(self) -> None:
        if self.terminal:
            sys.stderr.write("\n")
            sys.stderr.flush()


class Run:
    """A run folder: its summary, tables and figures. Tables are read when first asked for."""

    def __init__(self, path: PathLike):
        self.path = Path(path)
        self._summary: Optional[Dict[str, Any]] = None

    @property
    def summary(self) -> Dict[str, Any]:
        """summary.json as a dict (SI units; docs/user-guide.md describes the run folder and its keys)."""
        if self._summary is None:
            with open(self.path / "summary.json", encoding="utf-8") as f:
                self._summary = json.load(f)
        return self._summary

    @property
    def case(self) -> Case:
        """The resolved case the run ran (its case.toml)."""
        return Case.load(str(self.path / "case.toml"))

    def table(self, name: str):
        """The table of one CSV file of the run, e.g. ``run.table("flow.csv")``."""
        path = self.path / name
        if not path.is_file():
            present = sorted(p.name for p in self.path.glob("*.csv"))
            raise FileNotFoundError(
                f"{path}: this run has no {name} (tables it has: {', '.join(present) or 'none'})"
            )
        return read_table(path)

    def __getattr__(self, name: str):
        # Only the table names: any other missing attribute is an AttributeError as usual.
        if name in RUN_TABLES:
            return self.table(RUN_TABLES[name])
        raise AttributeError(f"{type(self).__name__!r} object has no attribute {name!r}")

    def __dir__(self):
        return sorted(set(super().__dir__()) | set(RUN_TABLES))

    def figure(self, name: str = "flow_rate.png") -> Path:
        """The path of a figure of the run (flow_rate.png, velocity_profile.png, ...)."""
        path = self.path / name
        if not path.is_file():
            raise FileNotFoundError(f"{path}: this run has no {name} (was it run with pictures=False?)")
        return path

    def __repr__(self) -> str:
        try:
            w = self.summary.get("discharge_rate")
            rate = f", W={w * 1e3:.2f} g/s" if isinstance(w, (int, float)) else ""
        except (OSError, ValueError):
            rate = ""
        return f"Run({str(self.path)!r}{rate})"

    def _repr_html_(self) -> str:
        rows = []
        for key, value in self.summary.items():
            if isinstance(value, (dict, list)):
                continue
            shown = f"{value:.6g}" if isinstance(value, float) else str(value)
            rows.append(f"<tr><td>{html.escape(str(key))}</td><td>{html.escape(shown)}</td></tr>")
        figure = ""
        png = self.path / "flow_rate.png"
        if png.is_file():
            data = base64.b64encode(png.read_bytes()).decode("ascii")
            figure = f"<img src='data:image/png;base64,{data}' style='max-width:560px' alt='W(t)'/>"
        return (
            f"<div><b>hopperflow run</b> <code>{html.escape(str(self.path))}</code>"
            "<div style='display:flex;gap:1em;align-items:flex-start'>"
            f"<table>{''.join(rows)}</table>{figure}</div></div>"
        )


def _as_case(case: Union[Case, PathLike, Dict[str, Any], None]) -> Case:
    if case is None:
        return Case.paper()
    if isinstance(case, Case):
        return case
    if isinstance(case, dict):
        return Case.from_dict(case)
    if isinstance(case, (str, os.PathLike)):
        return Case.load(os.fspath(case))
    raise TypeError(f"case: expected a Case, a case file path or a dict, not {type(case).__name__}")


def run(
    case: Union[Case, PathLike, Dict[str, Any], None] = None,
    out: Optional[PathLike] = None,
    threads: int = 1,
    progress: Union[bool, Callable[[str, float, int, float, float], Any]] = True,
    resume: bool = False,
    restart: bool = False,
    pictures: bool = True,
    from_bed: Optional[PathLike] = None,
    packing: Optional[PathLike] = None,
    save_bed: Optional[PathLike] = None,
) -> Run:
    """Runs a case (the paper's base case by default) into ``out`` and returns the Run.

    It is ``hopperflow run CASE --out OUT --threads THREADS``: the same files and bits.
    ``from_bed``, ``packing`` and ``save_bed`` are ``--from-bed``, ``--packing`` and
    ``--save-bed``: start from a bed saved by another run (without ``case``, the bed's own
    case is the base; the case may differ from it only in the outlet, the discharge rules
    and the [measure] and [output] keys), start from a packing file (CSV or VTU), or save
    this run's settled bed. Bad input raises ValueError naming the file, the line or key,
    the value and what is allowed, before anything is written.
    ``out`` defaults to a new temporary folder. A folder that already holds a run is
    refused unless ``resume=True`` (continue its checkpoint, or read back its finished
    summary) or ``restart=True`` (start over). Ctrl-C stops the run after a checkpoint is
    written and raises KeyboardInterrupt; ``resume=True`` continues it bit-identically.
    The GIL is released while the engine runs.

    ``progress`` is True (a bar in Jupyter or on a terminal), False, or a callable
    ``progress(phase, time, particles, fraction, particle_steps_per_second)`` called a few
    times a second; an exception it raises stops the run with a checkpoint, as Ctrl-C does.
    """
    if case is None and from_bed is not None:
        # The bed's own resolved case, as `hopperflow run --from-bed DIR` takes it.
        case = Case.from_toml(_native.bed_case_text(os.fspath(from_bed)), f"{os.fspath(from_bed)} (its case)")
    case = _as_case(case)
    if out is None:
        out = tempfile.mkdtemp(prefix="hopperflow-run-")
    if not isinstance(threads, int) or isinstance(threads, bool):
        raise TypeError(f"threads: expected an int, not {type(threads).__name__}")
    bar = _Progress(f"run {os.fspath(out)}") if progress is True else None

    def report(phase, time, particles, fraction, rate):
        bar.update(fraction, f"{phase} t = {time:.3f} s, {particles} particles, {rate:.2e} particle-steps/s")

    callback = report if bar is not None else (progress if callable(progress) else None)

    try:
        _native.run_case(
            case,
            os.fspath(out),
            threads=threads,
            resume=resume,
            restart=restart,
            pictures=pictures,
            progress=callback,
            from_bed=None if from_bed is None else os.fspath(from_bed),
            packing=None if packing is None else os.fspath(packing),
            save_bed=None if save_bed is None else os.fspath(save_bed),
        )
    finally:
        if bar is not None:
            bar.close()
    return Run(out)


def load_run(path: PathLike) -> Run:
    """A finished run folder (one with summary.json), as ``run`` returns it."""
    path = Path(path)
    if not (path / "summary.json").is_file():
        if (path / "checkpoint.bin").is_file():
            raise FileNotFoundError(
                f"{path} holds an unfinished run (a checkpoint, no summary.json); "
                "hf.run(case, out=path, resume=True) finishes it"
            )
        raise FileNotFoundError(f"{path}: no summary.json, so no finished hopperflow run")
    return Run(path)


def builtin_sweeps() -> List[str]:
    """The names of the built-in sweeps (``hopperflow study NAME``)."""
    return list(_native.builtin_sweeps())


class Study:
    """A study folder: results.csv, the case folders and the report."""

    def __init__(self, path: PathLike, outcome: Optional[Dict[str, Any]] = None):
        self.path = Path(path)
        #: What the call that ran it did (ran, reused, failed, skipped); None when loaded.
        self.outcome = outcome

    @property
    def results(self):
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
    overrides: Optional[Dict[str, Any]] = None,
    case_threads: int = 1,
    pictures: bool = False,
    progress: bool = True,
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
    Ctrl-C checkpoints the running cases and raises KeyboardInterrupt; calling again
    continues.
    """
    sweep = os.fspath(sweep)
    if out is None:
        out = f"study-{Path(sweep).stem}"
    # Written as `--set key=value` lines; the sweep reader validates them against its base
    # case, and a bad one raises CaseError naming its key before anything runs.
    sets = _native.overrides_of(overrides) if overrides else []
    bar = _Progress(f"study {sweep}") if progress else None

    def report(done, total, line):
        bar.update(done / total if total else 1.0, f"{done}/{total} cases; {line}")

    try:
        outcome = _native.run_study(
            sweep,
            os.fspath(out),
            jobs=0 if jobs is None else jobs,
            replicas=replicas,
            sets=sets,
            case_threads=case_threads,
            pictures=pictures,
            progress=report if bar is not None else None,
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
