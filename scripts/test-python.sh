#!/usr/bin/env bash
# The Python part of the project's test command (scripts/test.sh runs it): a fresh virtual
# environment under target/, the abi3 wheel of crates/python built by maturin and
# installed in it, the CLI that the tests compare against, then pytest.
#
#   scripts/test-python.sh            the three steps below, one after the other
#   scripts/test-python.sh env        the virtual environment and the packages from the index
#   scripts/test-python.sh wheel      the wheel, built and installed in that environment
#   scripts/test-python.sh run        pytest against what `wheel` installed
#
# scripts/test.sh runs `env`, which mostly waits on downloads, beside the Rust tests' build,
# and `wheel` and `run` after them.
#
# Needs python3 (≥ 3.9, with venv and pip) and the package index for maturin, numpy,
# pandas, matplotlib and pytest.
set -euo pipefail
cd "$(dirname "$0")/.."

venv=target/python-test-venv
wheels=target/python-wheels

env() {
    python3 -m venv --clear "$venv"
    "$venv/bin/python" -m pip install --quiet --upgrade pip
    "$venv/bin/python" -m pip install --quiet "maturin>=1.5,<2" numpy pandas matplotlib pytest
}

wheel() {
    rm -rf "$wheels"
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
    env) env ;;
    wheel) wheel ;;
    run) run ;;
    all) env && wheel && run ;;
    *) echo "usage: scripts/test-python.sh [env|wheel|run]" >&2; exit 2 ;;
esac
echo "Python part (${1:-all}): $(($(date +%s) - started)) s"
