"""Fixtures of the Python tests: the tiny test case, the command line to compare with, and
one run of the tiny case by each, shared by the tests that only read them."""

import os
import subprocess
from pathlib import Path

import pytest

HERE = Path(__file__).resolve().parent
REPO = HERE.parents[2]
CASES = HERE / "cases"
TINY = CASES / "tiny.toml"
TINY_SWEEP = CASES / "tiny-sweep.toml"


def cli_path() -> Path:
    """The CLI (scripts/test-python.sh names it in HOPPERFLOW_CLI; the release build if unset)."""
    return Path(os.environ.get("HOPPERFLOW_CLI", REPO / "target" / "release" / "hopperflow"))


@pytest.fixture(scope="session")
def cli():
    path = cli_path()
    if not path.is_file():
        pytest.fail(f"{path}: no hopperflow binary; build it with `cargo build --release -p hopperflow`")
    return path


@pytest.fixture(scope="session")
def tiny():
    return TINY


@pytest.fixture(scope="session")
def cli_run(cli, tmp_path_factory):
    """The command line's run of the tiny case (`hopperflow run tiny.toml --out DIR`)."""
    out = tmp_path_factory.mktemp("cli") / "run"
    subprocess.run([str(cli), "run", str(TINY), "--out", str(out), "--quiet"], check=True, capture_output=True)
    return out


@pytest.fixture(scope="session")
def py_run(tmp_path_factory):
    """The same case run from Python with one thread."""
    import hopperflow as hf

    out = tmp_path_factory.mktemp("py") / "run"
    return hf.run(hf.Case.load(str(TINY)), out=out, threads=1, progress=False)


@pytest.fixture(scope="session")
def tiny_bed(tmp_path_factory):
    """The settled bed of the tiny case, saved by one run from Python (`save_bed`); the tests
    that start runs and studies from it only read it."""
    import hopperflow as hf

    root = tmp_path_factory.mktemp("bed")
    bed = root / "bed"
    hf.run(str(TINY), out=root / "saving", progress=False, pictures=False, save_bed=bed)
    return bed
