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

# What runs beside the build (it waits mostly on the network and the disk) and what the
# command must undo whatever happens: the Python tests' virtual environment, and the one-node
# Slurm cluster (its packages installed where missing, its daemons started). Each one's
# output is shown once it is needed. At the end, whatever happened: a preparation still
# running stopped, the daemons' logs shown if something failed, the cluster stopped (a
# failed stop fails the command) and its folder removed.
prepare=""
cluster=""
starting=""
finish() {
    local status=$?
    if [ -n "$prepare" ]; then
        kill "$prepare" 2>/dev/null || true
    fi
    if [ -n "$cluster" ]; then
        if [ -n "$starting" ]; then
            wait "$starting" 2>/dev/null || true
        fi
        if [ "$status" != 0 ]; then
            tail -n 40 "$cluster"/log/*.log >&2 2>/dev/null || true
        fi
        scripts/slurm-cluster.sh stop "$cluster" || status=1
        rm -rf "$cluster"
    fi
    exit "$status"
}
trap finish EXIT
# Waits for the preparation of process $1, shows its log $2, and fails with message $3 and
# the preparation's status if it failed.
await() {
    local status=0
    wait "$1" || status=$?
    cat "$2"
    if [ "$status" != 0 ]; then
        echo "error: $3" >&2
        exit "$status"
    fi
}
mkdir -p target
if [ "${HOPPERFLOW_SKIP_PYTHON:-0}" != 1 ]; then
    scripts/test-python.sh --prepare >target/python-prepare.log 2>&1 &
    prepare=$!
fi
if [ "${HOPPERFLOW_SKIP_SLURM:-0}" != 1 ]; then
    cluster=$(mktemp -d -t hopperflow-slurm.XXXXXX)
    scripts/slurm-cluster.sh start "$cluster" >target/slurm-start.log 2>&1 &
    starting=$!
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
    await "$prepare" target/python-prepare.log "the Python tests' virtual environment could not be made"
    prepare=""
    scripts/test-python.sh --prepared
fi

if [ "${HOPPERFLOW_SKIP_SLURM:-0}" = 1 ]; then
    echo "Slurm tests skipped (HOPPERFLOW_SKIP_SLURM=1)"
    exit 0
fi
await "$starting" target/slurm-start.log "the Slurm tests' cluster could not be started"
starting=""
SLURM_CONF="$cluster/slurm.conf" cargo test --workspace --test slurm --locked -- --ignored
