#!/usr/bin/env python3
"""Writes a loose initial packing of the reduced benchmark silo as a packing CSV.

The packing CSV is the file both codes start from (bench/README.md, "The benchmark silo"):
a header line `x,y,z,radius,material`, then one sphere per line: centre [m], radius [m] and
the material's name (`M1`, `M2`), in the silo's frame (orifice plane z = 0, axis on z). The
spheres start at rest. Any packing in this format will do, e.g. a settled one written by
either code; this script makes one when none is at hand.

The packing is a simple cubic lattice of spacing `--spacing` diameters (default 1.1, solid
fraction about 0.39) with a column on the axis, every site moved by a random offset of at
most `--jitter` x (spacing - 1) d / 2 along each axis (default 0.9), so that two spheres are
at least spacing x d - 2 x that offset >= d apart: nothing overlaps. Sites are taken layer
by layer from the gate upwards; the top layer is a random subset. Every sphere, wherever its
offset puts it, keeps `--clearance` diameters (default 0.1) from the gate, the cone and the
cylinder, and stays below the top of the cylinder. Deterministic for a given --seed.

Usage: make_packing.py [-n 20000] [--out packing.csv] [--seed 1] [--spacing 1.1]
"""
import argparse
import math
import os
import random

# Geometry of the reduced silo [m] (the same numbers as make_silo_meshes.py).
CYLINDER_RADIUS = 0.100
ORIFICE_RADIUS = 0.030
CONE_TOP = 0.070
CYLINDER_TOP = 0.240
# The benchmark's spheres: d = 4 mm.
DIAMETER = 0.004


def gap_to_walls(x, y, z):
    """A lower bound [m] on the distance from a point inside the silo to the walls (gate,
    cone, cylinder, and the plane of the cylinder's top); negative outside. Below the
    junction the cone's distance is taken to its whole line r = ORIFICE_RADIUS + z, never
    more than the distance to the cone itself; above it the cylinder is nearer than the cone."""
    r = math.hypot(x, y)
    gaps = [z, CYLINDER_RADIUS - r, CYLINDER_TOP - z]
    if z <= CONE_TOP:
        gaps.append((ORIFICE_RADIUS + z - r) / math.sqrt(2.0))
    return min(gaps)


def packing(n, spacing, jitter, clearance, seed):
    """n sphere centres [m] of a jittered lattice inside the silo, from the gate upwards."""
    rng = random.Random(seed)
    a = spacing * DIAMETER
    offset = jitter * (a - DIAMETER) / 2.0  # largest offset along each axis
    radius = DIAMETER / 2.0
    # A site is used only if every offset keeps the sphere inside: the centre may move by up
    # to offset*sqrt(3) in any direction.
    margin = radius + clearance * DIAMETER + offset * math.sqrt(3.0)
    half = int(CYLINDER_RADIUS / a) + 1
    centres = []
    k = 0
    while len(centres) < n:
        z = margin + k * a
        if z > CYLINDER_TOP - margin:
            raise SystemExit("error: only %d spheres fit below the top of the cylinder at "
                             "spacing %g d; lower --spacing or -n" % (len(centres), spacing))
        layer = [(i * a, j * a, z) for i in range(-half, half + 1) for j in range(-half, half + 1)
                 if gap_to_walls(i * a, j * a, z) >= margin]
        if len(centres) + len(layer) > n:
            layer = rng.sample(layer, n - len(centres))
            layer.sort(key=lambda p: (p[1], p[0]))
        centres += layer
        k += 1
    return [(x + rng.uniform(-offset, offset), y + rng.uniform(-offset, offset),
             z + rng.uniform(-offset, offset)) for (x, y, z) in centres], radius


def write_csv(path, centres, radius, material):
    """Writes the packing CSV atomically; coordinates as the shortest exact decimals."""
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        f.write("x,y,z,radius,material\n")
        for (x, y, z) in centres:
            f.write("%r,%r,%r,%r,%s\n" % (round(x, 12) + 0.0, round(y, 12) + 0.0,
                                          round(z, 12) + 0.0, radius, material))
    os.replace(tmp, path)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("-n", "--particles", type=int, default=20000, help="spheres (default 20000)")
    ap.add_argument("--out", default="packing.csv", help="output CSV (default packing.csv)")
    ap.add_argument("--seed", type=int, default=1, help="random seed (default 1)")
    ap.add_argument("--spacing", type=float, default=1.1,
                    help="lattice spacing in diameters, > 1 (default 1.1)")
    ap.add_argument("--jitter", type=float, default=0.9,
                    help="largest offset as a fraction of (spacing - 1) d / 2 (default 0.9)")
    ap.add_argument("--clearance", type=float, default=0.1,
                    help="least gap to the walls in diameters (default 0.1)")
    ap.add_argument("--material", default="M1", help="material name (default M1)")
    args = ap.parse_args()
    if args.spacing <= 1.0 or not 0.0 <= args.jitter <= 1.0 or args.particles < 1:
        ap.error("need --spacing > 1, 0 <= --jitter <= 1 and -n >= 1")
    centres, radius = packing(args.particles, args.spacing, args.jitter, args.clearance,
                              args.seed)
    write_csv(args.out, centres, radius, args.material)
    top = max(z for (_, _, z) in centres) + radius
    print("%s: %d spheres of d = %g m, %s, up to z = %.4f m"
          % (args.out, len(centres), 2 * radius, args.material, top))


if __name__ == "__main__":
    main()
