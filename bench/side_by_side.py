#!/usr/bin/env python3
"""Side-by-side timing of the base hopper case: LIGGGHTS (bench/liggghts/in.hopper) against
hopperflow (`hopperflow bench --case hopper --threads 1 --json`).

The figure compared is the cost per particle-step, in ns, over the same discharge window:
0.2 s (80 000 steps of 2.5 µs) starting 0.1 s after the gate opens. For LIGGGHTS it is
    Loop time / (steps × mean atom count over the window)
with the loop time of the `run` between the log lines BENCH_WINDOW_BEGIN and BENCH_WINDOW_END
and the mean atom count from the thermo rows of that run (trapezoidal rule, one row per
0.01 s). The script also reports, from the same LIGGGHTS log, the steady discharge rate W
(least-squares slope of the mass through the outlet between 15 % and 70 % of the fill
discharged, docs/physics.md §7 "Steady window") and the total wall time of the case.

Ratio printed: LIGGGHTS ns / hopperflow ns (above 1 means hopperflow is faster).

Usage:
  python3 bench/side_by_side.py                 # run both (LIGGGHTS takes 6-7 min on one core)
  python3 bench/side_by_side.py --liggghts-log L  # reuse an existing LIGGGHTS log
  python3 bench/side_by_side.py --skip-liggghts   # hopperflow only
Both codes run on one thread at nice 10 (the machine is shared).
"""
import argparse
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
LIGGGHTS_DIR = os.path.join(HERE, "liggghts")
HOPPERFLOW = os.path.join(REPO, "target", "release", "hopperflow")
TIME_STEP = 2.5e-6  # Δt [s], docs/physics.md §6.1; must match in.hopper
STEADY_FROM, STEADY_TO = 0.15, 0.70  # steady window as fractions of the fill discharged (§7)

LOOP_RE = re.compile(r"Loop time of ([0-9.eE+-]+) on (\d+) procs for (\d+) steps with (\d+) atoms")
# The timing table LIGGGHTS prints after each run, e.g. "Pair  time (%) = 22.0291 (61.4617)".
SECTION_RE = re.compile(r"^(Pair|Neigh|Comm|Outpt|Modify|Other)\s+time \(%\) = ([0-9.eE+-]+)")


class LogError(Exception):
    """The LIGGGHTS log lacks a part that the measurement needs."""


# in.hopper's thermo columns, by position (LIGGGHTS truncates the header names, so the two
# outflow columns would both read "outflow["): step, atoms, translational KE [J], mass through
# the outlet [kg], particles through the outlet, particles deleted at the sink.
COLUMNS = ("step", "atoms", "ke", "mass_out", "count_out", "deleted")
STAMP_RE = re.compile(r"(?:Setting up run at|finish time) (\w{3} \w{3} +\d+ \d+:\d+:\d+ \d{4})")


def scan_log(text, columns):
    """The parts of a LIGGGHTS log that the benchmarks read, each with its line index.

    Returns (rows, markers, loops, sections): the thermo rows of every run as (index, dict of
    `columns`, all values), the BENCH_ marker lines by name as (index, tokens), each run's
    loop as (index, seconds, steps) and its timing table as (index, section, seconds).
    """
    in_thermo = False
    rows, markers, loops, sections = [], {}, [], []
    for i, line in enumerate(text.splitlines()):
        tokens = line.split()
        if not tokens:
            continue
        m = SECTION_RE.match(line)
        if m:
            sections.append((i, m.group(1).lower(), float(m.group(2))))
            continue
        if tokens[0] == "Step":
            in_thermo = True
            continue
        if tokens[0].startswith("BENCH_"):
            markers[tokens[0]] = (i, tokens)
            continue
        m = LOOP_RE.search(line)
        if m:
            loops.append((i, float(m.group(1)), int(m.group(3))))
            in_thermo = False
            continue
        if in_thermo and len(tokens) >= len(columns) and re.fullmatch(r"\d+", tokens[0]):
            try:
                values = [float(t) for t in tokens]
            except ValueError:
                continue
            rows.append((i, dict(zip(columns, values)), values))
    return rows, markers, loops, sections


def log_wall_seconds(text):
    """Seconds from the log's first run set-up to its last run's finish (its time stamps), or
    None where there are fewer than two."""
    stamps = STAMP_RE.findall(text)
    if len(stamps) < 2:
        return None
    first, last = (time.mktime(time.strptime(" ".join(s.split()), "%a %b %d %H:%M:%S %Y"))
                   for s in (stamps[0], stamps[-1]))
    return last - first


def parse_liggghts_log(text):
    """Extracts the timing and discharge figures from a log written by in.hopper.

    Returns a dict with window_loop_s [s], window_steps, window_mean_atoms,
    ns_per_particle_step [ns], discharge_rate_kg_per_s [kg/s], window_discharge_rate_kg_per_s
    [kg/s], mass_discharged_kg [kg], particles_discharged, settle_step, gate_open_step,
    end_step, loop_total_s [s] (sum of all loop times), log_wall_s [s] (first run set-up
    to last run finish, from the log's time stamps; None if they are missing) and
    window_sections_ns (LIGGGHTS' own timing table for the window, per particle-step [ns]:
    pair, neigh, comm, outpt, modify where printed, other).
    """
    rows, markers, loops, sections = scan_log(text, COLUMNS)
    for name in ("BENCH_GATE_OPEN", "BENCH_WINDOW_BEGIN", "BENCH_WINDOW_END"):
        if name not in markers:
            raise LogError("log has no %s line: the run did not reach it" % name)
    begin, end = markers["BENCH_WINDOW_BEGIN"][0], markers["BENCH_WINDOW_END"][0]
    window_loops = [lp for lp in loops if begin < lp[0] < end]
    window_rows = [r for (i, r, _) in rows if begin < i < end]
    if len(window_loops) != 1 or len(window_rows) < 2:
        raise LogError("the timed window has no complete run in the log")
    _, loop_s, steps = window_loops[0]
    atoms = [r["atoms"] for r in window_rows]
    # Trapezoidal mean over equally spaced rows (the first and last rows are the run's ends).
    mean_atoms = (sum(atoms) - 0.5 * (atoms[0] + atoms[-1])) / (len(atoms) - 1)
    ns = loop_s / (steps * mean_atoms) * 1e9
    # The timing table of the window's run: it follows that run's Loop line.
    loop_line = window_loops[0][0]
    window_sections = {name: secs / (steps * mean_atoms) * 1e9
                       for (i, name, secs) in sections if loop_line < i < end}

    open_line = markers["BENCH_GATE_OPEN"][0]
    open_step = int(markers["BENCH_GATE_OPEN"][1][2])
    # Rows at a run boundary appear twice (end of one run, start of the next): keep one.
    discharge = sorted({int(r["step"]): (r["mass_out"], r["count_out"])
                        for (i, r, _) in rows if i > open_line}.items())
    total_mass, total_count = discharge[-1][1]
    # The window's fractions refer to the fill (as hopperflow's, docs/physics.md §7): the atoms
    # present when the gate opened times the mass of one sphere (they are all alike). A run
    # that discharged less than STEADY_TO of its fill falls back to what did leave.
    fill_atoms = next(r["atoms"] for (i, r, _) in rows if i > open_line)
    fill_mass = fill_atoms * total_mass / total_count if total_count > 0 else total_mass
    reference = fill_mass if total_mass >= STEADY_TO * fill_mass else total_mass
    pts = [((s - open_step) * TIME_STEP, mass) for (s, (mass, _)) in discharge
           if STEADY_FROM * reference <= mass <= STEADY_TO * reference]
    rate = None
    if len(pts) >= 3:
        n = len(pts)
        mt = sum(t for t, _ in pts) / n
        mm = sum(mass for _, mass in pts) / n
        sxx = sum((t - mt) ** 2 for t, _ in pts)
        rate = sum((t - mt) * (mass - mm) for t, mass in pts) / sxx
    window_rate = (window_rows[-1]["mass_out"] - window_rows[0]["mass_out"]) / (steps * TIME_STEP)
    wall = log_wall_seconds(text)
    settle_step = int(markers["BENCH_SETTLED"][1][2]) if "BENCH_SETTLED" in markers else None
    return {
        "window_loop_s": loop_s,
        "window_steps": steps,
        "window_mean_atoms": mean_atoms,
        "ns_per_particle_step": ns,
        "discharge_rate_kg_per_s": rate,
        "window_discharge_rate_kg_per_s": window_rate,
        "mass_discharged_kg": total_mass,
        "particles_discharged": int(total_count),
        "settle_step": settle_step,
        "gate_open_step": open_step,
        "end_step": discharge[-1][0],
        "loop_total_s": sum(lp[1] for lp in loops),
        "log_wall_s": wall,
        "window_sections_ns": window_sections,
    }


def find_liggghts():
    """The LIGGGHTS executable: Debian installs `liggghts`; source builds make `lmp_auto`."""
    for name in ("liggghts", "lmp_auto", "lmp_serial", "lmp_mpi"):
        path = shutil.which(name)
        if path:
            return path
    return None


def load_average():
    """The 1-minute load average, or None where /proc is absent."""
    try:
        return float(open("/proc/loadavg").read().split()[0])
    except (OSError, ValueError, IndexError):
        return None


def niced():
    os.nice(10)


def run_liggghts(out_dir, extra_vars):
    """Runs in.hopper on one core; returns (log text, wall seconds measured here)."""
    exe = find_liggghts()
    if exe is None:
        raise FileNotFoundError("no LIGGGHTS executable found (install: apt-get install liggghts)")
    log = os.path.join(out_dir, "log.hopper")
    cmd = [exe, "-in", "in.hopper", "-log", log]
    for name, value in extra_vars:
        cmd += ["-var", name, value]
    env = dict(os.environ, OMP_NUM_THREADS="1")
    start = time.monotonic()
    with open(os.path.join(out_dir, "screen.out"), "w") as screen:
        subprocess.run(cmd, cwd=LIGGGHTS_DIR, env=env, stdout=screen, stderr=subprocess.STDOUT,
                       check=True, preexec_fn=niced)
    return open(log).read(), time.monotonic() - start


def run_hopperflow(case):
    """Runs the hopperflow bench on one thread.

    Returns (JSON object or None, message): None with the reason when the binary is missing,
    the command fails (e.g. the case is not implemented yet) or prints no JSON object.
    """
    if not os.path.exists(HOPPERFLOW):
        return None, ("not built (%s missing): build it with `cargo build --release -p "
                      "hopperflow`, then rerun this script" % os.path.relpath(HOPPERFLOW, REPO))
    cmd = [HOPPERFLOW, "bench", "--case", case, "--threads", "1", "--json"]
    env = dict(os.environ, RAYON_NUM_THREADS="1")
    done = subprocess.run(cmd, env=env, capture_output=True, text=True, preexec_fn=niced)
    if done.returncode != 0:
        tail = " ".join(done.stderr.strip().splitlines()[-3:])
        return None, "`%s` failed (exit %d): %s" % (" ".join(cmd[1:]), done.returncode, tail)
    out = done.stdout
    try:
        return json.loads(out[out.index("{"):out.rindex("}") + 1]), ""
    except ValueError:
        return None, "`%s` printed no JSON object" % " ".join(cmd[1:])


def print_breakdown(lig, hf):
    """Where each code's time went, per particle-step over the window, from each code's own
    timing table. The sections do not map one to one: LIGGGHTS' Pair is particle pairs
    only, and its walls (fix wall/gran), integration and outlet counters are in Other (or
    Modify, where printed); hopperflow's forces hold pairs and walls."""
    sections = (lig or {}).get("window_sections_ns") or {}
    if sections:
        names = [n for n in ("pair", "neigh", "comm", "outpt", "modify", "other") if n in sections]
        print("breakdown  : LIGGGHTS   %s  (ns per particle-step; walls, integration and fixes "
              "are in other)" % ", ".join("%s %.1f" % (n, sections[n]) for n in names))
    phases = hf.get("phases") if isinstance(hf, dict) else None
    if isinstance(phases, dict):
        parts = [("forces", "forces_ns"), ("integrate", "integrate_ns"),
                 ("neighbour", "neighbour_ns"), ("other", "other_ns")]
        print("             hopperflow %s  (ns per particle-step; forces hold pairs and walls)"
              % ", ".join("%s %.1f" % (n, phases[k]) for n, k in parts if k in phases))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--liggghts-log", help="parse this LIGGGHTS log instead of running LIGGGHTS")
    ap.add_argument("--skip-liggghts", action="store_true", help="do not run or parse LIGGGHTS")
    ap.add_argument("--keep", help="folder for the LIGGGHTS log and screen output "
                    "(default: a temporary folder)")
    ap.add_argument("--var", nargs=2, action="append", default=[], metavar=("NAME", "VALUE"),
                    help="pass -var NAME VALUE to LIGGGHTS (e.g. --var seed 49979687)")
    ap.add_argument("--hopperflow-case", default="hopper",
                    help="hopperflow bench case (default hopper, the comparable one)")
    ap.add_argument("--json", action="store_true", help="print one JSON object at the end")
    args = ap.parse_args()

    result = {"loadavg_before": load_average()}
    lig = None
    if not args.skip_liggghts:
        if args.liggghts_log:
            lig = parse_liggghts_log(open(args.liggghts_log).read())
        else:
            out = args.keep or tempfile.mkdtemp(prefix="liggghts_hopper_")
            os.makedirs(out, exist_ok=True)
            print("running LIGGGHTS (one core, 6-7 min on an idle core); log in %s" % out, flush=True)
            text, wall = run_liggghts(out, args.var)
            lig = parse_liggghts_log(text)
            lig["measured_wall_s"] = wall
        result["liggghts"] = lig
        print("LIGGGHTS   : %.1f ns/particle-step  (loop %.2f s, %d steps, mean %.1f atoms)"
              % (lig["ns_per_particle_step"], lig["window_loop_s"], lig["window_steps"],
                 lig["window_mean_atoms"]))
        if lig["discharge_rate_kg_per_s"] is not None:
            print("             steady discharge rate W = %.1f g/s (window: %.1f g/s), "
                  "%.1f g discharged" % (1e3 * lig["discharge_rate_kg_per_s"],
                                         1e3 * lig["window_discharge_rate_kg_per_s"],
                                         1e3 * lig["mass_discharged_kg"]))
        wall = lig.get("measured_wall_s") or lig["log_wall_s"]
        if wall is not None:
            print("             full case wall time %.0f s (%d particles through the outlet)"
                  % (wall, lig["particles_discharged"]))

    hf, why = run_hopperflow(args.hopperflow_case)
    if hf is None:
        print("hopperflow : %s" % why)
    else:
        if hf.get("case") != "hopper":
            print("caution    : hopperflow case %r is not the discharge window timed for "
                  "LIGGGHTS; the ratio is indicative only" % hf.get("case"))
        result["hopperflow"] = hf
        ns = hf.get("ns_per_particle_step")
        print("hopperflow : %s ns/particle-step  %s" % (
            "%.1f" % ns if isinstance(ns, (int, float)) else "?",
            json.dumps({k: v for k, v in hf.items() if k != "ns_per_particle_step"})))
        if lig is not None and isinstance(ns, (int, float)) and ns > 0:
            ratio = lig["ns_per_particle_step"] / ns
            result["ratio_liggghts_over_hopperflow"] = ratio
            print("ratio      : LIGGGHTS / hopperflow = %.2f (above 1: hopperflow is faster)"
                  % ratio)
        print_breakdown(lig, hf)
    result["loadavg_after"] = load_average()
    print("load average (1 min) before/after: %s / %s  (2 cores; above ~1 the timings are "
          "contended)" % (result["loadavg_before"], result["loadavg_after"]))
    if args.json:
        print(json.dumps(result))
    return 0


if __name__ == "__main__":
    try:
        sys.exit(main())
    except (LogError, FileNotFoundError, subprocess.CalledProcessError) as err:
        print("error: %s" % err, file=sys.stderr)
        sys.exit(1)
