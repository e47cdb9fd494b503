#!/usr/bin/env bash
# A one-node Slurm cluster on this machine, for the Slurm tests. Needs root (as CI runs).
#
#   slurm-cluster.sh start DIR   installs Debian's slurm-wlm and munge where they are missing,
#                                writes DIR/slurm.conf and starts munged (unless a munged
#                                already answers), slurmctld and slurmd
#   slurm-cluster.sh stop DIR    cancels the cluster's jobs, stops the daemons it started and
#                                undoes what start did outside DIR, then checks that it did
#
# Commands that should reach this cluster need SLURM_CONF=DIR/slurm.conf. DIR holds the
# configuration, the controller's state, the daemons' logs and this script's records; it is
# the caller's to remove after `stop` (start makes it traversable by the `slurm` user, who
# writes the state and the controller's log).
#
# The daemons run as Debian's packages run them, so that the files they leave are owned as
# the host's own services expect: munged as the `munge` user (its init script and unit do;
# munged refuses a log file another user owns, so a root munged would leave a log that stops
# the host's munge from starting), slurmctld started as root and dropping to SlurmUser=slurm
# (the unit starts it as root; Debian's example configurations set SlurmUser=slurm), slurmd
# as root.
#
# What start changes outside DIR, stop undoes: a munged it started is stopped, and what start
# and that munged created in munge's folders (/run/munge, the log, seed, socket and pid file,
# a key if there was none) is removed; packages it installed are purged (with the users and
# files their installation made), so the machine is left without them as it was found. Before anything else start
# records who owns what in those folders (and which of the users munge and slurm exist);
# stop compares the same record afterwards and fails, listing the differences, if any owner,
# mode or file differs. Outside that record remain apt's package lists (refreshed by start's
# `apt-get update`) and apt's and dpkg's logs of the installation.
set -euo pipefail

usage="usage: slurm-cluster.sh start|stop DIR"
action=${1:?$usage}
dir=${2:?$usage}
mkdir -p "$dir"
dir=$(cd "$dir" && pwd)

# Folders of munge and Slurm outside DIR: whatever the daemons or the packages could write.
MUNGE_PATHS=(/etc/munge /var/log/munge /var/lib/munge /run/munge)
SLURM_PATHS=(/etc/slurm /var/log/slurm /var/lib/slurm /var/spool/slurmd /var/spool/slurmctld /run/slurm)

# Owner, group, mode and path of everything under those folders, and the users the packages
# add: a record to compare before start and after stop.
ownership() {
    local user
    for user in munge slurm; do
        if id "$user" >/dev/null 2>&1; then
            echo "user $user $(id -u "$user"):$(id -g "$user")"
        else
            echo "user $user absent"
        fi
    done
    find "${MUNGE_PATHS[@]}" "${SLURM_PATHS[@]}" -printf '%u:%g %m %p\n' 2>/dev/null | sort -k3 || true
}

# Debian's packages: installed ("ii") package names, one a line.
installed_packages() {
    dpkg-query -W -f='${db:Status-Abbrev} ${Package}\n' 2>/dev/null | awk '$1 == "ii" {print $2}' | sort
}

# Waits up to $2 seconds for process $1 to end; 1 if it is still there.
wait_for_exit() {
    local pid=$1 tries=$(($2 * 10))
    while kill -0 "$pid" 2>/dev/null; do
        tries=$((tries - 1))
        [ "$tries" -gt 0 ] || return 1
        sleep 0.1
    done
}

# Stops the process whose id file $1 names (SIGTERM, then SIGKILL after $2 seconds).
stop_pid_file() {
    local file=$1 patience=$2 pid
    if [ ! -s "$file" ]; then
        rm -f "$file"
        return 0
    fi
    pid=$(cat "$file")
    if kill "$pid" 2>/dev/null && ! wait_for_exit "$pid" "$patience"; then
        echo "slurm-cluster: process $pid ($file) did not stop in ${patience} s; killing it" >&2
        kill -KILL "$pid" 2>/dev/null || true
        wait_for_exit "$pid" 5 || true
    fi
    rm -f "$file"
}

stop() {
    if [ -f "$dir/slurm.conf" ] && [ -s "$dir/slurmctld.pid" ] && kill -0 "$(cat "$dir/slurmctld.pid")" 2>/dev/null; then
        # Jobs left in the queue would go on running under slurmstepd after slurmd stops.
        local jobs
        jobs=$(SLURM_CONF="$dir/slurm.conf" squeue --noheader --format=%A 2>/dev/null || true)
        if [ -n "$jobs" ]; then
            # shellcheck disable=SC2086 # one job id a word
            SLURM_CONF="$dir/slurm.conf" scancel $jobs 2>/dev/null || true
            for _ in $(seq 300); do
                [ -z "$(SLURM_CONF="$dir/slurm.conf" squeue --noheader --format=%A 2>/dev/null)" ] && break
                sleep 0.2
            done
        fi
    fi
    stop_pid_file "$dir/slurmd.pid" 30
    stop_pid_file "$dir/slurmctld.pid" 30
    stop_pid_file "$dir/munged.started" 10
    if [ -f "$dir/munge.before" ]; then
        # What start and its munged created in munge's folders, deepest first: the record
        # taken before names everything that was there.
        { find "${MUNGE_PATHS[@]}" -depth -print 2>/dev/null || true; } | while read -r path; do
            grep -qxF -- "$path" "$dir/munge.before" || rm -rf -- "$path"
        done
        rm -f "$dir/munge.before"
    fi
    if [ -s "$dir/installed-packages" ]; then
        # shellcheck disable=SC2046 # one package a word
        DEBIAN_FRONTEND=noninteractive apt-get purge -y -qq $(cat "$dir/installed-packages") >/dev/null
    fi
    rm -f "$dir/installed-packages"
    if [ -f "$dir/ownership.before" ]; then
        # As before, but for what start gave back to munge (the `restored` lines).
        touch "$dir/restored"
        awk 'FILENAME == ARGV[1] {owner[$1] = $2; next} ($3 in owner) {$1 = owner[$3]} {print}' \
            "$dir/restored" "$dir/ownership.before" > "$dir/ownership.expected"
        ownership > "$dir/ownership.after"
        if ! diff -u "$dir/ownership.expected" "$dir/ownership.after" >"$dir/ownership.diff"; then
            echo "slurm-cluster: after stop, munge's and Slurm's files and users differ from before start (- before, + after):" >&2
            cat "$dir/ownership.diff" >&2
            return 1
        fi
        rm -f "$dir"/ownership.* "$dir/restored"
    fi
}

if [ "$action" = stop ]; then
    stop
    exit 0
fi
[ "$action" = start ] || { echo "$usage" >&2; exit 2; }

# A cluster this folder already holds is stopped (and its changes undone) first.
stop

ownership > "$dir/ownership.before"
: > "$dir/restored"

if ! command -v slurmctld >/dev/null || ! command -v munged >/dev/null || ! command -v sbatch >/dev/null; then
    export DEBIAN_FRONTEND=noninteractive
    installed_packages > "$dir/packages.before"
    apt-get update -qq
    apt-get install -y -qq --no-install-recommends slurm-wlm munge >/dev/null
    installed_packages | comm -13 "$dir/packages.before" - > "$dir/installed-packages"
    rm -f "$dir/packages.before"
fi

# Gives $1 to munge:munge if another user owns it; recorded in DIR/restored, which stop's
# check expects.
give_to_munge() {
    local path=$1
    if [ "$(stat -c %U "$path")" != munge ]; then
        echo "slurm-cluster: $path was $(stat -c %U:%G "$path"); giving it back to munge:munge, as Debian's package sets it" >&2
        chown munge:munge "$path"
        echo "$path munge:munge" >> "$dir/restored"
    fi
}

# munge authenticates the daemons and clients to each other; one key, one host.
if ! munge -n 2>/dev/null | unmunge >/dev/null 2>&1; then
    find "${MUNGE_PATHS[@]}" -print 2>/dev/null > "$dir/munge.before" || true
    # The folders as Debian's package sets them (its postinst; /run/munge as its init script
    # and unit make it), and munged's own files in them munge's: a munged run as root by an
    # earlier version of this script left its log root's, which munged refuses.
    for folder in /etc/munge:700 /var/log/munge:700 /var/lib/munge:711 /run/munge:755; do
        if [ -d "${folder%:*}" ]; then
            give_to_munge "${folder%:*}"
        else
            install -d -o munge -g munge -m "${folder#*:}" "${folder%:*}"
        fi
    done
    for file in /etc/munge/munge.key /var/log/munge/munged.log /var/lib/munge/munged.seed; do
        [ ! -e "$file" ] || give_to_munge "$file"
    done
    [ -s /etc/munge/munge.key ] || runuser -u munge -- mungekey --create
    touch "$dir/munged.started"
    runuser -u munge -- /usr/sbin/munged
    for _ in $(seq 50); do munge -n 2>/dev/null | unmunge >/dev/null 2>&1 && break; sleep 0.1; done
    cp /run/munge/munged.pid "$dir/munged.started"
    munge -n | unmunge >/dev/null || { echo "slurm-cluster: munged does not answer; see /var/log/munge/munged.log" >&2; exit 1; }
fi

node=$(hostname -s)
cpus=$(nproc)
memory=$(( $(awk '/MemTotal/ {print $2}' /proc/meminfo) / 1024 / 2 ))
# slurmctld writes its state and log as SlurmUser: those are slurm's, and DIR must let
# slurm through (as Debian's /var/lib/slurm/slurmctld and /var/log/slurm are slurm's).
chmod go+x "$dir"
mkdir -p "$dir/state" "$dir/spool" "$dir/log"
chown slurm:slurm "$dir/state" "$dir/log"
cat > "$dir/slurm.conf" <<CONF
ClusterName=hopperflow-test
SlurmctldHost=$node(127.0.0.1)
SlurmUser=slurm
SlurmdUser=root
SlurmctldPort=16817
SlurmdPort=16818
AuthType=auth/munge
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/log/slurmctld.log
SlurmdLogFile=$dir/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
MpiDefault=none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SchedulerType=sched/backfill
KillWait=30
NodeName=$node NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=$memory State=UNKNOWN
PartitionName=debug Nodes=$node Default=YES MaxTime=INFINITE State=UP
CONF
chmod 0644 "$dir/slurm.conf"
export SLURM_CONF="$dir/slurm.conf"
# -c: a clean start, without jobs a previous test cluster left in its state files.
slurmctld -c
slurmd -N "$node"
for _ in $(seq 100); do
    if sinfo --noheader --format=%T 2>/dev/null | grep -qx idle; then
        echo "slurm: one node ($node, $cpus CPUs) up; SLURM_CONF=$dir/slurm.conf"
        exit 0
    fi
    sleep 0.2
done
echo "slurm: the node did not come up; see $dir/log" >&2
exit 1
