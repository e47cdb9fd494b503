#!/usr/bin/env python3
"""Writes the ASCII STL surfaces that in.hopper reads (the base case, docs/physics.md §5).

All coordinates are in metres. x is across the hopper (walls at x = -L/2 and +L/2), y is the
slab normal (front/back walls at y = 0 and y = Z), z is vertical with the outlet plane at z = 0.
Only the flat bottom plates need a mesh (they are finite rectangles with the outlet between
them); the side, front and back walls are infinite planes (LIGGGHTS primitives) and the gate
is a primitive z-plane that is removed when the discharge starts.

Usage: make_meshes.py [output folder]   (default: meshes/ next to this file)
"""
import os
import sys

# Geometry of the base case (paper Table 1; docs/physics.md §1.1 and §5) [m].
HOPPER_WIDTH = 0.100  # L
SLAB_THICKNESS = 3.03e-3  # Z = 1.01 d
OUTLET_WIDTH = 0.030  # D
PARTICLE_DIAMETER = 3.0e-3  # d
# The plates overhang the slab by this much in y so that no particle can meet their y-edges;
# the front/back walls are separate planes, so the overhang changes nothing physical [m].
OVERHANG = 2.0e-4
# Particles are deleted 5 d below the outlet plane (docs/physics.md §5, "Removal") [m].
SINK_DEPTH = 5.0 * PARTICLE_DIAMETER


def rectangle(x0, x1, y0, y1, z):
    """Two triangles covering [x0,x1] x [y0,y1] at height z, normal +z (counter-clockwise)."""
    a, b, c, d = (x0, y0, z), (x1, y0, z), (x1, y1, z), (x0, y1, z)
    return [(a, b, c), (a, c, d)]


def write_stl(path, name, triangles):
    """Writes an ASCII STL atomically (temporary file in the same folder, then rename)."""
    lines = ["solid %s" % name]
    for tri in triangles:
        lines.append("  facet normal 0 0 1")
        lines.append("    outer loop")
        for v in tri:
            lines.append("      vertex %.9e %.9e %.9e" % v)
        lines.append("    endloop")
        lines.append("  endfacet")
    lines.append("endsolid %s" % name)
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        f.write("\n".join(lines) + "\n")
    os.replace(tmp, path)


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(here, "meshes")
    os.makedirs(out, exist_ok=True)
    half_l, half_d = HOPPER_WIDTH / 2, OUTLET_WIDTH / 2
    y0, y1 = -OVERHANG, SLAB_THICKNESS + OVERHANG
    # Flat bottom (alpha = 90 deg): two plates from the side walls to the outlet edges.
    plates = rectangle(-half_l, -half_d, y0, y1, 0.0) + rectangle(half_d, half_l, y0, y1, 0.0)
    write_stl(os.path.join(out, "bottom_plates.stl"), "bottom_plates", plates)
    # The outlet opening itself: a counting surface for fix massflow/mesh, not a wall.
    write_stl(os.path.join(out, "outlet.stl"), "outlet", rectangle(-half_d, half_d, y0, y1, 0.0))
    # The sink 5 d below the outlet: particles crossing it are deleted.
    write_stl(os.path.join(out, "sink.stl"), "sink", rectangle(-half_l, half_l, y0, y1, -SINK_DEPTH))


if __name__ == "__main__":
    main()
