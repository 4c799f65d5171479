"""Writes the small 3D Gmsh meshes of tests/gmsh3d.rs into tests/data/ (MSH 4.1, ASCII and
binary) with Gmsh's Python API (`pip install gmsh`; it runs headless).

- cube_tet4 / cube_tet10: the unit cube [0, 1]^3 in 4-node and 10-node tetrahedra (mesh size
  0.45), physical groups "bottom" (surface z = 0), "top" (surface z = 1), "corner" (the point
  at the origin) and "body" (the volume);
- cube_hex8: the unit cube as a transfinite 4 x 4 x 4 grid of 8-node hexahedra, same groups;
- cylinder_tet4 / cylinder_tet10: a disk of radius 0.5 and thickness 0.1 (axis z), groups
  "tread" (the cylindrical surface), "flank" (z = 0) and "body": curved boundary faces, the
  10-node tetrahedra's mid-edge nodes placed on the cylinder by Gmsh.

Each mesh is written as NAME.msh (ASCII) and NAME_bin.msh (binary). Usage:
`/work/venv-peers/bin/python validation/gmsh_meshes3d.py [out_dir]` (default tests/data).
"""

import os
import sys

import gmsh

OUT = sys.argv[1] if len(sys.argv) > 1 else os.path.join(
    os.path.dirname(__file__), "..", "tests", "data"
)


def write(name):
    """Writes the current model as NAME.msh (ASCII) and NAME_bin.msh (binary), MSH 4.1."""
    gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
    for binary, suffix in [(0, ""), (1, "_bin")]:
        gmsh.option.setNumber("Mesh.Binary", binary)
        gmsh.write(os.path.join(OUT, f"{name}{suffix}.msh"))
    types, tags, _ = gmsh.model.mesh.getElements(3)
    n = sum(len(t) for t in tags)
    print(f"{name}: element types {list(types)}, {n} volume elements")


def cube(order, hexes):
    gmsh.model.add("cube")
    gmsh.model.occ.addBox(0, 0, 0, 1, 1, 1)
    gmsh.model.occ.synchronize()
    surfaces = gmsh.model.getEntities(2)
    bottom = top = None
    for dim, tag in surfaces:
        x, y, z = gmsh.model.occ.getCenterOfMass(dim, tag)
        if abs(z) < 1e-9:
            bottom = tag
        elif abs(z - 1) < 1e-9:
            top = tag
    origin = [
        tag
        for dim, tag in gmsh.model.getEntities(0)
        if max(abs(c) for c in gmsh.model.getValue(0, tag, [])) < 1e-9
    ][0]
    gmsh.model.addPhysicalGroup(2, [bottom], name="bottom")
    gmsh.model.addPhysicalGroup(2, [top], name="top")
    gmsh.model.addPhysicalGroup(0, [origin], name="corner")
    gmsh.model.addPhysicalGroup(3, [1], name="body")
    if hexes:
        for dim, tag in gmsh.model.getEntities(1):
            gmsh.model.mesh.setTransfiniteCurve(tag, 5)
        for dim, tag in surfaces:
            gmsh.model.mesh.setTransfiniteSurface(tag)
            gmsh.model.mesh.setRecombine(dim, tag)
        gmsh.model.mesh.setTransfiniteVolume(1)
    else:
        gmsh.model.mesh.setSize(gmsh.model.getEntities(0), 0.45)
    gmsh.model.mesh.generate(3)
    gmsh.model.mesh.setOrder(order)
    name = "cube_hex8" if hexes else f"cube_tet{4 if order == 1 else 10}"
    write(name)
    gmsh.model.remove()


def cylinder(order):
    gmsh.model.add("cylinder")
    gmsh.model.occ.addCylinder(0, 0, 0, 0, 0, 0.1, 0.5)
    gmsh.model.occ.synchronize()
    tread = flank = None
    for dim, tag in gmsh.model.getEntities(2):
        x, y, z = gmsh.model.occ.getCenterOfMass(dim, tag)
        if abs(z) < 1e-9:
            flank = tag
        elif abs(z - 0.1) > 1e-9:
            tread = tag
    gmsh.model.addPhysicalGroup(2, [tread], name="tread")
    gmsh.model.addPhysicalGroup(2, [flank], name="flank")
    gmsh.model.addPhysicalGroup(3, [1], name="body")
    gmsh.model.mesh.setSize(gmsh.model.getEntities(0), 0.15)
    gmsh.model.mesh.generate(3)
    gmsh.model.mesh.setOrder(order)
    write(f"cylinder_tet{4 if order == 1 else 10}")
    gmsh.model.remove()


gmsh.initialize()
gmsh.option.setNumber("General.Terminal", 0)
cube(1, False)
cube(2, False)
cube(1, True)
cylinder(1)
cylinder(2)
gmsh.finalize()
