#!/usr/bin/env python3
"""Side-by-side timing on the reduced benchmark silo: LIGGGHTS (bench/liggghts/silo/in.silo)
against hopperflow, both starting from one packing CSV and the same STL walls.

The figure compared is the cost per particle-step, in ns, over the same discharge window.
LIGGGHTS settles the packing on the closed gate for --settle-steps, removes the gate, runs
--transient-steps untimed and then times --window-steps (Δt = 1.5 µs); hopperflow's bench
does the same, with its own end of the settling and its fixed window (below). For LIGGGHTS it is
    Loop time / (steps × mean atom count over the window)
with the loop time of the `run` between the log lines BENCH_WINDOW_BEGIN and BENCH_WINDOW_END
and the mean atom count from the thermo rows of that run (trapezoidal rule). The script also
reports the atoms at the window's ends, how many spheres left the silo (centre below the
orifice plane) during the window, and the wall time of the LIGGGHTS case. When it runs
LIGGGHTS itself, it also reads LIGGGHTS' CPU time over the window (window_cpu_s,
cpu_ns_per_particle_step): loop / CPU above about 1.05 means the core was shared.

hopperflow's half is a hook: --hopperflow-cmd TEMPLATE is run on one thread, with the
placeholders below filled in, and must print one JSON object with `ns_per_particle_step`
over the same window (it may add `phases`, `mean_particles`, ...):
    {hopperflow}       target/release/hopperflow
    {packing}          the packing CSV both codes start from (absolute path)
    {meshes}           the folder of cylinder.stl, cone.stl, gate.stl (absolute path)
    {silo_case}        hopperflow's case file of this silo (bench/liggghts/silo/
                       hopperflow-silo.toml, absolute path)
    {case}             case.json in the run folder: geometry, materials and protocol
    {particles}        the number of spheres in the packing
    {settle_steps} {transient_steps} {window_steps} {dt} {skin} {delete_below}
The template is filled with Python's str.format (double any literal brace) and split like a
shell command line (no shell runs it). The default, DEFAULT_HOPPERFLOW_CMD below, is
hopperflow's silo bench on {silo_case} started from {packing}: the same STL walls
(cylinder.stl and cone.stl, read as they are; the gate is hopperflow's polygon around the
orifice), materials, time step and deletion plane, and the same packing, placed at rest. Two
things differ: the packing settles on the closed gate until hopperflow's criterion holds (mean
kinetic energy below 1e-9 J per sphere, after at least 0.05 s) instead of for --settle-steps,
and the window is hopperflow's fixed one, 0.05-0.08 s after the opening, that is the defaults
of --transient-steps and --window-steps (the script says so when they are changed). hopperflow
caches the settled bed (out/bench-cache/ under the current folder) under a name that stands
for the case and the packing's bytes, so a rerun on the same packing times the window again
without settling. A template without {packing} is flagged as such in the output.

Ratio printed: LIGGGHTS ns / hopperflow ns (above 1 means hopperflow is faster).

Usage:
  python3 bench/side_by_side_silo.py                    # 20 000 spheres; LIGGGHTS 7-10 min
  python3 bench/side_by_side_silo.py --particles 5000 --settle-steps 20000   # a quick look
  python3 bench/side_by_side_silo.py --liggghts-log L   # reuse an existing LIGGGHTS log
  python3 bench/side_by_side_silo.py --hopperflow-cmd '{hopperflow} bench --case silo ...'
Both codes run on one thread at nice 10 (the machine is shared).
"""
import argparse
import json
import os
import shlex
import shutil
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
SILO_DIR = os.path.join(HERE, "liggghts", "silo")
MESHES = os.path.join(SILO_DIR, "meshes")
HOPPERFLOW = os.path.join(REPO, "target", "release", "hopperflow")
sys.path.insert(0, SILO_DIR)
sys.path.insert(0, HERE)
sys.dont_write_bytecode = True  # no __pycache__ in the source tree
import make_packing  # noqa: E402  (bench/liggghts/silo)
from side_by_side import (  # noqa: E402  (bench/)
    find_liggghts, load_average, log_wall_seconds, niced, scan_log)
import packing_to_data  # noqa: E402

TIME_STEP = 1.5e-6  # Δt [s]; must match in.silo
DELETE_BELOW = packing_to_data.DELETE_BELOW  # [m]; spheres below are deleted
# Mass of one benchmark sphere (M1, d = 4 mm) [kg], for the discharge rate in kg/s.
SPHERE_MASS = 2500.0 * 3.141592653589793 / 6.0 * 0.004 ** 3
# hopperflow's case file of this silo: the STL walls of meshes/, in.silo's materials and Δt.
SILO_CASE = os.path.join(SILO_DIR, "hopperflow-silo.toml")
# The command the hook runs when --hopperflow-cmd is not given: hopperflow's silo bench on its
# case file of this silo, started from the shared packing, timed 0.05-0.08 s after the opening.
DEFAULT_HOPPERFLOW_CMD = ("{hopperflow} bench --case silo --case-file {silo_case} "
                          "--packing {packing} --threads 1 --json")
# hopperflow's silo window [steps of Δt]: 0.05 s after the opening, then 0.03 s timed.
HOPPERFLOW_TRANSIENT_STEPS = 33333
HOPPERFLOW_WINDOW_STEPS = 20000

# in.silo's thermo columns, by position: step, atoms, translational KE [J], spheres with the
# centre above the orifice plane; the settling run adds Δt/t_Rayleigh and Δt/t_Hertz.
COLUMNS = ("step", "atoms", "ke", "in_silo")


class LogError(Exception):
    """The LIGGGHTS log lacks a part that the measurement needs."""


def parse_liggghts_log(text):
    """Extracts the timing figures from a log written by in.silo.

    Returns a dict with window_loop_s [s], window_steps, window_mean_atoms,
    ns_per_particle_step [ns], atoms_window_begin, atoms_window_end, in_silo_window_begin,
    in_silo_window_end, window_outflow_per_s (spheres leaving the silo per second over the
    window) and window_outflow_kg_per_s, settle_steps, settled_ke_j [J], gate_open_step,
    dt_over_rayleigh (from check/timestep/gran, None if absent), loop_total_s [s], log_wall_s
    [s] (first run set-up to last run finish, from the log's time stamps) and
    window_sections_ns (LIGGGHTS' timing table for the window per particle-step [ns]).
    """
    rows, markers, loops, sections = scan_log(text, COLUMNS)
    for name in ("BENCH_SETTLED", "BENCH_GATE_OPEN", "BENCH_WINDOW_BEGIN", "BENCH_WINDOW_END"):
        if name not in markers:
            raise LogError("log has no %s line: the run did not reach it" % name)
    begin, end = markers["BENCH_WINDOW_BEGIN"][0], markers["BENCH_WINDOW_END"][0]
    window_loops = [lp for lp in loops if begin < lp[0] < end]
    window_rows = [r for (i, r, _) in rows if begin < i < end]
    if len(window_loops) != 1 or len(window_rows) < 2:
        raise LogError("the timed window has no complete run in the log")
    loop_line, loop_s, steps = window_loops[0]
    atoms = [r["atoms"] for r in window_rows]
    # Trapezoidal mean over equally spaced rows (the first and last rows are the run's ends;
    # a window that is not a multiple of the thermo interval has a shorter last interval).
    t = [r["step"] for r in window_rows]
    mean_atoms = sum((t[k + 1] - t[k]) * (atoms[k] + atoms[k + 1]) / 2.0
                     for k in range(len(t) - 1)) / (t[-1] - t[0])
    ns = loop_s / (steps * mean_atoms) * 1e9
    window_sections = {name: secs / (steps * mean_atoms) * 1e9
                       for (i, name, secs) in sections if loop_line < i < end}
    left = window_rows[0]["in_silo"] - window_rows[-1]["in_silo"]
    window_time = (t[-1] - t[0]) * TIME_STEP
    # Δt / t_Rayleigh from the settling run's check/timestep/gran column, where present.
    settled_line = markers["BENCH_SETTLED"][0]
    checks = [v[4] for (i, _, v) in rows if i < settled_line and len(v) >= 6 and v[4] > 0]
    wall = log_wall_seconds(text)
    settled = markers["BENCH_SETTLED"][1]
    return {
        "window_loop_s": loop_s,
        "window_steps": steps,
        "window_mean_atoms": mean_atoms,
        "ns_per_particle_step": ns,
        "atoms_window_begin": int(window_rows[0]["atoms"]),
        "atoms_window_end": int(window_rows[-1]["atoms"]),
        "in_silo_window_begin": int(window_rows[0]["in_silo"]),
        "in_silo_window_end": int(window_rows[-1]["in_silo"]),
        "window_outflow_per_s": left / window_time,
        "window_outflow_kg_per_s": left * SPHERE_MASS / window_time,
        "settle_steps": int(settled[2]),
        "settled_atoms": int(settled[4]),
        "settled_ke_j": float(settled[6]),
        "gate_open_step": int(markers["BENCH_GATE_OPEN"][1][2]),
        "dt_over_rayleigh": checks[-1] if checks else None,
        "loop_total_s": sum(lp[1] for lp in loops),
        "log_wall_s": wall,
        "window_sections_ns": window_sections,
    }


def prepare(out_dir, args):
    """Puts the packing CSV (given, or made here), its LIGGGHTS data file and case.json into
    out_dir; returns the absolute paths (packing CSV, data file, case.json)."""
    packing = os.path.join(out_dir, "packing.csv")
    if args.packing:
        if os.path.abspath(args.packing) != packing:
            shutil.copyfile(args.packing, packing)
    else:
        centres, radius = make_packing.packing(args.particles, 1.1, 0.9, 0.1, args.seed)
        make_packing.write_csv(packing, centres, radius, "M1")
    spheres = packing_to_data.read_packing(packing)
    data = os.path.join(out_dir, "packing.data")
    packing_to_data.write_data(data, spheres, packing)
    case = os.path.join(out_dir, "case.json")
    with open(case, "w") as f:
        json.dump(case_description(packing, len(spheres), args), f, indent=2)
        f.write("\n")
    return packing, data, case


def case_description(packing, n, args):
    """What both codes run, for the hopperflow hook ({case}); in.silo holds the same numbers."""
    return {
        "name": "reduced benchmark silo (Dosta et al. 2024, large orifice, M1)",
        "frame": "orifice plane z = 0, axis on z, SI units",
        "meshes": {"cylinder": os.path.join(MESHES, "cylinder.stl"),
                   "cone": os.path.join(MESHES, "cone.stl"),
                   "gate": os.path.join(MESHES, "gate.stl")},
        "packing": packing,
        "particles": n,
        "materials": {"M1": {"E": 1.0e9, "nu": 0.2, "density": 2500.0},
                      "steel": {"E": 210.0e9, "nu": 0.2, "density": 7200.0}},
        "pairs": {"M1-M1": {"restitution": 0.5, "friction": 0.3},
                  "M1-steel": {"restitution": 0.4, "friction": 0.2}},
        "walls_material": "steel",
        "contact": "Hertz normal with restitution damping; Mindlin tangential with history and "
                   "Coulomb limit; no rolling resistance",
        "gravity": [0.0, 0.0, -9.8],
        "dt": TIME_STEP,
        "skin": args.skin,
        "delete_below_z": DELETE_BELOW,
        "protocol": {"settle_steps": args.settle_steps, "gate": "removed after settling",
                     "transient_steps": args.transient_steps,
                     "window_steps": args.window_steps},
    }


def process_cpu_s(pid):
    """User + system CPU seconds of a running process, from /proc (None where absent)."""
    try:
        fields = open("/proc/%d/stat" % pid).read().rsplit(")", 1)[1].split()
        return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")
    except (OSError, ValueError, IndexError):
        return None


def run_liggghts(out_dir, data, args):
    """Runs in.silo on one core in out_dir.

    Returns (log text, wall seconds measured here, CPU seconds of the window or None). The
    window's CPU time is LIGGGHTS' user + system time from the moment its log shows
    BENCH_WINDOW_BEGIN (the log is flushed with the window's first thermo row, at its set-up)
    to its exit (the window is the last run); it is read every 0.2 s. Unlike the loop time it
    does not grow when other work takes the core, so wall / CPU says how contended the
    window was."""
    exe = find_liggghts()
    if exe is None:
        raise FileNotFoundError("no LIGGGHTS executable found (install: apt-get install liggghts)")
    log = os.path.join(out_dir, "log.silo")
    cmd = [exe, "-in", os.path.join(SILO_DIR, "in.silo"), "-log", log,
           "-var", "data", data, "-var", "meshes", MESHES, "-var", "skin", repr(args.skin),
           "-var", "settle_steps", str(args.settle_steps),
           "-var", "transient_steps", str(args.transient_steps),
           "-var", "window_steps", str(args.window_steps)]
    for name, value in args.var:
        cmd += ["-var", name, value]
    env = dict(os.environ, OMP_NUM_THREADS="1")
    if os.path.exists(log):
        os.remove(log)  # a log of an earlier run would show its markers
    start = time.monotonic()
    cpu_begin = None
    with open(os.path.join(out_dir, "screen.out"), "w") as screen:
        proc = subprocess.Popen(cmd, cwd=out_dir, env=env, stdout=screen,
                                stderr=subprocess.STDOUT, preexec_fn=niced)
        seen = 0
        while True:
            try:
                _, status, usage = os.wait4(proc.pid, os.WNOHANG)
            except ChildProcessError:
                raise subprocess.CalledProcessError(-1, cmd)
            if _ == proc.pid:
                break
            if cpu_begin is None and os.path.exists(log):
                with open(log, "rb") as f:
                    f.seek(seen)
                    chunk = f.read()
                if b"\nBENCH_WINDOW_BEGIN" in chunk:
                    cpu_begin = process_cpu_s(proc.pid)
                # Read on from a little before the end, in case the marker is cut in two.
                seen = max(seen, seen + len(chunk) - 64)
            time.sleep(0.2)
        proc.returncode = os.waitstatus_to_exitcode(status)
    if proc.returncode != 0:
        raise subprocess.CalledProcessError(proc.returncode, cmd)
    window_cpu = None
    if cpu_begin is not None:
        window_cpu = usage.ru_utime + usage.ru_stime - cpu_begin
    return open(log).read(), time.monotonic() - start, window_cpu


def run_hopperflow(template, fields):
    """Runs the hopperflow command on one thread.

    Returns (JSON object or None, message): None with the reason when the binary is missing,
    the command fails (e.g. hopperflow has no silo bench yet) or prints no JSON object.
    """
    try:
        cmd = shlex.split(template.format(**fields))
    except (KeyError, IndexError, ValueError) as err:
        return None, "--hopperflow-cmd: bad template (%s)" % err
    if cmd and cmd[0] == HOPPERFLOW and not os.path.exists(HOPPERFLOW):
        return None, ("not built (%s missing): build it with `cargo build --release -p "
                      "hopperflow`, then rerun this script" % os.path.relpath(HOPPERFLOW, REPO))
    env = dict(os.environ, RAYON_NUM_THREADS="1", OMP_NUM_THREADS="1")
    try:
        done = subprocess.run(cmd, env=env, capture_output=True, text=True, preexec_fn=niced)
    except OSError as err:
        return None, "`%s` could not start: %s" % (" ".join(cmd), err)
    shown = " ".join(os.path.basename(c) if c == HOPPERFLOW else c for c in cmd)
    if done.returncode != 0:
        tail = " ".join(done.stderr.strip().splitlines()[-3:])
        return None, "`%s` failed (exit %d): %s" % (shown, done.returncode, tail)
    out = done.stdout
    try:
        return json.loads(out[out.index("{"):out.rindex("}") + 1]), ""
    except ValueError:
        return None, "`%s` printed no JSON object" % shown


def print_breakdown(lig, hf):
    """Where each code's time went, per particle-step over the window, from each code's own
    timing table. LIGGGHTS' Pair is sphere pairs only; its mesh walls (fix wall/gran),
    integration and gravity are in Other. hopperflow's forces hold pairs and walls."""
    sections = (lig or {}).get("window_sections_ns") or {}
    if sections:
        names = [n for n in ("pair", "neigh", "comm", "outpt", "modify", "other") if n in sections]
        print("breakdown  : LIGGGHTS   %s  (ns per particle-step; walls and integration are in "
              "other)" % ", ".join("%s %.1f" % (n, sections[n]) for n in names))
    phases = hf.get("phases") if isinstance(hf, dict) else None
    if isinstance(phases, dict):
        parts = [("forces", "forces_ns"), ("integrate", "integrate_ns"),
                 ("neighbour", "neighbour_ns"), ("other", "other_ns")]
        print("             hopperflow %s  (ns per particle-step; forces hold pairs and walls)"
              % ", ".join("%s %.1f" % (n, phases[k]) for n, k in parts if k in phases))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--particles", type=int, default=20000,
                    help="spheres in the packing made here (default 20000)")
    ap.add_argument("--seed", type=int, default=1, help="seed of the packing made here")
    ap.add_argument("--packing", help="start from this packing CSV instead of making one")
    ap.add_argument("--settle-steps", type=int, default=100000,
                    help="steps on the closed gate (default 100000 = 0.15 s)")
    ap.add_argument("--transient-steps", type=int, default=33333,
                    help="untimed steps after the gate is removed (default 33333 = 0.05 s)")
    ap.add_argument("--window-steps", type=int, default=20000,
                    help="timed steps (default 20000 = 0.03 s)")
    ap.add_argument("--skin", type=float, default=0.0004,
                    help="Verlet skin [m] (default 0.0004 = 0.1 d, hopperflow's)")
    ap.add_argument("--liggghts-log", help="parse this LIGGGHTS log instead of running LIGGGHTS")
    ap.add_argument("--skip-liggghts", action="store_true", help="do not run or parse LIGGGHTS")
    ap.add_argument("--keep", help="folder for the packing, the LIGGGHTS log and screen output "
                    "(default: a temporary folder)")
    ap.add_argument("--var", nargs=2, action="append", default=[], metavar=("NAME", "VALUE"),
                    help="pass -var NAME VALUE to LIGGGHTS (e.g. --var thermo_every 1000)")
    ap.add_argument("--hopperflow-cmd", default=DEFAULT_HOPPERFLOW_CMD,
                    help="hopperflow command template (see the module docstring; default: %(default)s)")
    ap.add_argument("--skip-hopperflow", action="store_true", help="do not run hopperflow")
    ap.add_argument("--json", action="store_true", help="print one JSON object at the end")
    args = ap.parse_args()

    out = args.keep or tempfile.mkdtemp(prefix="liggghts_silo_")
    os.makedirs(out, exist_ok=True)
    out = os.path.abspath(out)
    result = {"loadavg_before": load_average()}
    packing, data, case = prepare(out, args)
    lig = None
    if not args.skip_liggghts:
        if args.liggghts_log:
            lig = parse_liggghts_log(open(args.liggghts_log).read())
        else:
            print("running LIGGGHTS (one core); packing, log and screen output in %s" % out,
                  flush=True)
            text, wall, window_cpu = run_liggghts(out, data, args)
            lig = parse_liggghts_log(text)
            lig["measured_wall_s"] = wall
            if window_cpu:
                lig["window_cpu_s"] = window_cpu
                lig["cpu_ns_per_particle_step"] = (window_cpu / (lig["window_steps"]
                                                   * lig["window_mean_atoms"]) * 1e9)
        result["liggghts"] = lig
        print("LIGGGHTS   : %.1f ns/particle-step  (loop %.2f s, %d steps, mean %.1f atoms)"
              % (lig["ns_per_particle_step"], lig["window_loop_s"], lig["window_steps"],
                 lig["window_mean_atoms"]))
        print("             window: %d -> %d atoms, %d -> %d in the silo; %.0f spheres/s "
              "(%.2f kg/s) leave the silo" % (
                  lig["atoms_window_begin"], lig["atoms_window_end"],
                  lig["in_silo_window_begin"], lig["in_silo_window_end"],
                  lig["window_outflow_per_s"], lig["window_outflow_kg_per_s"]))
        if lig.get("window_cpu_s"):
            print("             CPU time over the window %.2f s (%.1f ns/particle-step); "
                  "loop / CPU = %.2f (above ~1.05: the core was shared)"
                  % (lig["window_cpu_s"], lig["cpu_ns_per_particle_step"],
                     lig["window_loop_s"] / lig["window_cpu_s"]))
        if lig["in_silo_window_end"] >= lig["in_silo_window_begin"]:
            print("caution    : no sphere left the silo during the window: it is not a discharge")
        print("             settled %d steps (KE %.3g J, %d atoms)%s" % (
            lig["settle_steps"], lig["settled_ke_j"], lig["settled_atoms"],
            "; dt = %.3f t_Rayleigh" % lig["dt_over_rayleigh"] if lig["dt_over_rayleigh"] else ""))
        wall = lig.get("measured_wall_s") or lig["log_wall_s"]
        if wall is not None:
            print("             whole case wall time %.0f s" % wall)

    if not args.skip_hopperflow:
        fields = {"hopperflow": HOPPERFLOW, "packing": packing, "meshes": MESHES,
                  "silo_case": SILO_CASE, "case": case,
                  "particles": len(packing_to_data.read_packing(packing)),
                  "settle_steps": args.settle_steps, "transient_steps": args.transient_steps,
                  "window_steps": args.window_steps, "dt": TIME_STEP, "skin": args.skin,
                  "delete_below": DELETE_BELOW}
        hf, why = run_hopperflow(args.hopperflow_cmd, fields)
        if hf is None:
            print("hopperflow : %s" % why)
        else:
            result["hopperflow"] = hf
            if "{packing}" not in args.hopperflow_cmd:
                print("caution    : the hopperflow command reads no {packing}: hopperflow timed "
                      "its own fill of the silo, not the shared packing")
            window = (args.transient_steps, args.window_steps)
            if (args.hopperflow_cmd == DEFAULT_HOPPERFLOW_CMD
                    and window != (HOPPERFLOW_TRANSIENT_STEPS, HOPPERFLOW_WINDOW_STEPS)):
                print("caution    : hopperflow's bench timed its own window (%d steps from %d "
                      "after the opening), not --transient-steps %d --window-steps %d"
                      % ((HOPPERFLOW_WINDOW_STEPS, HOPPERFLOW_TRANSIENT_STEPS) + window))
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
    if lig is not None and "hopperflow" not in result:
        print_breakdown(lig, None)
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
