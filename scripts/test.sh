#!/usr/bin/env bash
# The project's test command (README; .ci/run calls it): the Rust tests, the Python
# package's tests (scripts/test-python.sh), then the Slurm tests against a one-node cluster
# that it starts on this machine and stops again.
#
# HOPPERFLOW_SKIP_PYTHON=1 leaves the Python part out (it builds a virtual environment
# and installs packages from the package index).
#
# The Slurm part installs Debian's slurm-wlm and munge where they are missing (and purges
# them again at the end), so it needs root (as CI has); HOPPERFLOW_SKIP_SLURM=1 leaves it
# out on a machine without them. Stopping the cluster checks that munge's and Slurm's files
# and users are as they were before it started; if they are not, the command fails.
set -euo pipefail
cd "$(dirname "$0")/.."

# The Python tests' virtual environment is made while Cargo builds: it waits mostly on the
# network and the disk. Its output is shown once it is ready.
if [ "${HOPPERFLOW_SKIP_PYTHON:-0}" != 1 ]; then
    mkdir -p target
    scripts/test-python.sh --prepare >target/python-prepare.log 2>&1 &
    prepare=$!
    trap 'kill "$prepare" 2>/dev/null || true' EXIT
fi

# A build from nothing, as on a clean clone, is about a tenth faster without incremental
# compilation's bookkeeping (2 min 57 s against 3 min 16 s for the test build, on two idle
# cores): the test command builds every crate once, so it keeps none.
export CARGO_INCREMENTAL=0

# Every later step reuses this build: the CLI binary it made (the test profile is optimised)
# and, for the Slurm tests, the same workspace-wide feature set. A step that builds one
# package alone (`-p`) unifies features differently and compiles the CLI again.
#
# The Rust tests run under cargo-nextest where it is installed: it keeps both cores busy with
# the tests of every crate at once (a process per test), where `cargo test` runs one test
# binary after another and leaves a core idle while a binary's last long test runs (the same
# tests on two cores: 242 s against 304 s). nextest runs no doc-tests; `cargo test --doc`
# does. Without nextest, `cargo test` runs them all.
if cargo nextest --version >/dev/null 2>&1; then
    cargo nextest run --workspace --locked
    cargo test --workspace --doc --locked
else
    cargo test --workspace --locked
fi
export HOPPERFLOW_CLI="$PWD/target/debug/hopperflow"

if [ "${HOPPERFLOW_SKIP_PYTHON:-0}" = 1 ]; then
    echo "Python tests skipped (HOPPERFLOW_SKIP_PYTHON=1)"
else
    prepared=0
    wait "$prepare" || prepared=$?
    trap - EXIT
    cat target/python-prepare.log
    if [ "$prepared" != 0 ]; then
        echo "error: the Python tests' virtual environment could not be made" >&2
        exit "$prepared"
    fi
    scripts/test-python.sh --prepared
fi

if [ "${HOPPERFLOW_SKIP_SLURM:-0}" = 1 ]; then
    echo "Slurm tests skipped (HOPPERFLOW_SKIP_SLURM=1)"
    exit 0
fi
cluster=$(mktemp -d -t hopperflow-slurm.XXXXXX)
# Whatever happened: the daemons' logs if something failed, then the cluster stopped (a
# failed stop fails the command) and its folder removed.
finish() {
    local status=$?
    if [ "$status" != 0 ]; then
        tail -n 40 "$cluster"/log/*.log >&2 2>/dev/null || true
    fi
    scripts/slurm-cluster.sh stop "$cluster" || status=1
    rm -rf "$cluster"
    exit "$status"
}
trap finish EXIT
scripts/slurm-cluster.sh start "$cluster"
SLURM_CONF="$cluster/slurm.conf" cargo test --workspace --test slurm --locked -- --ignored
