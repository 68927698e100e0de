"""Gmsh's geo-kernel baseline of `bench/compare-curves` (run with the gmsh Python).

Usage: python compare-curves-gmsh.py NETWORK.json H OUT.json

Builds one geo-kernel model from the curve network written by
`quadrille curves MODEL --write-network NETWORK.json` (the same cycles as
ours): each network curve becomes a spline through its samples, tag = its
`cad_curve` (1-based, i.e. CAD id + 1), its end points welded. Per cycle:
- one loop of 3–4 curves and no hole: `addSurfaceFilling`, transfinite
  (each curve gets ⌈len / H⌉ intervals, as ours,, opposite sides of a 4-loop and
  all sides of a 3-loop set to their maximum), recombined;
- other loops on a plane (every sample within 1e-6 × diagonal of the
  least-squares plane): `addPlaneSurface` with its holes, Algorithm 11
  (quasi-structured quads), recombined;
- otherwise: "not meshed by Gmsh" (Gmsh cannot fill a non-planar loop of
  other than 3–4 curves from curves alone).
Surface tag = `cad_face`. One thread. The mesh is written as JSON (nodes per
entity, elements per entity): the spline control points are geo points too,
so Gmsh's own MSH would classify curve nodes on them; the caller writes the
MSH with every node on a curve or a surface, as `quadrille curves` does.
"""
import json
import math
import sys
import time

import gmsh
import numpy as np

FILL_TOL = 1e-6  # × diagonal: a loop is planar when all samples are this close to its plane
CONTROL_TAG0 = 1_000_000  # geo point tags of the spline interiors


def main():
    net_path, h, out_path = sys.argv[1], float(sys.argv[2]), sys.argv[3]
    net = json.load(open(net_path))
    curves = net["curves"]
    allpts = np.array([p for c in curves for p in c["points"]], dtype=float)
    diag = float(np.linalg.norm(allpts.max(0) - allpts.min(0)))
    weld = 1e-6 * diag  # end points closer than this are one geo point

    gmsh.initialize(["-v", "0"])
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.option.setNumber("General.NumThreads", 1)
    gmsh.option.setNumber("Mesh.MeshSizeMax", h)
    gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 0)
    gmsh.model.add("curves")
    t0 = time.perf_counter()

    ends = []  # (xyz, tag) of the welded end points

    def end_point(p):
        for q, tag in ends:
            if math.dist(p, q) <= weld:
                return tag
        tag = len(ends) + 1
        gmsh.model.geo.addPoint(p[0], p[1], p[2], h, tag)
        ends.append((p, tag))
        return tag

    ctag = CONTROL_TAG0
    curve_tag, curve_len, curve_ends = [], [], []
    for i, c in enumerate(curves):
        pts = c["points"]
        a, b = end_point(pts[0]), end_point(pts[-1])
        inner = []
        for p in pts[1:-1]:
            gmsh.model.geo.addPoint(p[0], p[1], p[2], h, ctag)
            inner.append(ctag)
            ctag += 1
        tag = int(c.get("cad_curve", i + 1))
        gmsh.model.geo.addSpline([a] + inner + [b], tag)
        curve_tag.append(tag)
        curve_len.append(sum(math.dist(pts[k], pts[k + 1]) for k in range(len(pts) - 1)))
        curve_ends.append((a, b))

    # cycles: which kind of surface
    kinds, loops_of = [], []
    for ci, cyc in enumerate(net["cycles"]):
        loops = cyc["loops"]
        pts = np.array([p for loop in loops for (cu, _) in loop for p in curves[cu]["points"]])
        centred = pts - pts.mean(0)
        normal = np.linalg.svd(centred, full_matrices=False)[2][-1]
        planar = float(np.abs(centred @ normal).max()) <= FILL_TOL * diag
        if len(loops) == 1 and len(loops[0]) in (3, 4):
            kinds.append("filling")
        elif planar:
            kinds.append("plane")
        else:
            kinds.append("none")
        loops_of.append(loops)

    # transfinite counts: union-find over the sides that must match
    parent = list(range(len(curves)))

    def find(x):
        while parent[x] != x:
            parent[x] = parent[parent[x]]
            x = parent[x]
        return x

    for kind, loops in zip(kinds, loops_of):
        if kind != "filling":
            continue
        loop = [cu for cu, _ in loops[0]]
        pairs = [(loop[0], loop[2]), (loop[1], loop[3])] if len(loop) == 4 else [(loop[0], loop[1]), (loop[1], loop[2])]
        for x, y in pairs:
            parent[find(x)] = find(y)
    group_n = {}
    for i in range(len(curves)):
        n = max(1, math.ceil(curve_len[i] / h - 1e-9))
        group_n[find(i)] = max(group_n.get(find(i), 1), n)
    transfinite = set()
    for kind, loops in zip(kinds, loops_of):
        if kind == "filling":
            transfinite.update(cu for cu, _ in loops[0])

    surf_of = {}
    for ci, (kind, loops) in enumerate(zip(kinds, loops_of)):
        if kind == "none":
            continue
        wires = []
        for loop in loops:
            wires.append(gmsh.model.geo.addCurveLoop([s * curve_tag[cu] for cu, s in loop]))
        stag = int(net["cycles"][ci].get("cad_face", ci + 1))
        if kind == "filling":
            gmsh.model.geo.addSurfaceFilling([wires[0]], stag)
        else:
            gmsh.model.geo.addPlaneSurface(wires, stag)
        surf_of[ci] = stag
    gmsh.model.geo.synchronize()
    for cu in transfinite:
        gmsh.model.mesh.setTransfiniteCurve(curve_tag[cu], group_n[find(cu)] + 1)
    for ci, stag in surf_of.items():
        if kinds[ci] == "filling":
            gmsh.model.mesh.setTransfiniteSurface(stag)
        else:
            gmsh.model.mesh.setAlgorithm(2, stag, 11)
        gmsh.model.mesh.setRecombine(2, stag)
    error = None
    try:
        gmsh.model.mesh.generate(2)
    except Exception as e:  # noqa: BLE001 -- reported, the partial mesh is still judged
        error = str(e)
    seconds = time.perf_counter() - t0

    # the mesh, every node on a curve or a surface
    out = {"seconds": seconds, "error": error, "kinds": kinds, "surfaces": surf_of,
           "curves": {}, "faces": {}}
    node_entity = {}
    for cu, tag in enumerate(curve_tag):
        a, b = curve_ends[cu]
        tags, xyz = [], []
        for dim, t in ((0, a), (0, b), (1, tag)):
            nt, nx, _ = gmsh.model.mesh.getNodes(dim, t)
            for k, n in enumerate(nt):
                if int(n) not in node_entity:
                    node_entity[int(n)] = (1, tag)
                    tags.append(int(n))
                    xyz.append(list(nx[3 * k:3 * k + 3]))
        et, en = gmsh.model.mesh.getElementsByType(1, tag)
        out["curves"][tag] = {"nodes": tags, "xyz": xyz, "lines": [int(x) for x in en]}
    for ci, stag in surf_of.items():
        nt, nx, _ = gmsh.model.mesh.getNodes(2, stag)
        quads, tris = [], []
        types, _, enodes = gmsh.model.mesh.getElements(2, stag)
        for ty, en in zip(types, enodes):
            if ty == 3:
                quads = [int(x) for x in en]
            elif ty == 2:
                tris = [int(x) for x in en]
            else:
                error = (error or "") + f" surface {stag}: element type {ty}"
        out["faces"][stag] = {"cycle": ci, "nodes": [int(x) for x in nt],
                              "xyz": [list(nx[3 * k:3 * k + 3]) for k in range(len(nt))],
                              "quads": quads, "triangles": tris,
                              "bounding": sorted({curve_tag[cu] for loop in loops_of[ci] for cu, _ in loop})}
    out["error"] = error
    gmsh.finalize()
    with open(out_path, "w") as f:
        json.dump(out, f)


if __name__ == "__main__":
    main()
