#!/usr/bin/env python3
"""Converts a packing CSV (x,y,z,radius,material) into the LIGGGHTS data file that in.silo reads.

The data file holds the simulation box and one line per sphere in the layout of LIGGGHTS'
`atom_style granular` (`read_data`): `atom-ID atom-type diameter density x y z`, SI units;
velocities and spins start at zero. The material's name gives the atom type and the density:
in.silo knows M1 (type 1, 2500 kg/m^3) and the steel of the walls (type 2), as the benchmark's
tables give them (bench/README.md, "The benchmark silo").

The box is x, y in [-BOX_HALF_WIDTH, BOX_HALF_WIDTH] and z in [DELETE_BELOW, BOX_TOP], with
fixed (`f`) boundaries: a sphere whose centre falls below z = DELETE_BELOW = -0.02 m (0.02 m
below the orifice plane) leaves the box and LIGGGHTS deletes it at its next neighbour-list
build. This is the benchmark's deletion rule, at no cost per step.

The reverse direction, a settled packing written by in.silo (`-var settled_dump FILE`) back
to a packing CSV, is `--from-dump`.

Usage: packing_to_data.py packing.csv packing.data
       packing_to_data.py --from-dump settled.dump packing.csv
"""
import argparse
import csv
import os
import sys

BOX_HALF_WIDTH = 0.105  # [m]; the cylinder's radius is 0.100 m
DELETE_BELOW = -0.020  # [m]; the box's floor: spheres below it are deleted
BOX_TOP = 0.250  # [m]; the cylinder's top is at 0.240 m
# Material name -> (LIGGGHTS atom type, density [kg/m^3]); type 2 is the walls' steel.
MATERIALS = {"M1": (1, 2500.0)}
FIELDS = ["x", "y", "z", "radius", "material"]


def read_packing(path):
    """The spheres of a packing CSV as (x, y, z, radius, material) tuples."""
    with open(path, newline="") as f:
        reader = csv.reader(f)
        header = [h.strip() for h in next(reader)]
        if header != FIELDS:
            raise SystemExit("error: %s: header is %s, expected %s"
                             % (path, ",".join(header), ",".join(FIELDS)))
        spheres = []
        for line, row in enumerate(reader, start=2):
            if not row:
                continue
            if len(row) != len(FIELDS):
                raise SystemExit("error: %s:%d: %d fields, expected %d"
                                 % (path, line, len(row), len(FIELDS)))
            try:
                x, y, z, r = (float(v) for v in row[:4])
            except ValueError:
                raise SystemExit("error: %s:%d: unreadable number in %s" % (path, line, row))
            spheres.append((x, y, z, r, row[4].strip()))
    return spheres


def write_data(path, spheres, source):
    lines = ["LIGGGHTS data file: the packing %s (bench/liggghts/silo)" % os.path.basename(source),
             "", "%d atoms" % len(spheres), "2 atom types", "",
             "%r %r xlo xhi" % (-BOX_HALF_WIDTH, BOX_HALF_WIDTH),
             "%r %r ylo yhi" % (-BOX_HALF_WIDTH, BOX_HALF_WIDTH),
             "%r %r zlo zhi" % (DELETE_BELOW, BOX_TOP), "", "Atoms", ""]
    for i, (x, y, z, r, material) in enumerate(spheres, start=1):
        if material not in MATERIALS:
            raise SystemExit("error: sphere %d: material %r is not one of in.silo's (%s)"
                             % (i, material, ", ".join(sorted(MATERIALS))))
        if not (abs(x) < BOX_HALF_WIDTH and abs(y) < BOX_HALF_WIDTH
                and DELETE_BELOW <= z < BOX_TOP):
            raise SystemExit("error: sphere %d at (%g, %g, %g) lies outside the box" % (i, x, y, z))
        atom_type, density = MATERIALS[material]
        lines.append("%d %d %r %r %r %r %r" % (i, atom_type, 2.0 * r, density, x, y, z))
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        f.write("\n".join(lines) + "\n")
    os.replace(tmp, path)


def dump_to_packing(dump_path, csv_path):
    """Reads the last snapshot of a LIGGGHTS custom dump with columns id type radius x y z
    (in.silo's settled_dump) and writes it as a packing CSV, by id."""
    with open(dump_path) as f:
        lines = f.read().splitlines()
    starts = [i for i, l in enumerate(lines) if l.startswith("ITEM: ATOMS")]
    if not starts:
        raise SystemExit("error: %s has no ITEM: ATOMS section" % dump_path)
    head = lines[starts[-1]].split()[2:]
    col = {name: head.index(name) for name in ("id", "type", "radius", "x", "y", "z")}
    types = {t: name for name, (t, _) in MATERIALS.items()}
    rows = []
    for l in lines[starts[-1] + 1:]:
        if l.startswith("ITEM:"):
            break
        v = l.split()
        rows.append((int(v[col["id"]]), float(v[col["x"]]), float(v[col["y"]]),
                     float(v[col["z"]]), float(v[col["radius"]]), types[int(v[col["type"]])]))
    rows.sort()
    tmp = csv_path + ".tmp"
    with open(tmp, "w") as f:
        f.write(",".join(FIELDS) + "\n")
        for (_, x, y, z, r, material) in rows:
            f.write("%r,%r,%r,%r,%s\n" % (x, y, z, r, material))
    os.replace(tmp, csv_path)
    return len(rows)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--from-dump", action="store_true",
                    help="convert a settled dump (first argument) to a packing CSV (second)")
    ap.add_argument("source")
    ap.add_argument("target")
    args = ap.parse_args()
    if args.from_dump:
        n = dump_to_packing(args.source, args.target)
        print("%s: %d spheres" % (args.target, n))
    else:
        spheres = read_packing(args.source)
        write_data(args.target, spheres, args.source)
        print("%s: %d atoms" % (args.target, len(spheres)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
