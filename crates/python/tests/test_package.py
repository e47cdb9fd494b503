"""The package itself: its public names, its typing files, the tables of a run as
properties, and the one progress convention of runs and studies."""

import inspect
import subprocess
import sys
from pathlib import Path

import pytest

import hopperflow as hf
from hopperflow import _native


def test_every_public_name_is_there():
    for name in hf.__all__:
        assert hasattr(hf, name), name
    # The names a user of the first versions wrote keep working.
    for name in ["Case", "CaseError", "RunError", "Run", "Simulation", "Study", "load_run", "load_study",
                 "run", "study", "builtin_sweeps", "read_table", "RUN_TABLES", "PathLike", "__version__"]:
        assert name in hf.__all__, name


def test_test_hooks_are_not_public():
    # The test hooks live in hopperflow._testing, which `import hopperflow` does not load;
    # the extension names its hook privately.
    public = {n for n in dir(_native) if not n.startswith("_")}
    assert not {n for n in public if "reference" in n or "test" in n}
    script = "import sys, hopperflow; print(sorted(m for m in sys.modules if m.startswith('hopperflow')))"
    loaded = subprocess.run([sys.executable, "-c", script], check=True, capture_output=True, text=True).stdout
    assert "_testing" not in loaded and "hopperflow._runs" in loaded


def test_the_package_ships_its_stubs_and_the_typed_marker():
    root = Path(hf.__file__).parent
    assert (root / "py.typed").is_file()
    stubs = (root / "_native.pyi").read_text()
    # Every public name of the extension has a stub.
    for name in dir(_native):
        if not name.startswith("__") or name == "__version__":
            assert f"{name}" in stubs, name


def test_each_table_of_a_run_is_a_documented_property():
    for name, file in hf.RUN_TABLES.items():
        prop = inspect.getattr_static(hf.Run, name)
        assert isinstance(prop, property), name
        assert prop.__doc__ and prop.__doc__.startswith(file), name


def test_an_absent_table_raises_file_not_found_and_other_names_attribute_error(tmp_path):
    run = hf.Run(tmp_path)
    (tmp_path / "flow.csv").write_text("time,rate,cumulative_mass\n0.5,1.0,0.1\n")
    assert list(run.flow["time"]) == [0.5]
    with pytest.raises(FileNotFoundError, match=r"no composition\.csv \(tables it has: flow\.csv\)"):
        run.composition
    with pytest.raises(AttributeError):
        getattr(run, "not_a_table")


def test_progress_must_be_a_bool_or_a_callable(tmp_path):
    with pytest.raises(TypeError, match="progress"):
        hf.run(hf.Case.paper(), out=tmp_path / "r", progress="yes")  # type: ignore[arg-type]


def test_one_callable_takes_the_progress_of_runs_and_studies():
    # RunProgress and StudyProgress are both Progress: one callable serves both.
    run = hf.RunProgress(0.5, "fill", "fill", 0.1, 10, 1e6)
    study = hf.StudyProgress(1.0, "3/3 cases", 3, 3)
    seen = []

    def show(p: hf.Progress) -> None:
        seen.append((p.fraction, p.message))

    show(run)
    show(study)
    assert seen == [(0.5, "fill"), (1.0, "3/3 cases")]
