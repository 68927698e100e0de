#!/usr/bin/env python3
"""Write the industrial corpus (issue 32 item 3) as STEP files, with MANIFEST.json.

Public parametric parts of bd_warehouse (ISO/DIN fasteners, flanges, bearings, gears,
sprockets, ...; Apache-2.0) and torture parts built here with build123d / OCP (variable
and vanishing fillets, a real thread, cusps, a thin-walled shell, 500+ faces).

Usage (in a venv of its own, Python 3.10+):
  python3 -m venv /tmp/venv-corpus && /tmp/venv-corpus/bin/pip install build123d bd_warehouse
  /tmp/venv-corpus/bin/python data/industrial/generate.py [--out data/industrial] [--only NAME,...]

Each part is written to OUT/NAME.step; MANIFEST.json lists file, source package and
version, function and parameters, licence, solids and faces. A part whose construction
fails is listed under "failed" with the error, and the run goes on.
"""
import argparse
import json
import math
import os
import sys
import traceback
from importlib import metadata

import build123d as bd
import bd_warehouse.bearing as bearing
import bd_warehouse.bushing as bushing
import bd_warehouse.fastener as fastener
import bd_warehouse.flange as flange
import bd_warehouse.gear as gear
import bd_warehouse.o_rings as o_rings
import bd_warehouse.pipe as pipe
import bd_warehouse.retaining_ring as retaining_ring
import bd_warehouse.shaft_key as shaft_key
import bd_warehouse.sprocket as sprocket
import bd_warehouse.thread as thread

HERE = os.path.dirname(os.path.abspath(__file__))
BD_WAREHOUSE = ("bd_warehouse", "Apache-2.0")
BUILD123D = ("build123d", "Apache-2.0 (generated here; this script's parts are the project's own)")


def warehouse(name, cls, **params):
    """A bd_warehouse part: its class and keyword parameters."""
    return (name, BD_WAREHOUSE, f"bd_warehouse.{cls.__module__.split('.')[-1]}.{cls.__name__}",
            params, lambda: cls(**params))


# ---------------------------------------------------------------- torture parts


def variable_fillet_plate():
    """A 60 x 40 x 10 plate whose four vertical edges have fillets going from 6 to 1.5."""
    from OCP.BRepFilletAPI import BRepFilletAPI_MakeFillet
    box = bd.Box(60, 40, 10)
    mk = BRepFilletAPI_MakeFillet(box.wrapped)
    for e in box.edges().filter_by(bd.Axis.Z):
        mk.Add(6.0, 1.5, e.wrapped)
    mk.Build()
    return bd.Solid(mk.Shape())


def vanishing_fillet_block():
    """A block with a ramp: the fillet along the ramp's edges goes from 4 to 0.05 (vanishing)."""
    from OCP.BRepFilletAPI import BRepFilletAPI_MakeFillet
    with bd.BuildPart() as p:
        with bd.BuildSketch(bd.Plane.XZ):
            bd.Polygon((0, 0), (60, 0), (60, 8), (0, 20), align=None)
        bd.extrude(amount=-30)
    solid = p.part.solids()[0]
    mk = BRepFilletAPI_MakeFillet(solid.wrapped)
    for e in solid.edges():
        c = e.center()
        # the two sloped edges of the ramp (in the XZ side planes): radius tapers to ~0
        if e.length > 55 and min(abs(c.Y), abs(abs(c.Y) - 30)) < 1e-6 and c.Z > 8.5:
            mk.Add(4.0, 0.05, e.wrapped)
    mk.Build()
    return bd.Solid(mk.Shape())


def corner_three_radii():
    """A box whose three edges at one corner have fillets of radii 2, 4 and 6 (a setback corner)."""
    box = bd.Box(30, 30, 30)
    corner = bd.Vector(15, 15, 15)
    edges = sorted((e for e in box.edges() if (e.center() - corner).length < 15.5), key=lambda e: e.center().Z)
    from OCP.BRepFilletAPI import BRepFilletAPI_MakeFillet
    mk = BRepFilletAPI_MakeFillet(box.wrapped)
    for r, e in zip((2.0, 4.0, 6.0), edges):
        mk.Add(r, e.wrapped)
    mk.Build()
    return bd.Solid(mk.Shape())


def threaded_rod():
    """An M6 rod 12 long with a real ISO thread (pitch 1) fused on a core."""
    t = thread.IsoThread(major_diameter=6, pitch=1, length=8, external=True, end_finishes=("fade", "fade"),
                         simple=False)
    core = bd.Cylinder(t.min_radius, 12, align=(bd.Align.CENTER, bd.Align.CENTER, bd.Align.MIN))
    core = bd.Pos(0, 0, -2) * core
    return core + t


def cusp_prism():
    """A prism whose section has a cusp: a line and an arc leave (10, 0) tangentially (angle 0)."""
    with bd.BuildPart() as p:
        with bd.BuildSketch():
            with bd.BuildLine():
                bd.Line((0, 0), (10, 0))
                bd.CenterArc((10, 5), 5, 270, -90)  # from (10, 0) to (5, 5), tangent (-1, 0) at (10, 0)
                bd.Line((5, 5), (0, 5))
                bd.Line((0, 5), (0, 0))
            bd.make_face()
        bd.extrude(amount=4)
    return p.part


def tangent_cylinders():
    """A plate with a boss whose cylinder touches the plate's side plane: cusps on the top face."""
    plate = bd.Box(40, 20, 4, align=(bd.Align.MIN, bd.Align.MIN, bd.Align.MIN))
    # a half-disk boss beyond the edge y = 20, tangent to x = 40 at (40, 20): cusp between x = 40 and the circle
    boss = bd.Pos(34, 20, 0) * bd.Cylinder(6, 4, align=(bd.Align.CENTER, bd.Align.CENTER, bd.Align.MIN))
    return plate + boss


def thin_shell_box():
    """A 100 x 60 x 40 box with rounded edges, hollowed to a 0.4 wall, open at the top."""
    box = bd.fillet(bd.Box(100, 60, 40).edges(), 5)
    top = box.faces().sort_by(bd.Axis.Z)[-1]
    return bd.offset(box, amount=-0.4, openings=[top])


def hole_grid_plate():
    """A 130 x 130 x 5 plate with 13 x 13 holes, both hole edges filleted: 500+ faces."""
    plate = bd.Box(130, 130, 5)
    with bd.BuildPart() as p:
        bd.add(plate)
        with bd.GridLocations(10, 10, 13, 13):
            bd.Hole(3)
        bd.fillet(p.edges().filter_by(bd.GeomType.CIRCLE), 0.6)
    return p.part


def gear_many_teeth():
    """A spur gear, module 1, 60 teeth, root fillets: several hundred faces."""
    return gear.SpurGear(module=1, tooth_count=60, pressure_angle=20, root_fillet=0.25, thickness=6)


TORTURE = [
    ("t_variable_fillet_plate", variable_fillet_plate, {"edges": "4 vertical", "radius": "6 -> 1.5"}),
    ("t_vanishing_fillet_ramp", vanishing_fillet_block, {"ramp edges": 2, "radius": "4 -> 0.05"}),
    ("t_corner_three_radii", corner_three_radii, {"radii": [2, 4, 6]}),
    ("t_threaded_rod_m6", threaded_rod, {"major_diameter": 6, "pitch": 1, "thread_length": 8, "simple": False}),
    ("t_cusp_prism", cusp_prism, {"section": "line + tangent arc at (10,0)", "height": 4}),
    ("t_tangent_boss_plate", tangent_cylinders, {"plate": [40, 20, 4], "boss radius": 6}),
    ("t_thin_shell_box", thin_shell_box, {"box": [100, 60, 40], "fillet": 5, "wall": 0.4}),
    ("t_hole_grid_plate", hole_grid_plate, {"plate": [130, 130, 5], "holes": "13 x 13, d 3", "fillet": 0.6}),
    ("t_gear_60_teeth", gear_many_teeth, {"module": 1, "tooth_count": 60, "root_fillet": 0.25}),
]


def warehouse_parts():
    """The bd_warehouse parts: one per class, mid-range sizes."""
    f = fastener
    return [
        warehouse("socket_head_cap_screw_m6x20", f.SocketHeadCapScrew, size="M6-1", length=20, fastener_type="iso4762"),
        warehouse("hex_head_screw_m8x25", f.HexHeadScrew, size="M8-1.25", length=25, fastener_type="iso4014"),
        warehouse("counter_sunk_screw_m5x16", f.CounterSunkScrew, size="M5-0.8", length=16, fastener_type="iso10642"),
        warehouse("button_head_screw_m4x10", f.ButtonHeadScrew, size="M4-0.7", length=10, fastener_type="iso7380_1"),
        warehouse("button_head_collar_screw_m5x12", f.ButtonHeadWithCollarScrew, size="M5-0.8", length=12,
                  fastener_type="iso7380_2"),
        warehouse("pan_head_screw_m4x10", f.PanHeadScrew, size="M4-0.7", length=10, fastener_type="iso1580"),
        warehouse("pan_head_collar_screw_m5x12", f.PanHeadWithCollarScrew, size="M5-0.8", length=12,
                  fastener_type="din967"),
        warehouse("cheese_head_screw_m5x12", f.CheeseHeadScrew, size="M5-0.8", length=12, fastener_type="iso1207"),
        warehouse("raised_cheese_head_screw_m4x10", f.RaisedCheeseHeadScrew, size="M4-0.7", length=10,
                  fastener_type="iso7045"),
        warehouse("raised_csk_oval_screw_m5x12", f.RaisedCounterSunkOvalHeadScrew, size="M5-0.8", length=12,
                  fastener_type="iso2010"),
        warehouse("set_screw_m5x8", f.SetScrew, size="M5-0.8", length=8, fastener_type="iso4026"),
        warehouse("shoulder_screw_m6x20", f.ShoulderScrew, size="M6-1", length=20, fastener_type="iso7379"),
        warehouse("hex_flange_screw_m8x20", f.HexHeadWithFlangeScrew, size="M8-1.25", length=20,
                  fastener_type="din1662"),
        warehouse("low_profile_screw_m5x10", f.LowProfileScrew, size="M5-0.8", length=10, fastener_type="OpenBuilds"),
        warehouse("hex_nut_m8", f.HexNut, size="M8-1.25", fastener_type="iso4032"),
        warehouse("hex_nut_flange_m8", f.HexNutWithFlange, size="M8-1.25", fastener_type="din1665"),
        warehouse("domed_cap_nut_m6", f.DomedCapNut, size="M6-1", fastener_type="din1587"),
        warehouse("square_nut_m6", f.SquareNut, size="M6-1", fastener_type="din557"),
        warehouse("unchamfered_hex_nut_m6", f.UnchamferedHexagonNut, size="M6-1", fastener_type="iso4036"),
        warehouse("heat_set_nut_m3", f.HeatSetNut, size="M3-0.5-Standard", fastener_type="McMaster-Carr"),
        warehouse("plain_washer_m8", f.PlainWasher, size="M8", fastener_type="iso7089"),
        warehouse("chamfered_washer_m8", f.ChamferedWasher, size="M8", fastener_type="iso7090"),
        warehouse("cheese_head_washer_m4", f.CheeseHeadWasher, size="M4", fastener_type="iso7092"),
        warehouse("internal_tooth_lock_washer_10", f.InternalToothLockWasher, size="#10", fastener_type="asme_b18.21.1"),
        warehouse("weld_neck_flange_2in_150", flange.WeldNeckFlange, nps="2", flange_class=150),
        warehouse("slip_on_flange_2in_300", flange.SlipOnFlange, nps="2", flange_class=300),
        warehouse("blind_flange_1in_150", flange.BlindFlange, nps="1", flange_class=150),
        warehouse("socket_weld_flange_1in_150", flange.SocketWeldFlange, nps="1", flange_class=150),
        warehouse("lapped_flange_2in_150", flange.LappedFlange, nps="2", flange_class=150),
        warehouse("ball_bearing_8_22_7", bearing.SingleRowDeepGrooveBallBearing, size="M8-22-7", bearing_type="SKT"),
        warehouse("angular_contact_bearing_10_30_9", bearing.SingleRowAngularContactBallBearing, size="M10-30-9",
                  bearing_type="SKT"),
        warehouse("cylindrical_roller_bearing_15_35_11", bearing.SingleRowCylindricalRollerBearing, size="M15-35-11",
                  bearing_type="SKT"),
        warehouse("tapered_roller_bearing_15_42", bearing.SingleRowTaperedRollerBearing, size="M15-42-14.25",
                  bearing_type="SKT"),
        warehouse("spur_gear_m1_z20", gear.SpurGear, module=1, tooth_count=20, pressure_angle=20, thickness=5,
                  root_fillet=0.2),
        warehouse("helical_gear_m1_z18", gear.HelicalGear, module=1, tooth_count=18, pressure_angle=20,
                  helix_angle=20, thickness=6),
        warehouse("rack_gear_m1_z10", gear.RackGear, module=1, tooth_count=10, pressure_angle=20, thickness=5),
        warehouse("sprocket_16", sprocket.Sprocket, num_teeth=16, bore_diameter=10),
        warehouse("eccentric_bushing", bushing.HexFlangedEccentricBushing, bore_diameter=5, body_diameter=7.2,
                  body_length=8, flange_height=2, hex_size=10, eccentricity=0.8),
        warehouse("shaft_key_d20", shaft_key.ShaftKey, shaft_diameter=20, length=25),
        warehouse("external_snap_ring_10", retaining_ring.ExternalSnapRing, size="10"),
        warehouse("o_ring_iso3601", o_rings.ORing, size="110"),
    ]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", default=HERE)
    ap.add_argument("--only", default="")
    args = ap.parse_args()
    only = set(args.only.split(",")) if args.only else None
    versions = {p: metadata.version(p) for p in ("bd_warehouse", "build123d", "cadquery-ocp-novtk")}
    parts = warehouse_parts() + [
        (name, BUILD123D, f"data/industrial/generate.py:{fn.__name__}", params, fn) for name, fn, params in TORTURE
    ]
    manifest_path = os.path.join(args.out, "MANIFEST.json")
    old = {}
    if only and os.path.exists(manifest_path):
        with open(manifest_path) as fh:
            old = {e["file"]: e for e in json.load(fh)["parts"]
                   if os.path.exists(os.path.join(args.out, e["file"]))}
    entries, failed = [], []
    for name, (package, licence), function, params, make in parts:
        if only and name not in only:
            continue
        path = os.path.join(args.out, name + ".step")
        try:
            shape = make()
            if not isinstance(shape, bd.Shape):
                shape = bd.Compound(list(shape))
            solids, faces = len(shape.solids()), len(shape.faces())
            if faces == 0:
                raise ValueError("no faces")
            if not bd.export_step(shape, path):
                raise IOError("export_step failed")
        except Exception as e:  # a failed part is recorded, the run goes on
            failed.append({"file": name + ".step", "function": function, "error": f"{type(e).__name__}: {e}"})
            print(f"FAILED {name}: {type(e).__name__}: {e}", file=sys.stderr)
            traceback.print_exc(limit=2)
            continue
        entry = {
            "file": name + ".step",
            "kind": "torture" if name.startswith("t_") else "catalogue part",
            "source": f"{package} {versions.get(package, '?')} (PyPI), exported by build123d {versions['build123d']}"
                      f" / OCP {versions['cadquery-ocp-novtk']}",
            "function": function,
            "parameters": {k: (v if isinstance(v, (int, float, str, list)) else str(v)) for k, v in params.items()},
            "licence": licence,
            "solids": solids,
            "faces": faces,
            "bytes": os.path.getsize(path),
        }
        old[entry["file"]] = entry
        entries.append(entry)
        print(f"{name}: {solids} solid(s), {faces} faces, {entry['bytes']} bytes", flush=True)
    if only:
        entries = list(old.values())
    with open(manifest_path, "w") as fh:
        json.dump({"generator": "data/industrial/generate.py", "versions": versions,
                   "parts": sorted(entries, key=lambda e: e["file"]), "failed": failed}, fh, indent=1)
        fh.write("\n")
    print(f"{len(entries)} parts written, {len(failed)} failed; manifest {manifest_path}")


if __name__ == "__main__":
    main()
