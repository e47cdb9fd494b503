#!/usr/bin/env bash
# The Python part of the project's test command (scripts/test.sh runs it): a fresh virtual
# environment under target/, the abi3 wheel of crates/python built by maturin and
# installed in it, the CLI that the tests compare against, the type check (mypy), then
# pytest.
#
# Needs python3 (≥ 3.9, with venv and pip) and the package index for maturin, numpy,
# pandas, matplotlib, pytest, pytest-xdist and mypy.
#
# `--prepare` only makes the virtual environment (scripts/test.sh runs that while Cargo
# builds, as it waits mostly on the network and the disk); `--prepared` uses the one made.
set -euo pipefail
cd "$(dirname "$0")/.."

started=$(date +%s)
venv=target/python-test-venv
wheels=target/python-wheels
if [ "${1:-}" != --prepared ]; then
    mkdir -p target
    python3 -m venv --clear "$venv"
    "$venv/bin/python" -m pip install --quiet --upgrade pip
    "$venv/bin/python" -m pip install --quiet "maturin>=1.5,<2" numpy pandas matplotlib pytest pytest-xdist mypy
fi
if [ "${1:-}" = --prepare ]; then
    exit 0
fi

# The wheel is built in the dev profile, which the test profile inherits (optimised like the
# release build, without its link-time optimisation): it reuses every crate the Rust tests
# built (the features agree, as no development dependency of the workspace changes them),
# so only pyo3 and the module itself are compiled here. The command line the tests compare
# its results with, byte for byte, is the same build's.
rm -rf "$wheels"
"$venv/bin/maturin" build --profile dev --locked -m crates/python/Cargo.toml -o "$wheels"
"$venv/bin/python" -m pip install --quiet "$wheels"/hopperflow-*.whl

# The tests compare runs from Python with the command line's, byte for byte.
# The CLI the tests compare with: scripts/test.sh passes the one its `cargo test` built;
# run alone, this script builds the release binary.
if [ -z "${HOPPERFLOW_CLI:-}" ]; then
    cargo build --release --locked -p hopperflow
    HOPPERFLOW_CLI="$PWD/target/release/hopperflow"
fi
export HOPPERFLOW_CLI

# The type check: the package's source against the stubs of its extension
# (_native.pyi), and the tests and the example as code that uses it; the settings are in
# crates/python/pyproject.toml. The wheel ships the same files, with py.typed.
checked=$(date +%s)
"$venv/bin/python" -m mypy --config-file crates/python/pyproject.toml --cache-dir target/mypy-cache \
    crates/python/python/hopperflow crates/python/tests examples/quickstart.py
echo "Type check: $(($(date +%s) - checked)) s"

# Run from outside the source tree, so that `import hopperflow` finds the installed wheel.
# pytest-xdist spreads the tests over the cores (at most four workers; each makes for itself
# the runs of the tiny case that the tests share): most of them wait on one-thread runs.
(cd target && "../$venv/bin/python" -m pytest ../crates/python/tests -q -p no:cacheprovider \
    -n auto --maxprocesses 4)
echo "Python part: $(($(date +%s) - started)) s"
