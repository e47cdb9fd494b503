#!/usr/bin/env python3
"""A/B timing of two hopperflow builds on one benchmark, alternating.

This machine's speed drifts by up to 15 % within minutes (docs/performance.md), more than
most changes worth measuring, so two builds are never timed one after the other in blocks.
The builds alternate in ABBA order, round after round, so that a slow spell falls on both,
and each round gives a ratio A/B of their wall time per particle-step (above 1: B is
faster). The median ratio, with the range of the rounds, is the result; a difference
smaller than that range is noise.

    python3 bench/ab.py OLD_BINARY NEW_BINARY [--runs 4] [--case hopper] [--threads 1]
    python3 bench/ab.py OLD NEW --case scaling -- --particles 10000   # extra bench options

Each build keeps its own hopper cache (out/bench-cache/ab-a.bin and ab-b.bin), since
checkpoint formats may differ between builds. Only `hopperflow bench` is run. When the two
builds' runs hold different contacts per particle (more than 1 % apart) a warning says so:
builds whose results differ in any bit follow different trajectories in the hopper window.
The ratio per contact (each build's ns per particle-step over its contacts per particle)
is then printed as well: the nearest to like for like that two trajectories allow.

    python3 bench/ab.py OLD NEW --start out/bench-cache/hopper.bin   # one settled hopper for both

`--start CACHE` copies one settled hopper into both builds' caches before the first round,
so that both windows start from the same state (the builds must read the same checkpoint
format); without it, each build fills and settles its own hopper, and builds whose bits
differ then start from different packings as well.
"""

import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys


def bench(binary, case, threads, cache, extra):
    """One `bench --json` run of `binary`: its JSON result (the first, if several)."""
    cmd = [binary, "bench", "--case", case, "--threads", str(threads), "--json"]
    if case == "hopper":
        cmd += ["--cache", cache]
    cmd += extra
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    result = json.loads(out)
    return result[0] if isinstance(result, list) else result


def median_and_range(values):
    return statistics.median(values), min(values), max(values)


def main():
    parser = argparse.ArgumentParser(
        description=__doc__.split("\n\n")[0],
        epilog="Options after -- are passed to `hopperflow bench`.",
    )
    parser.add_argument("a", help="build A (the reference), a hopperflow binary")
    parser.add_argument("b", help="build B (the candidate), a hopperflow binary")
    parser.add_argument("--runs", type=int, default=4, help="rounds of one A and one B run (default 4)")
    parser.add_argument("--case", default="hopper", choices=["bed", "hopper", "scaling"])
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument("--cache-dir", default="out/bench-cache", help="where the two hopper caches live")
    parser.add_argument(
        "--start",
        metavar="CACHE",
        help="a settled hopper (a `bench --case hopper` cache) copied into both builds' caches first",
    )
    parser.add_argument("--json", action="store_true", help="print JSON instead of a table")
    argv = sys.argv[1:]
    # Everything after `--` goes to `hopperflow bench` unchanged.
    extra = argv[argv.index("--") + 1 :] if "--" in argv else []
    argv = argv[: argv.index("--")] if "--" in argv else argv
    args = parser.parse_args(argv)
    args.extra = extra
    if args.runs < 1:
        parser.error(f"--runs must be at least 1, got {args.runs}")
    for name in (args.a, args.b):
        if not (os.path.isfile(name) and os.access(name, os.X_OK)):
            parser.error(f"{name}: not an executable file")
    os.makedirs(args.cache_dir, exist_ok=True)
    caches = {
        "a": os.path.join(args.cache_dir, "ab-a.bin"),
        "b": os.path.join(args.cache_dir, "ab-b.bin"),
    }
    binaries = {"a": args.a, "b": args.b}
    if args.start is not None:
        if args.case != "hopper":
            parser.error("--start applies to --case hopper only")
        if not os.path.isfile(args.start):
            parser.error(f"--start {args.start}: no such file")
        for cache in caches.values():
            if os.path.abspath(cache) != os.path.abspath(args.start):
                shutil.copyfile(args.start, cache)

    load_before = os.getloadavg()[0]
    rounds = []
    for r in range(args.runs):
        # ABBA: A first in even rounds, B first in odd ones, so a drift within a round
        # favours neither build over the whole comparison.
        order = ("a", "b") if r % 2 == 0 else ("b", "a")
        got = {}
        for side in order:
            got[side] = bench(binaries[side], args.case, args.threads, caches[side], args.extra)
        ns = {side: got[side]["ns_per_particle_step"] for side in got}
        rounds.append(
            {
                "order": "".join(order).upper(),
                "a_ns": ns["a"],
                "b_ns": ns["b"],
                "ratio_a_over_b": ns["a"] / ns["b"],
                "a_contacts_per_particle": got["a"].get("contacts_per_particle"),
                "b_contacts_per_particle": got["b"].get("contacts_per_particle"),
                "a_phases": got["a"].get("phases"),
                "b_phases": got["b"].get("phases"),
            }
        )
        if not args.json:
            print(
                f"round {r + 1} ({rounds[-1]['order']}): A {ns['a']:.1f} ns, B {ns['b']:.1f} ns,"
                f" A/B {rounds[-1]['ratio_a_over_b']:.3f}",
                flush=True,
            )
    load_after = os.getloadavg()[0]

    ratio = median_and_range([x["ratio_a_over_b"] for x in rounds])
    a_ns = median_and_range([x["a_ns"] for x in rounds])
    b_ns = median_and_range([x["b_ns"] for x in rounds])
    # Cost per particle-step grows with the contacts per particle. Two builds whose results
    # differ in any bit follow different trajectories from the same cached hopper, and their
    # windows need not hold the same number of contacts (such builds can differ by 5 %):
    # the ratio then mixes speed with work.
    contacts = {
        side: statistics.median(
            x[f"{side}_contacts_per_particle"] or 0.0 for x in rounds
        )
        for side in ("a", "b")
    }
    work_differs = (
        contacts["a"] > 0.0
        and abs(contacts["a"] - contacts["b"]) > 0.01 * contacts["a"]
    )
    # ns per contact, round by round: the cost per particle-step follows the contacts, so
    # this ratio compares speed on different work.
    per_contact = (
        median_and_range(
            [
                (x["a_ns"] / x["a_contacts_per_particle"])
                / (x["b_ns"] / x["b_contacts_per_particle"])
                for x in rounds
            ]
        )
        if all(x["a_contacts_per_particle"] and x["b_contacts_per_particle"] for x in rounds)
        else None
    )
    summary = {
        "case": args.case,
        "threads": args.threads,
        "runs": args.runs,
        "a": args.a,
        "b": args.b,
        "a_ns_median": a_ns[0],
        "b_ns_median": b_ns[0],
        "ratio_median": ratio[0],
        "ratio_min": ratio[1],
        "ratio_max": ratio[2],
        "a_contacts_per_particle": contacts["a"],
        "b_contacts_per_particle": contacts["b"],
        "work_differs": work_differs,
        "ratio_per_contact_median": per_contact[0] if per_contact else None,
        "ratio_per_contact_min": per_contact[1] if per_contact else None,
        "ratio_per_contact_max": per_contact[2] if per_contact else None,
        "start": args.start,
        "loadavg_before": load_before,
        "loadavg_after": load_after,
        "rounds": rounds,
    }
    if args.json:
        print(json.dumps(summary, indent=2))
        return 0
    print(
        f"A median {a_ns[0]:.1f} ns ({a_ns[1]:.1f}–{a_ns[2]:.1f}), "
        f"B median {b_ns[0]:.1f} ns ({b_ns[1]:.1f}–{b_ns[2]:.1f}) per particle-step"
    )
    print(
        f"A/B median {ratio[0]:.3f} (rounds {ratio[1]:.3f}–{ratio[2]:.3f}); above 1: B is faster."
    )
    if ratio[1] <= 1.0 <= ratio[2]:
        print("The rounds fall on both sides of 1: no difference beyond the machine's noise.")
    if work_differs:
        print(
            f"Warning: the builds' runs hold different work, {contacts['a']:.3f} (A) and"
            f" {contacts['b']:.3f} (B) contacts per particle: their trajectories differ, so the"
            " ratio is not like for like. `--case bed` or `--case scaling` keeps the contacts."
        )
        if per_contact:
            print(
                f"Per contact, A/B median {per_contact[0]:.3f}"
                f" (rounds {per_contact[1]:.3f}–{per_contact[2]:.3f}): the ratio of ns per"
                " particle-step over contacts per particle."
            )
    print(f"load average (1 min) before/after: {load_before:.2f} / {load_after:.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
