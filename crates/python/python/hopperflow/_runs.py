"""Runs: running a case as ``hopperflow run`` does, and reading a run folder."""

from __future__ import annotations

import base64
import html
import json
import os
import tempfile
from collections.abc import Mapping
from pathlib import Path
from typing import Any, Dict, Optional, Union

from . import _native
from ._native import Case
from ._progress import ProgressArg, RunProgress, _receiver
from ._tables import RUN_TABLES, PathLike, Table, read_table

#: What ``run`` accepts as its case: a Case, a case file's path, a dict of keys set on the
#: paper's base case (nested or dotted), or None for the paper's base case.
CaseLike = Union[Case, PathLike, Mapping[str, Any], None]


class Run:
    """A run folder: its summary, tables and figures. Tables are read when asked for.

    Each table a run writes is a property (``run.flow``, ``run.wall_forces``, ...; the
    names are the keys of ``RUN_TABLES``); ``run.table(file)`` reads any CSV file of the
    folder. A table the folder does not hold raises FileNotFoundError naming the tables it
    has: which ones a run writes depends on its container and its particles.
    """

    def __init__(self, path: PathLike) -> None:
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

    def table(self, name: str) -> Table:
        """The table of one CSV file of the run, e.g. ``run.table("flow.csv")``."""
        path = self.path / name
        if not path.is_file():
            present = sorted(p.name for p in self.path.glob("*.csv"))
            raise FileNotFoundError(
                f"{path}: this run has no {name} (tables it has: {', '.join(present) or 'none'})"
            )
        return read_table(path)

    @property
    def flow(self) -> Table:
        """flow.csv: W(t), the discharge rate by time bin (time, rate, cumulative_mass)."""
        return self.table(RUN_TABLES["flow"])

    @property
    def profiles(self) -> Table:
        """profiles.csv: velocity and area fraction across the outlet, v(x) and φ(x) (v(r), φ(r) for a circular one)."""
        return self.table(RUN_TABLES["profiles"])

    @property
    def field(self) -> Table:
        """field.csv: a slab's velocity field over its steady window (when that window was found)."""
        return self.table(RUN_TABLES["field"])

    @property
    def crossings(self) -> Table:
        """crossings.csv: every downward crossing of the outlet by a particle centre."""
        return self.table(RUN_TABLES["crossings"])

    @property
    def remaining(self) -> Table:
        """remaining.csv: N(t), the particles left in the container."""
        return self.table(RUN_TABLES["remaining"])

    @property
    def wall_forces(self) -> Table:
        """wall_forces.csv: the mean load the particles exerted on each wall, by window of the run."""
        return self.table(RUN_TABLES["wall_forces"])

    @property
    def wall_pressure(self) -> Table:
        """wall_pressure.csv: a cylindrical silo's wall pressure by zone of height."""
        return self.table(RUN_TABLES["wall_pressure"])

    @property
    def composition(self) -> Table:
        """composition.csv: a mixture's outflow by component, per bin of W(t)."""
        return self.table(RUN_TABLES["composition"])

    @property
    def avalanches(self) -> Table:
        """avalanches.csv: a run that breaks its arches, by avalanche: size in grains and mass, start, end, duration, the arrest before it, and the arch that ended it."""
        return self.table(RUN_TABLES["avalanches"])

    @property
    def residence(self) -> Table:
        """residence.csv: each grain of the bed at the opening, its centre then [m] and its residence time from the opening to its exit [s] (NaN for a grain that stayed)."""
        return self.table(RUN_TABLES["residence"])

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


def _as_case(case: CaseLike) -> Case:
    if case is None:
        return Case.paper()
    if isinstance(case, Case):
        return case
    if isinstance(case, Mapping):
        return Case.from_dict(case)
    if isinstance(case, (str, os.PathLike)):
        return Case.load(os.fspath(case))
    raise TypeError(f"case: expected a Case, a case file path or a dict, not {type(case).__name__}")


def _path(path: Optional[PathLike]) -> Optional[str]:
    return None if path is None else os.fspath(path)


def run(
    case: CaseLike = None,
    out: Optional[PathLike] = None,
    threads: int = 1,
    progress: ProgressArg[RunProgress] = True,
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
    ``progress(p)`` called with a ``RunProgress`` a few times a second; an exception it
    raises stops the run with a checkpoint, as Ctrl-C does.
    """
    if case is None and from_bed is not None:
        # The bed's own resolved case, as `hopperflow run --from-bed DIR` takes it.
        case = Case.from_toml(_native.bed_case_text(os.fspath(from_bed)), f"{os.fspath(from_bed)} (its case)")
    case = _as_case(case)
    if out is None:
        out = tempfile.mkdtemp(prefix="hopperflow-run-")
    if not isinstance(threads, int) or isinstance(threads, bool):
        raise TypeError(f"threads: expected an int, not {type(threads).__name__}")
    receive, bar = _receiver(progress, f"run {os.fspath(out)}")

    def report(phase: str, time: float, particles: int, fraction: float, rate: float) -> None:
        assert receive is not None
        message = f"{phase} t = {time:.3f} s, {particles} particles, {rate:.2e} particle-steps/s"
        receive(RunProgress(fraction, message, phase, time, particles, rate))

    try:
        _native.run_case(
            case,
            os.fspath(out),
            threads=threads,
            resume=resume,
            restart=restart,
            pictures=pictures,
            progress=None if receive is None else report,
            from_bed=_path(from_bed),
            packing=_path(packing),
            save_bed=_path(save_bed),
        )
    finally:
        if bar is not None:
            bar.close()
    return Run(out)


def estimate(
    case: CaseLike = None,
    threads: int = 1,
    from_bed: Optional[PathLike] = None,
    packing: Optional[PathLike] = None,
) -> Dict[str, Any]:
    """What running ``case`` would cost, as ``hopperflow run --estimate --json`` prints it.

    A dict (SI units): ``particles``, ``time_step`` [s], ``threads``; ``simulated``,
    ``particle_steps`` and ``wall_time`` [s], each by part of the protocol (``fill``,
    ``settle``, ``discharge``: the fill estimated, the settling and the discharge at most as
    long as ``protocol.max_settle_time`` and ``protocol.time_limit`` allow); ``likely``, the
    same three likely (the settling until the last poured spheres land, the discharge as the
    mass in the container over its Beverloo rate), with ``likely["discharge"]``: ``law``
    ("beverloo_2d", "beverloo_3d" or None), ``rate`` [kg/s], ``mass`` [kg], ``fraction``,
    ``flowing`` [s] and ``bounded`` (why the bound is kept, or None); ``steps`` (at most),
    ``wall_time_total_s`` and ``likely_wall_time_total_s``, ``speed`` (the engine's ns per
    particle-step, timed on a dense block of the case's spheres on this machine),
    ``peak_memory`` and ``physical_memory`` [bytes], and ``refusal``: why ``hopperflow run``
    would refuse the run as unable to finish (its likely wall time over 30 days, or its
    memory over the machine's), or None. Takes about 0.1-0.3 s.
    """
    if case is None and from_bed is not None:
        case = Case.from_toml(_native.bed_case_text(os.fspath(from_bed)), f"{os.fspath(from_bed)} (its case)")
    case = _as_case(case)
    if not isinstance(threads, int) or isinstance(threads, bool):
        raise TypeError(f"threads: expected an int, not {type(threads).__name__}")
    text = _native.estimate_cost(case, threads=threads, from_bed=_path(from_bed), packing=_path(packing))
    result: Dict[str, Any] = json.loads(text)
    return result


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
