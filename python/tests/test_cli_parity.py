"""quadrille.mesh gives the arrays of the command line's file, on every bundled model:
the same nodes (bit for bit), quads, node classification and quad faces, the
same MSH file when written, and meshio reads the command's default file as the
same arrays."""

import numpy as np
import pytest

import quadrille
from conftest import MODELS, assert_same_quads, need


@pytest.mark.parametrize("path", MODELS, ids=lambda p: p.stem)
def test_arrays_equal_the_cli_file(path, cli, tmp_path):
    m = quadrille.mesh(path)
    out = tmp_path / "cli.msh"
    cli("mesh", path, "-o", out, "--quiet")
    r = quadrille.read_mesh(out)
    np.testing.assert_array_equal(m.nodes, r.nodes)
    np.testing.assert_array_equal(m.quads, r.quads)
    np.testing.assert_array_equal(m.node_entity, r.node_entity)
    np.testing.assert_array_equal(m.quad_face, r.quad_face)
    assert m.report["quads"] == len(r.quads) == len(m)
    # the same file, byte for byte
    mine = tmp_path / "py.msh"
    m.write(mine)
    assert mine.read_bytes() == out.read_bytes()
    # meshio reads the command's default file as the same mesh
    meshio = need("meshio")
    mm = meshio.read(out)
    assert_same_quads(mm.points, mm.cells_dict["quad"], m.nodes, m.quads)


def test_model_counts_equal_info(cli_json):
    for path in MODELS[:6]:
        model = quadrille.load(path)
        info = cli_json("info", path, "--json")
        assert (model.faces, model.curves, model.corners) == (info["faces"], info["curves"], info["corners"])
        lo, hi = model.bounding_box
        assert isinstance(lo, tuple) and len(lo) == len(hi) == 3
        np.testing.assert_allclose([lo, hi], info["bounding_box"], rtol=0, atol=1e-12)
        assert model.path.name == path.name
        assert model.diagonal == pytest.approx(info["diagonal"], rel=1e-12)
        assert model.warnings == []


def test_stats_equal_the_cli_json(cli, cli_json, tmp_path):
    path = MODELS[0]
    out = tmp_path / "m.msh"
    cli("mesh", path, "-o", out, "--quiet")
    read = quadrille.read_mesh(out)
    assert read.stats() == cli_json("stats", out, "--json")
    model = quadrille.load(path)
    assert read.stats(model) == cli_json("stats", out, "--cad", path, "--json")
    # the mesh in memory: the same numbers as its file without CAD; with its
    # model, no inverted quad and the summary line's numbers
    m = quadrille.mesh(model)
    assert m.stats() == read.stats()
    s = m.stats(m.model)
    assert s["inverted_quads"] == 0 and s["cad_normals"] is True
    assert s["inverted_quads_element_geometry"] == 0
    line = cli("mesh", path, "-o", out).stderr.strip().splitlines()[-1]
    assert f"SICN min {s['sicn']['min']:.3f} avg {s['sicn']['avg']:.3f}" in line


def test_field_matches_the_cli(cli_json):
    path = MODELS[0].parent / "s17o_sphere.stp"
    f = quadrille.field(path)
    j = cli_json("field", path, "--json", "--quiet")
    assert f["totals"]["triangles"] == j["totals"]["triangles"]
    assert f["totals"]["faces_euler_ok"] == j["totals"]["faces_euler_ok"] == 1
    # the sphere's eight +1 singularities (4χ = 8)
    assert len(f["singularities"]) == 8
    assert all(s["index"] == 1 and s["face"] == 1 for s in f["singularities"])
    got = sorted(tuple(s["position"]) for s in f["singularities"])
    want = sorted(tuple(s["position"]) for s in j["faces"][0]["singularities"])
    np.testing.assert_allclose(got, want, rtol=0, atol=1e-12)
    m = len(f["triangles"])
    assert f["triangles"].shape == (m, 3) and f["cross"].shape == (m, 3)
    assert f["triangle_face"].shape == (m,) and f["size_map"].shape == (m,)
    assert f["triangles"].max() < len(f["points"])
    # unit cross vectors, positive sizes
    norms = np.linalg.norm(f["cross"], axis=1)
    ok = np.isfinite(norms)
    np.testing.assert_allclose(norms[ok], 1.0, atol=1e-9)
    assert (f["size_map"] > 0).all()
