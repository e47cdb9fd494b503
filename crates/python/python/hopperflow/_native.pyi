"""Type stubs of the Rust extension ``hopperflow._native`` (crates/python/src).

The package re-exports ``Case``, ``CaseError``, ``RunError``, ``Simulation`` and
``__version__``; the functions are the package's own plumbing, called by ``run``,
``study``, ``Study.report`` and ``calibrate``.
"""

import os
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any, Optional, Union

import numpy as np
import numpy.typing as npt

from ._studies import StudyOutcome

__version__: str

#: A path the extension accepts.
_Path = Union[str, "os.PathLike[str]"]
#: One point or vector [x, y, z]: a sequence of three numbers or a numpy array of 3.
_Vec3 = Union[Sequence[float], npt.NDArray[np.floating[Any]]]
#: N points or vectors: a sequence of [x, y, z] or an N×3 numpy array.
_Vec3s = Union[Sequence[Sequence[float]], npt.NDArray[np.floating[Any]]]
_Floats = Union[Sequence[float], npt.NDArray[np.floating[Any]]]
_Ints = Union[Sequence[int], npt.NDArray[np.integer[Any]]]

class CaseError(ValueError):
    """A case or sweep that cannot be used: ``.key``, ``.line``, ``.value`` and ``.message``
    describe the first problem, ``.errors`` lists every one; ``str()`` is the command line's
    text."""

    #: The dotted key of the first problem ("" when it is about the whole file).
    key: Optional[str]
    #: Its line in the file (1-based), None for a value set from Python.
    line: Optional[int]
    column: Optional[int]
    #: The value as the message shows it, None when there is none.
    value: Optional[str]
    message: Optional[str]
    #: The file, "--set" or "python".
    source: Optional[str]
    kind: Optional[str]
    #: Every problem, as dicts with key, line, column, value, message, source, kind and text.
    errors: list[dict[str, Any]]

class RunError(RuntimeError):
    """A run or study that stopped with an error (the engine, a probe, an output file)."""

class Case:
    """A validated hopper case: every change is checked as ``hopperflow run FILE --set
    key=value`` checks it, and a refused change leaves the case as it was."""

    @staticmethod
    def paper() -> Case: ...
    @staticmethod
    def load(path: _Path) -> Case: ...
    @staticmethod
    def from_toml(text: str, name: str = "<string>") -> Case: ...
    @staticmethod
    def from_dict(d: Mapping[str, Any]) -> Case: ...
    def __setitem__(self, key: str, value: Any) -> None: ...
    def __getitem__(self, key: str) -> Any: ...
    def __contains__(self, key: object) -> bool: ...
    def update(self, values: Mapping[str, Any]) -> None: ...
    def check(self) -> Case: ...
    def to_toml(self) -> str: ...
    def to_dict(self) -> dict[str, Any]: ...
    @property
    def overrides(self) -> list[str]: ...
    def copy(self) -> Case: ...
    def __copy__(self) -> Case: ...
    def __deepcopy__(self, memo: Any) -> Case: ...
    def __eq__(self, other: object) -> bool: ...

class Simulation:
    """The DEM engine of a case, stepped from Python; arrays are read-only copies."""

    @staticmethod
    def from_case(case: Case, threads: int = 1) -> Simulation: ...
    @staticmethod
    def from_bed(path: _Path, threads: int = 1) -> Simulation: ...
    def step(self, n: int = 1) -> None: ...
    def add_particle(
        self,
        position: _Vec3,
        radius: float,
        velocity: Optional[_Vec3] = None,
        angular_velocity: Optional[_Vec3] = None,
        component: int = 0,
    ) -> int: ...
    def add_particles(
        self,
        positions: _Vec3s,
        radii: _Floats,
        velocities: Optional[_Vec3s] = None,
        components: Optional[_Ints] = None,
    ) -> list[int]: ...
    def remove_particles(self, ids: _Ints) -> int: ...
    def remove_below(self, z: float) -> list[int]: ...
    def add_clump(
        self,
        members: Sequence[Sequence[float]],
        position: _Vec3,
        orientation: Optional[Sequence[float]] = None,
        velocity: Optional[_Vec3] = None,
        angular_velocity: Optional[_Vec3] = None,
        component: int = 0,
    ) -> int: ...
    @property
    def clumps(self) -> dict[str, npt.NDArray[Any]]: ...
    @property
    def clump_indices(self) -> npt.NDArray[np.int64]: ...
    def add_plane(self, point: _Vec3, normal: _Vec3) -> int: ...
    def add_polygon(self, vertices: _Vec3s) -> int: ...
    def remove_wall(self, id: int) -> None: ...
    def open_gate(self) -> None: ...
    def translate_wall(self, id: int, offset: _Vec3) -> None: ...
    def set_wall_velocity(self, id: int, velocity: _Vec3) -> None: ...
    def wall_load(self, id: int) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]: ...
    @property
    def walls(self) -> dict[str, int]: ...
    @property
    def kind(self) -> str: ...
    @property
    def component_names(self) -> list[str]: ...
    @property
    def time(self) -> float: ...
    @property
    def steps(self) -> int: ...
    @property
    def time_step(self) -> float: ...
    def __len__(self) -> int: ...
    @property
    def positions(self) -> npt.NDArray[np.float64]: ...
    @property
    def velocities(self) -> npt.NDArray[np.float64]: ...
    @property
    def angular_velocities(self) -> npt.NDArray[np.float64]: ...
    @property
    def forces(self) -> npt.NDArray[np.float64]: ...
    @property
    def radii(self) -> npt.NDArray[np.float64]: ...
    @property
    def masses(self) -> npt.NDArray[np.float64]: ...
    @property
    def ids(self) -> npt.NDArray[np.uint64]: ...
    @property
    def components(self) -> npt.NDArray[np.uint8]: ...
    @property
    def materials(self) -> npt.NDArray[np.uint16]: ...
    def energy(self) -> dict[str, float]: ...
    def contacts(self) -> dict[str, int]: ...

def overrides_of(values: Mapping[str, Any]) -> list[str]: ...
def bed_case_text(dir: _Path) -> str: ...
def estimate_cost(
    case: Case,
    threads: int = 1,
    from_bed: Optional[_Path] = None,
    packing: Optional[_Path] = None,
) -> str: ...
def run_case(
    case: Case,
    out: _Path,
    threads: int = 1,
    resume: bool = False,
    restart: bool = False,
    pictures: bool = True,
    progress: Optional[Callable[[str, float, int, float, float], object]] = None,
    from_bed: Optional[_Path] = None,
    packing: Optional[_Path] = None,
    save_bed: Optional[_Path] = None,
) -> str: ...
def run_study(
    sweep: str,
    out: _Path,
    jobs: int = 0,
    replicas: Optional[int] = None,
    sets: Sequence[str] = ...,
    case_threads: int = 1,
    pictures: bool = False,
    progress: Optional[Callable[[int, int, str], object]] = None,
    from_bed: Optional[_Path] = None,
) -> StudyOutcome: ...
def study_report(root: _Path) -> list[Path]: ...
def run_calibration_file(
    file: _Path,
    out: _Path,
    jobs: int = 0,
    progress: Optional[Callable[[int, int, str], object]] = None,
) -> str: ...
def builtin_sweeps() -> list[str]: ...
def _engine_reference(
    case: Case,
    positions: _Vec3s,
    radii: _Floats,
    velocities: _Vec3s,
    steps: int,
    threads: int = 1,
    open_gate: bool = True,
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64], npt.NDArray[np.float64]]: ...
