#!/usr/bin/env python3
"""Writes the ASCII STL walls of the reduced Janssen silo that in.janssen reads (metres, the
axis on z, the base at z = 0): cylinder.stl, radius 0.02 m from z = 0 to 0.22 m, in 40 layers
of 96 segments; bottom.stl, a closed disc of radius 0.021 m at z = 0 (reaching past the
cylinder, so that its rim lies where no sphere can touch it). Usage: make_janssen_meshes.py,
in the folder where in.janssen runs."""
import math
N=96; R=0.02; H=0.22; RB=0.021
def tri(f,a,b,c):
    f.write("facet normal 0 0 0\n outer loop\n")
    for p in (a,b,c): f.write("  vertex %.12g %.12g %.12g\n"%p)
    f.write(" endloop\nendfacet\n")
ring=lambda r,z:[(r*math.cos(2*math.pi*k/N), r*math.sin(2*math.pi*k/N), z) for k in range(N)]
layers=40
with open('cylinder.stl','w') as f:
    f.write("solid cyl\n")
    for l in range(layers):
        lo=ring(R,H*l/layers); hi=ring(R,H*(l+1)/layers)
        for k in range(N):
            k1=(k+1)%N
            tri(f,lo[k],lo[k1],hi[k1]); tri(f,lo[k],hi[k1],hi[k])
    f.write("endsolid cyl\n")
with open('bottom.stl','w') as f:
    f.write("solid bot\n")
    rim=ring(RB,0.0)
    for k in range(N):
        tri(f,(0.0,0.0,0.0),rim[k],rim[(k+1)%N])
    f.write("endsolid bot\n")
