#!/usr/bin/env python3
"""Writes a packing CSV of N equal spheres on a square lattice inside a cylinder.

The spheres stand in layers of a square lattice 1.02 d apart (a 2 % gap), each centre
jittered by at most 10 µm so that no column is exactly vertical, from the floor z = 0 up;
each layer holds the lattice points at least 0.6 d inside the cylinder's radius. The
lattice is loose (solid fraction 0.49), so a run that starts from it
(`hopperflow run CASE --packing FILE`) collapses it into a settled bed. It is there to
start large silos in minutes where a fill would take hours: the memory figures of
docs/performance.md ("Memory of a silo run") start from it.

Usage: python3 bench/lattice_packing.py N RADIUS DIAMETER OUT.csv [SEED]
(N spheres, RADIUS and DIAMETER in metres.)
"""

import random
import sys


def lattice(count, radius, diameter, seed):
    """The centres (x, y, z) [m] of `count` spheres, layer by layer."""
    spacing = 1.02 * diameter
    reach = radius - 0.6 * diameter
    if reach <= 0.0:
        raise ValueError(f"RADIUS {radius} m holds no sphere of {diameter} m")
    m = int(reach / spacing)
    layer = [
        (i * spacing, j * spacing)
        for i in range(-m, m + 1)
        for j in range(-m, m + 1)
        if (i * spacing) ** 2 + (j * spacing) ** 2 <= reach**2
    ]
    rng = random.Random(seed)
    jitter = 1.0e-5
    for k in range(count):
        x, y = layer[k % len(layer)]
        z = (0.5 + k // len(layer)) * spacing
        yield (x + rng.uniform(-jitter, jitter), y + rng.uniform(-jitter, jitter), z)


def main(argv):
    if len(argv) not in (5, 6):
        sys.exit(__doc__)
    try:
        count, radius, diameter = int(argv[1]), float(argv[2]), float(argv[3])
        seed = int(argv[5]) if len(argv) == 6 else 1
    except ValueError as e:
        sys.exit(f"error: {e}\n{__doc__}")
    if count < 1 or not diameter > 0.0:
        sys.exit("error: N must be at least 1 and DIAMETER positive")
    with open(argv[4], "w", encoding="ascii") as out:
        out.write("x,y,z,radius\n")
        top = 0.0
        for x, y, z in lattice(count, radius, diameter, seed):
            out.write(f"{x:.7f},{y:.7f},{z:.7f},{0.5 * diameter}\n")
            top = max(top, z)
    print(f"{count} spheres up to z = {top + 0.5 * diameter:.4f} m")


if __name__ == "__main__":
    main(sys.argv)
