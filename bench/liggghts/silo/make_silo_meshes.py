#!/usr/bin/env python3
"""Writes the ASCII STL walls of the reduced benchmark silo (Dosta et al. 2024, large orifice).

Coordinates in metres: the orifice plane is z = 0 and the silo axis is the z axis.

- cylinder.stl: the side wall, radius 0.1 m, from z = 0.070 m up to z = 0.240 m;
- cone.stl: the hopper at 45 deg to the axis, from the orifice (radius 0.030 m, z = 0) up to
  the cylinder (radius 0.100 m, z = 0.070 m);
- gate.stl: the disc of radius 0.030 m at z = 0 that closes the orifice until the discharge.

Every surface is built from rings of N vertices at the angles 2*pi*k/N, k = 0..N-1. The
cone's top ring is the cylinder's bottom ring and the gate's rim is the cone's bottom ring:
the same coordinates, printed as the same text, so that a reader that welds equal vertices
sees watertight walls. The side walls are cut into layers along the axis, about as tall as a
triangle is wide at the cylinder (2*pi*0.1/N), so that no triangle is a long sliver; the
layers can be set with --layers-cylinder / --layers-cone. The vertex order makes every normal
point into the silo (towards the axis, and up for the gate); the walls are two-sided in both
codes anyway. Coordinates are rounded to 1e-12 m.

Usage: make_silo_meshes.py [--segments N] [--out DIR]   (default: 96, meshes/ next to this file)
"""
import argparse
import math
import os

# Geometry of the reduced silo [m]: the benchmark's large orifice, shifted so that the orifice
# plane is z = 0 (bench/README.md, "The benchmark silo").
CYLINDER_RADIUS = 0.100
ORIFICE_RADIUS = 0.030
CONE_TOP = 0.070  # = CYLINDER_RADIUS - ORIFICE_RADIUS at 45 deg
CYLINDER_TOP = 0.240
DECIMALS = 12


def ring(radius, z, segments):
    """N vertices on a circle at height z, at the angles 2*pi*k/N (k = 0..N-1)."""
    pts = []
    for k in range(segments):
        a = 2.0 * math.pi * k / segments
        pts.append((round(radius * math.cos(a), DECIMALS) + 0.0,
                    round(radius * math.sin(a), DECIMALS) + 0.0,
                    round(z, DECIMALS) + 0.0))
    return pts


def band(lower, upper):
    """Triangles between two rings of equal size, two per segment; their vertex order
    (right-hand rule) makes the normals point towards the axis."""
    n = len(lower)
    tris = []
    for k in range(n):
        k1 = (k + 1) % n
        tris.append((lower[k], upper[k1], lower[k1]))
        tris.append((lower[k], upper[k], upper[k1]))
    return tris


def surface(r0, z0, r1, z1, layers, segments, first=None, last=None):
    """Side of a frustum from (r0, z0) to (r1, z1) in `layers` layers. `first`/`last` replace
    the bottom/top rings so that shared rings are the very same vertices."""
    rings = []
    for j in range(layers + 1):
        if j == 0 and first is not None:
            rings.append(first)
        elif j == layers and last is not None:
            rings.append(last)
        else:
            t = j / layers
            rings.append(ring(r0 + (r1 - r0) * t, z0 + (z1 - z0) * t, segments))
    tris = []
    for j in range(layers):
        tris += band(rings[j], rings[j + 1])
    return tris


def disc(rim, z):
    """A fan from the centre to the rim ring, normals +z (counter-clockwise seen from above)."""
    n = len(rim)
    centre = (0.0, 0.0, round(z, DECIMALS) + 0.0)
    return [(centre, rim[k], rim[(k + 1) % n]) for k in range(n)]


def normal(tri):
    (ax, ay, az), (bx, by, bz), (cx, cy, cz) = tri
    ux, uy, uz = bx - ax, by - ay, bz - az
    vx, vy, vz = cx - ax, cy - ay, cz - az
    nx, ny, nz = uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx
    length = math.sqrt(nx * nx + ny * ny + nz * nz)
    return nx / length, ny / length, nz / length


def fmt(x):
    """Shortest text that reads back to the same double: equal vertices print equally."""
    return repr(float(x))


def write_stl(path, name, triangles):
    """Writes an ASCII STL atomically (temporary file in the same folder, then rename)."""
    lines = ["solid %s" % name]
    for tri in triangles:
        lines.append("  facet normal %s" % " ".join("%.9e" % c for c in normal(tri)))
        lines.append("    outer loop")
        for v in tri:
            lines.append("      vertex %s" % " ".join(fmt(c) for c in v))
        lines.append("    endloop")
        lines.append("  endfacet")
    lines.append("endsolid %s" % name)
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        f.write("\n".join(lines) + "\n")
    os.replace(tmp, path)


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--segments", type=int, default=96, help="vertices per ring (default 96)")
    ap.add_argument("--layers-cylinder", type=int, default=None,
                    help="layers of the cylinder (default: triangles about as tall as wide)")
    ap.add_argument("--layers-cone", type=int, default=None,
                    help="layers of the cone (default: as tall as the cylinder's)")
    ap.add_argument("--out", default=os.path.join(here, "meshes"), help="output folder")
    args = ap.parse_args()
    n = args.segments
    if n < 3:
        ap.error("--segments must be at least 3")
    width = 2.0 * math.pi * CYLINDER_RADIUS / n  # triangle width at the cylinder
    layers_cyl = args.layers_cylinder or max(1, round((CYLINDER_TOP - CONE_TOP) / width))
    layers_cone = args.layers_cone or max(1, round(CONE_TOP / width))

    orifice = ring(ORIFICE_RADIUS, 0.0, n)
    junction = ring(CYLINDER_RADIUS, CONE_TOP, n)
    cone = surface(ORIFICE_RADIUS, 0.0, CYLINDER_RADIUS, CONE_TOP, layers_cone, n,
                   first=orifice, last=junction)
    cylinder = surface(CYLINDER_RADIUS, CONE_TOP, CYLINDER_RADIUS, CYLINDER_TOP, layers_cyl, n,
                       first=junction)
    # The gate's normals point up, into the silo; the fan's rim is the orifice ring.
    gate = disc(orifice, 0.0)

    os.makedirs(args.out, exist_ok=True)
    for name, tris in (("cylinder", cylinder), ("cone", cone), ("gate", gate)):
        write_stl(os.path.join(args.out, name + ".stl"), name, tris)
        print("%s.stl: %d triangles" % (name, len(tris)))


if __name__ == "__main__":
    main()
