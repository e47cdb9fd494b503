#!/usr/bin/env bash
# The Python part of the project's test command (scripts/test.sh runs it): a fresh virtual
# environment under target/, the abi3 wheel of crates/python built by maturin and
# installed in it, the CLI that the tests compare against, then pytest.
#
#   scripts/test-python.sh            both steps below, one after the other
#   scripts/test-python.sh prepare    the environment and the wheel only
#   scripts/test-python.sh run        pytest against what `prepare` installed
#
# scripts/test.sh runs `prepare` beside the Rust tests, whose test runs leave a core idle
# much of the time. The wheel is built in its own target folder (target/python-wheel-build),
# so that its cargo never waits for the Rust tests' lock on target/.
#
# Needs python3 (≥ 3.9, with venv and pip) and the package index for maturin, numpy,
# pandas, matplotlib and pytest.
set -euo pipefail
cd "$(dirname "$0")/.."

venv=target/python-test-venv
wheels=target/python-wheels

prepare() {
    python3 -m venv --clear "$venv"
    "$venv/bin/python" -m pip install --quiet --upgrade pip
    "$venv/bin/python" -m pip install --quiet "maturin>=1.5,<2" numpy pandas matplotlib pytest
    rm -rf "$wheels"
    CARGO_TARGET_DIR="$PWD/target/python-wheel-build" \
        "$venv/bin/maturin" build --release --locked -m crates/python/Cargo.toml -o "$wheels"
    "$venv/bin/python" -m pip install --quiet "$wheels"/hopperflow-*.whl
}

run() {
    # The tests compare runs from Python with the command line's, byte for byte.
    # The CLI the tests compare with: scripts/test.sh passes the one its `cargo test` built;
    # run alone, this script builds the release binary.
    if [ -z "${HOPPERFLOW_CLI:-}" ]; then
        cargo build --release --locked -p hopperflow
        HOPPERFLOW_CLI="$PWD/target/release/hopperflow"
    fi
    export HOPPERFLOW_CLI
    # Run from outside the source tree, so that `import hopperflow` finds the installed wheel.
    (cd target && "../$venv/bin/python" -m pytest ../crates/python/tests -q -p no:cacheprovider)
}

started=$(date +%s)
case "${1:-all}" in
    prepare) prepare ;;
    run) run ;;
    all) prepare && run ;;
    *) echo "usage: scripts/test-python.sh [prepare|run]" >&2; exit 2 ;;
esac
echo "Python part (${1:-all}): $(($(date +%s) - started)) s"
