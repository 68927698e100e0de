"""Round trips through meshio and Gmsh: our files read by them with the same
arrays and CAD entities, their files read back by quadrille.read_mesh."""

import numpy as np
import pytest

import quadrille
from conftest import CAD, assert_same_quads, need


@pytest.fixture(scope="module")
def cube_cyl():
    return quadrille.mesh(CAD / "s11o_cube_cyl.stp")


def test_meshio_round_trips(cube_cyl, tmp_path):
    meshio = need("meshio")
    m = cube_cyl
    # our MSH → meshio: points, quads, CAD face per quad, nodes per entity
    out = tmp_path / "m.msh"
    m.write(out)
    mm = meshio.read(out)
    assert_same_quads(mm.points, mm.cells_dict["quad"], m.nodes, m.quads)
    faces = mm.cell_data_dict["gmsh:geometrical"]["quad"]
    np.testing.assert_array_equal(np.sort(faces), np.sort(m.quad_face))
    assert len(mm.cells_dict["vertex"]) == m.model.corners
    assert len(mm.cells_dict["line"]) > 0
    # to_meshio → VTU → meshio
    mo = m.to_meshio()
    np.testing.assert_array_equal(mo.points, m.nodes)
    np.testing.assert_array_equal(mo.point_data["cad_dim"], m.node_entity[:, 0])
    vtu = tmp_path / "m.vtu"
    mo.write(vtu)
    back = meshio.read(vtu)
    np.testing.assert_array_equal(back.cells_dict["quad"], m.quads)
    np.testing.assert_array_equal(back.cell_data["cad_face"][0], m.quad_face)
    np.testing.assert_allclose(back.points, m.nodes, rtol=0, atol=0)
    # meshio's own MSH 2.2 → quadrille.read_mesh (its 4.1 writer wants
    # physical groups, which neither Gmsh's default output nor ours has)
    theirs = tmp_path / "by-meshio.msh"
    meshio.write(theirs, mm, file_format="gmsh22", binary=False)
    r = quadrille.read_mesh(theirs)
    np.testing.assert_allclose(r.nodes, mm.points, rtol=1e-15, atol=0)
    np.testing.assert_array_equal(r.quads, mm.cells_dict["quad"])
    np.testing.assert_array_equal(r.quad_face, faces)
    assert_same_quads(r.nodes, r.quads, m.nodes, m.quads)
    # and quadrille's own VTU has the SICN meshio sees
    ours = tmp_path / "ours.vtu"
    m.write(ours)
    v = meshio.read(ours)
    np.testing.assert_array_equal(v.cells_dict["quad"], m.quads)


GMSH_READ = """
import sys, json, gmsh
gmsh.initialize(["-noenv"])
gmsh.option.setNumber("General.Terminal", 0)
gmsh.open(sys.argv[1])
tags, coords, _ = gmsh.model.mesh.getNodes()
types, etags, _ = gmsh.model.mesh.getElements(2)
out = {"nodes": len(tags), "quads": sum(len(e) for t, e in zip(types, etags) if t == 3),
       "entities": [len(gmsh.model.getEntities(d)) for d in range(3)]}
gmsh.option.setNumber("Mesh.Binary", 1)
gmsh.write(sys.argv[2])
gmsh.finalize()
print("JSON" + json.dumps(out))
"""


@pytest.mark.parametrize("binary", [False, True])
def test_gmsh_round_trip(cube_cyl, tmp_path, binary):
    need("gmsh")
    import json
    import subprocess
    import sys

    m = cube_cyl
    out = tmp_path / "m.msh"
    m.write(out, binary=binary)
    back = tmp_path / "by-gmsh.msh"
    # Gmsh in its own process: its global state stays out of the tests
    r = subprocess.run([sys.executable, "-c", GMSH_READ, str(out), str(back)], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    v = json.loads(next(line[4:] for line in r.stdout.splitlines() if line.startswith("JSON")))
    assert v["nodes"] == len(m.nodes) and v["quads"] == len(m)
    assert v["entities"] == [m.model.corners, m.model.curves, m.model.faces]
    g = quadrille.read_mesh(back)
    np.testing.assert_array_equal(g.nodes, m.nodes)
    np.testing.assert_array_equal(g.node_entity, m.node_entity)
    key = lambda q, f: sorted(zip(map(tuple, q.tolist()), f.tolist()))
    assert key(g.quads, g.quad_face) == key(m.quads, m.quad_face)
    s = g.stats(m.model)
    assert s["quads"] == len(m) and s["inverted_quads"] == 0 and s["open_edges"] == 0
    assert s["inverted_quads_element_geometry"] == 0
