"""quadrille.mesh and QuadMesh: every method's default MSH output read by meshio,
the array conventions, options (size, threads, stages), the report, progress,
the interpreter left free while meshing, and Ctrl-C."""

import os
import pathlib
import signal
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

import quadrille
from conftest import CAD, METHODS, MODELS, SMALL, assert_same_quads, need


#: QUADRILLE_PYTEST_ALL=1: every bundled model (several minutes: the regular
#: method takes up to 20 s a model), not only the small ones.
EVERY_MODEL = os.environ.get("QUADRILLE_PYTEST_ALL") == "1"


@pytest.mark.parametrize("method", METHODS)
def test_meshio_reads_every_methods_default_msh(method, tmp_path):
    meshio = need("meshio")
    for path in MODELS if EVERY_MODEL else SMALL:
        m = quadrille.mesh(path, method=method)
        assert m.report["method"] == method
        for binary in (False, True):
            out = tmp_path / f"{path.stem}-{binary}.msh"
            m.write(out, binary=binary)
            mm = meshio.read(out)
            assert_same_quads(mm.points, mm.cells_dict["quad"], m.nodes, m.quads)
            tags = np.concatenate(
                [t for c, t in zip(mm.cells, mm.cell_data["gmsh:geometrical"]) if c.type == "quad"]
            )
            np.testing.assert_array_equal(np.sort(tags), np.sort(m.quad_face))


def test_array_conventions():
    path = CAD / "s12o_cube_rounded_1.stp"
    m = quadrille.mesh(path)
    model = m.model
    n, q = len(m.nodes), len(m.quads)
    assert m.nodes.shape == (n, 3) and m.nodes.dtype == np.float64
    assert m.quads.shape == (q, 4) and m.quads.dtype == np.int64
    assert m.node_entity.shape == (n, 2) and m.quad_face.shape == (q,)
    assert m.triangles.shape == (0, 3) and m.triangle_face.shape == (0,)
    assert 0 <= m.quads.min() and m.quads.max() < n
    assert set(np.unique(m.node_entity[:, 0])) == {0, 1, 2}
    for dim, count in zip((0, 1, 2), (model.corners, model.curves, model.faces)):
        ids = m.node_entity[m.node_entity[:, 0] == dim, 1]
        assert 1 <= ids.min() and ids.max() <= count
    assert 1 <= m.quad_face.min() and m.quad_face.max() == model.faces
    # every corner of the model is a node
    assert (m.node_entity[:, 0] == 0).sum() == model.corners
    # each quad's nodes are on its face or its boundary
    face_nodes = m.node_entity[m.quads][m.node_entity[m.quads][:, :, 0] == 2]
    assert set(face_nodes[:, 1]) <= set(m.quad_face)
    # counter-clockwise seen from outside: the closed mesh encloses a positive volume
    p = m.nodes[m.quads]
    vol = sum(np.einsum("ij,ij->i", p[:, 0], np.cross(p[:, k], p[:, k + 1])).sum() for k in (1, 2)) / 6
    assert vol > 0
    # read-only, and the same objects on each access
    assert not m.nodes.flags.writeable and not m.quads.flags.writeable
    with pytest.raises(ValueError):
        m.nodes[0, 0] = 1.0
    assert m.nodes is m.nodes
    assert repr(m) == f"QuadMesh({n} nodes, {q} quads)" and len(m) == q


def test_size_threads_and_stages():
    path = CAD / "s11o_cube_cyl.stp"
    model = quadrille.load(path)
    default = quadrille.mesh(model, threads=1)
    coarse = quadrille.mesh(model, size_factor=2.0, threads=1)
    assert len(coarse) < 0.5 * len(default)
    h = model.diagonal / 24
    same = quadrille.mesh(model, size=h, threads=1)
    np.testing.assert_array_equal(same.quads, default.quads)
    two = quadrille.mesh(model, threads=2)
    np.testing.assert_array_equal(two.nodes, default.nodes)
    np.testing.assert_array_equal(two.quads, default.quads)
    rounded = quadrille.load(CAD / "s12o_cube_rounded_1.stp")
    on = quadrille.mesh(rounded)
    off = quadrille.mesh(rounded, patterns=False, cavities=False)
    assert on.report["patterns"] and not off.report["patterns"]
    assert off.report["stages"] == {"patterns": False, "defects": True, "cavities": False, "regular_pass": True}
    assert on.report["cavities"]["replaced"] is not None


def test_report():
    m = quadrille.mesh(CAD / "i01o_m1.step")
    r = m.report
    assert r["method"] == "quasi-structured" and r["faces"] == m.model.faces == 42
    assert r["quads"] == len(m) and r["nodes"] == len(m.nodes)
    # 38 library patterns and one annulus meshed as a ring grid
    assert len(r["patterns"]) == 39 and all(1 <= p["face"] <= 42 for p in r["patterns"])
    assert sum(p["pattern"] == "ring" for p in r["patterns"]) == 1
    assert r["fallback"] == [] and r["regularize"] is None
    t = r["times"]
    assert t["total"] > 0 and t["fields"] > 0 and t["faces"] > 0
    reg = quadrille.mesh(CAD / "s17o_sphere.stp", method="regular")
    assert reg.report["stages"] is None
    assert reg.report["regularize"]["faces"] >= 1
    assert reg.report["regularize"]["irregular_after"] <= reg.report["regularize"]["irregular_before"]
    # a mesh read from a file has no report and no model
    assert quadrille.read_mesh(CAD.parent.parent / "crates/mesh/tests/data/i01o_m1_quadqs.msh").report is None


def test_progress_callable_and_stderr(capsys):
    calls = []
    path = CAD / "i01o_m1.step"
    quadrille.mesh(path, progress=lambda done, total: calls.append((done, total)))
    # seen by the waiting thread: increasing, ending at every face done
    assert calls, "the callable was called"
    assert calls[-1] == (42, 42)
    assert all(a <= b for a, b in zip(calls, calls[1:]))
    quadrille.mesh(path, progress=True)
    err = capsys.readouterr().err
    assert "meshing: 42/42 faces" in err and err.endswith("\n")
    # a mesh done before the first poll still reports its end
    calls.clear()
    quadrille.mesh(CAD / "s17o_sphere.stp", size_factor=4, progress=lambda d, t: calls.append((d, t)))
    assert calls == [(1, 1)]


def test_a_raising_progress_callable_stops_meshing():
    def stop(done, total):
        raise RuntimeError(f"stop at {done}")

    t = time.perf_counter()
    with pytest.raises(RuntimeError, match="stop at"):
        quadrille.mesh(CAD / "i05o_m5.step", size_factor=0.5, progress=stop, threads=1)
    assert time.perf_counter() - t < 4.0


def test_other_threads_run_while_meshing():
    ticks = []
    done = threading.Event()

    def count():
        while not done.is_set():
            ticks.append(time.perf_counter())
            time.sleep(0.005)

    t = threading.Thread(target=count)
    t.start()
    start = time.perf_counter()
    try:
        quadrille.mesh(CAD / "i05o_m5.step", size_factor=0.7, threads=1)
    finally:
        done.set()
        t.join()
    end = time.perf_counter()
    during = [x for x in ticks if start < x < end]
    # the interpreter was free: the counter ticked all along
    assert (end - start) > 0.3
    assert len(during) > 0.3 * (end - start) / 0.005 * 0.5, (len(during), end - start)


CTRL_C = r"""
import os, signal, sys, threading, time
import quadrille
# a job started in the background by a non-interactive shell (a CI runner,
# say) inherits SIGINT ignored, and Python then keeps it ignored: the test is
# about our interrupt, so Python's own Ctrl-C handler is put in place
signal.signal(signal.SIGINT, signal.default_int_handler)
model = quadrille.load(sys.argv[1])
threading.Timer(0.5, lambda: os.kill(os.getpid(), signal.SIGINT)).start()
t = time.perf_counter()
try:
    quadrille.mesh(model, size_factor=0.3, threads=1)
    print("FINISHED", time.perf_counter() - t)
except KeyboardInterrupt:
    print("INTERRUPTED", time.perf_counter() - t)
"""


def test_ctrl_c_interrupts_a_long_mesh():
    r = subprocess.run(
        [sys.executable, "-c", CTRL_C, str(CAD / "i05o_m5.step")],
        capture_output=True, text=True, timeout=120,
    )
    assert r.returncode == 0, r.stderr
    word, seconds = r.stdout.split()
    # the whole mesh takes several seconds; the interrupt ends it at once
    assert word == "INTERRUPTED", r.stdout
    assert float(seconds) < 1.5, r.stdout


def test_triangle_mesh_input(tmp_path):
    # the sphere's quads, split, as an ASCII STL
    m = quadrille.mesh(CAD / "s17o_sphere.stp", size_factor=2.0)
    tris = np.concatenate([m.quads[:, [0, 1, 2]], m.quads[:, [0, 2, 3]]])
    stl = tmp_path / "sphere.stl"
    with open(stl, "w") as f:
        f.write("solid s\n")
        for t in tris:
            p = m.nodes[t]
            n = np.cross(p[1] - p[0], p[2] - p[0])
            f.write(f"facet normal {n[0]} {n[1]} {n[2]}\nouter loop\n")
            for v in p:
                f.write("vertex %r %r %r\n" % tuple(map(float, v)))
            f.write("endloop\nendfacet\n")
        f.write("endsolid s\n")
    model = quadrille.load(stl)
    assert model.faces >= 1
    q = quadrille.mesh(model)
    assert len(q) > 50
    s = q.stats(model)
    assert s["inverted_quads"] == 0 and s["open_edges"] == 0
    assert s["inverted_quads_element_geometry"] == 0
    assert quadrille.load(stl, feature_angle=60).faces >= 1
