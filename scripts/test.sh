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

# The Rust tests' build comes first. Beside it run the steps that mostly wait on downloads: the Python environment and
# its packages (scripts/test-python.sh env, its output in target/python-env.log) and the
# Slurm cluster's start, with its package installation (target/slurm-start.log). The
# cluster's daemons then wait idle until the Slurm tests; the tests that must not see Slurm's
# tools run with a PATH of their own.
mkdir -p target
python=0
if [ "${HOPPERFLOW_SKIP_PYTHON:-0}" = 1 ]; then
    echo "Python tests skipped (HOPPERFLOW_SKIP_PYTHON=1)"
else
    scripts/test-python.sh env > target/python-env.log 2>&1 &
    python=$!
fi

slurm=0
cluster=
if [ "${HOPPERFLOW_SKIP_SLURM:-0}" = 1 ]; then
    echo "Slurm tests skipped (HOPPERFLOW_SKIP_SLURM=1)"
else
    cluster=$(mktemp -d -t hopperflow-slurm.XXXXXX)
    scripts/slurm-cluster.sh start "$cluster" > target/slurm-start.log 2>&1 &
    slurm=$!
fi

# Whatever happened: the background steps waited for, the daemons' logs if something failed,
# then the cluster stopped (a failed stop fails the command) and its folder removed.
finish() {
    local status=$?
    [ "$python" = 0 ] || wait "$python" 2>/dev/null || true
    if [ -n "$cluster" ]; then
        [ "$slurm" = 0 ] || wait "$slurm" 2>/dev/null || true
        if [ "$status" != 0 ]; then
            cat target/slurm-start.log >&2 2>/dev/null || true
            tail -n 40 "$cluster"/log/*.log >&2 2>/dev/null || true
        fi
        scripts/slurm-cluster.sh stop "$cluster" || status=1
        rm -rf "$cluster"
    fi
    exit "$status"
}
trap finish EXIT

# Every later step reuses this build: the CLI binary it made (the test profile is optimised)
# and, for the Slurm tests, the same workspace-wide feature set. A step that builds one
# package alone (`-p`) unifies features differently and compiles the CLI again.
cargo test --workspace --locked
export HOPPERFLOW_CLI="$PWD/target/debug/hopperflow"

if [ "$python" != 0 ]; then
    if ! wait "$python"; then
        python=0
        cat target/python-env.log >&2
        echo "the Python environment could not be prepared" >&2
        exit 1
    fi
    python=0
    tail -n 1 target/python-env.log
    scripts/test-python.sh wheel
    scripts/test-python.sh run
fi

if [ "$slurm" != 0 ]; then
    if ! wait "$slurm"; then
        slurm=0
        echo "the Slurm cluster did not start" >&2
        exit 1
    fi
    slurm=0
    cat target/slurm-start.log
    SLURM_CONF="$cluster/slurm.conf" cargo test --workspace --test slurm --locked -- --ignored
fi
