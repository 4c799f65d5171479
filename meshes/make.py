"""Remakes every meshes/*.msh from its .geo with Gmsh's Python API (pip install gmsh).

    python3 -m venv /tmp/venv-gmsh && /tmp/venv-gmsh/bin/pip install gmsh
    /tmp/venv-gmsh/bin/python meshes/make.py

The same as `gmsh -2 -format msh41 X.geo -o X.msh` for each file. softway itself reads the
.msh files and needs neither Python nor Gmsh.
"""

import pathlib

import gmsh

here = pathlib.Path(__file__).resolve().parent
gmsh.initialize()
gmsh.option.setNumber("General.Terminal", 0)
for geo in sorted(here.glob("*.geo")):
    gmsh.clear()
    gmsh.open(str(geo))
    gmsh.model.mesh.generate(2)
    msh = geo.with_suffix(".msh")
    gmsh.write(str(msh))
    print(f"{msh.name}: {len(gmsh.model.mesh.getNodes()[0])} nodes")
gmsh.finalize()
