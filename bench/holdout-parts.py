#!/usr/bin/env python3
"""Random parts nobody has tuned on: a fresh held-out set for each seed (issue 32).

The industrial corpus (`data/industrial`) is measured every session, so it is a training set.
This script draws a new set of parts from a seed: random sizes and types of the bd_warehouse
catalogue (fasteners, nuts, washers, flanges, gears) and random build123d parts made here
(plates with holes and fillets, turned parts with chamfers, L brackets, pocketed blocks,
slotted bars). A draw the CAD kernel refuses is listed and drawn again (up to 4 times). Parts are written to
OUT/NAME.step with OUT/MANIFEST.json (seed, family, parameters, faces).

It needs build123d and bd_warehouse (see data/industrial/README.md for the venv):

    /tmp/venv-corpus/bin/python bench/holdout-parts.py --seed 7 --count 24 --out /tmp/holdout

`bench/holdout` calls it and then meshes and judges every part.
"""
import argparse
import json
import os
import random
import sys

import build123d as bd
import bd_warehouse.fastener as fastener
import bd_warehouse.flange as flange
import bd_warehouse.gear as gear

# ---------------------------------------------------------------- catalogue parts

SCREWS = [
    (fastener.SocketHeadCapScrew, "iso4762"),
    (fastener.HexHeadScrew, "iso4014"),
    (fastener.CounterSunkScrew, "iso10642"),
    (fastener.ButtonHeadScrew, "iso7380_1"),
    (fastener.PanHeadScrew, "iso1580"),
    (fastener.CheeseHeadScrew, "iso1207"),
    (fastener.SetScrew, "iso4026"),
    (fastener.HexHeadWithFlangeScrew, "din1662"),
]
NUTS = [
    (fastener.HexNut, "iso4032"),
    (fastener.HexNutWithFlange, "din1665"),
    (fastener.SquareNut, "din557"),
    (fastener.DomedCapNut, "din1587"),
    (fastener.UnchamferedHexagonNut, "iso4036"),
]
WASHERS = [
    (fastener.PlainWasher, "iso7089"),
    (fastener.ChamferedWasher, "iso7090"),
    (fastener.CheeseHeadWasher, "iso7092"),
]
FLANGES = [flange.WeldNeckFlange, flange.SlipOnFlange, flange.BlindFlange, flange.SocketWeldFlange]


def metric_size(rng, cls, kind):
    """A metric size between M3 and M20 that the class lists for this type."""
    sizes = [s for s in cls.sizes(kind) if s.startswith("M")]
    usable = [s for s in sizes if 3 <= float(s[1:].split("-")[0]) <= 20] or sizes
    return rng.choice(sorted(usable))


def screw(rng):
    cls, kind = rng.choice(SCREWS)
    size = metric_size(rng, cls, kind)
    diameter = float(size[1:].split("-")[0])
    length = round(diameter * rng.choice([1.5, 2, 2.5, 3, 4]))
    params = {"size": size, "length": length, "fastener_type": kind}
    return f"bd_warehouse.fastener.{cls.__name__}", params, lambda: cls(**params)


def nut_or_washer(rng):
    cls, kind = rng.choice(NUTS + WASHERS)
    size = rng.choice(sorted(cls.sizes(kind)))
    if size.startswith("M"):
        size = metric_size(rng, cls, kind)
    params = {"size": size, "fastener_type": kind}
    return f"bd_warehouse.fastener.{cls.__name__}", params, lambda: cls(**params)


def catalogue_flange(rng):
    cls = rng.choice(FLANGES)
    params = {"nps": rng.choice(["1/2", "3/4", "1", "1 1/2", "2", "3", "4", "6"]), "flange_class": rng.choice([150, 300])}
    return f"bd_warehouse.flange.{cls.__name__}", params, lambda: cls(**params)


def catalogue_gear(rng):
    params = {"module": rng.choice([0.8, 1, 1.5, 2]), "tooth_count": rng.randint(9, 30),
              "pressure_angle": 20, "thickness": rng.choice([3, 5, 8])}
    if rng.random() < 0.5:
        params["root_fillet"] = round(0.1 * params["module"] * rng.randint(1, 3), 2)
    return "bd_warehouse.gear.SpurGear", params, lambda: gear.SpurGear(**params)


# ---------------------------------------------------------------- parts made here


def top_circles(part):
    """The circular edges on the part's highest z level."""
    return part.edges().filter_by(bd.GeomType.CIRCLE).group_by(bd.Axis.Z)[-1]


def plate(rng):
    """A plate with corner fillets and non-overlapping holes, some chamfered."""
    length, width, thick = rng.uniform(30, 120), rng.uniform(20, 80), rng.uniform(2, 12)
    corner = rng.uniform(0.5, min(length, width) / 5)
    holes = []
    for _ in range(rng.randint(1, 7)):
        r = rng.uniform(1, min(length, width) / 8)
        x, y = rng.uniform(-length / 2 + r + 3, length / 2 - r - 3), rng.uniform(-width / 2 + r + 3, width / 2 - r - 3)
        if all((x - a) ** 2 + (y - b) ** 2 > (r + c + 2) ** 2 for a, b, c in holes):
            holes.append((x, y, r))
    chamfer = rng.random() < 0.5
    params = {"size": [round(length, 2), round(width, 2), round(thick, 2)], "corner_fillet": round(corner, 2),
              "holes": [[round(v, 2) for v in h] for h in holes], "chamfered_holes": chamfer}

    def make():
        p = bd.Box(length, width, thick)
        p = bd.fillet(p.edges().filter_by(bd.Axis.Z), radius=corner)
        for x, y, r in holes:
            p = p - bd.Pos(x, y, 0) * bd.Cylinder(r, thick)
        if chamfer:
            p = bd.chamfer(top_circles(p), length=min(0.25 * thick, 0.3 * min(h[2] for h in holes)))
        return p

    return "plate", params, make


def turned(rng):
    """A revolved stepped shaft with a bore, some steps filleted or chamfered."""
    steps = rng.randint(2, 4)
    radii = sorted((rng.uniform(4, 25) for _ in range(steps)), reverse=rng.random() < 0.5)
    lengths = [rng.uniform(3, 20) for _ in range(steps)]
    bore = rng.uniform(1, min(radii) * 0.6) if rng.random() < 0.7 else 0.0
    round_edges = rng.random() < 0.5
    params = {"radii": [round(r, 2) for r in radii], "lengths": [round(v, 2) for v in lengths],
              "bore": round(bore, 2), "edge": "fillet" if round_edges else "chamfer"}

    def make():
        pts, z = [(bore, 0.0)], 0.0
        for r, l in zip(radii, lengths):
            pts += [(r, z), (r, z + l)]
            z += l
        pts.append((bore, z))
        with bd.BuildPart() as t:
            with bd.BuildSketch(bd.Plane.XZ):
                bd.Polygon(*pts, align=None)
            bd.revolve(axis=bd.Axis.Z)
        part = t.part
        outer = [e for e in part.edges().filter_by(bd.GeomType.CIRCLE) if e.radius > bore + 1e-6]
        pick = outer[:: max(1, len(outer) // 3)]
        steps = [abs(a - b) for a, b in zip(radii, radii[1:])] + [r - bore for r in radii]
        size = 0.2 * min(min(lengths), min(steps))
        return bd.fillet(pick, radius=size) if round_edges else bd.chamfer(pick, length=size)

    return "turned", params, make


def bracket(rng):
    """An L bracket: inner corner filleted, one hole in each flange."""
    a, b, t, w = rng.uniform(20, 60), rng.uniform(20, 60), rng.uniform(2, 8), rng.uniform(15, 50)
    inner = rng.uniform(0.5, min(3 * t, 0.3 * (min(a, b) - t)))
    params = {"legs": [round(a, 2), round(b, 2)], "thickness": round(t, 2), "width": round(w, 2),
              "inner_fillet": round(inner, 2)}

    def make():
        with bd.BuildPart() as p:
            with bd.BuildSketch(bd.Plane.XZ):
                bd.Polygon((0, 0), (a, 0), (a, t), (t, t), (t, b), (0, b), align=None)
            bd.extrude(amount=w)
        part = p.part
        corner = part.edges().filter_by(bd.Axis.Y).sort_by_distance((t, 0, t))[0]
        part = bd.fillet(corner, radius=inner)
        r = min(w, a - t, b - t) / 6
        part = part - bd.Pos((a + t) / 2 + t, -w / 2, 0) * bd.Cylinder(r, 3 * t)
        part = part - bd.Pos(0, -w / 2, (b + t) / 2 + t) * bd.Rot(0, 90, 0) * bd.Cylinder(r, 3 * t)
        return part

    return "bracket", params, make


def pocket_block(rng):
    """A block with a rounded rectangular pocket and all outer edges rounded."""
    lx, ly, lz = rng.uniform(20, 80), rng.uniform(20, 80), rng.uniform(8, 30)
    px, py, pz = lx * rng.uniform(0.3, 0.8), ly * rng.uniform(0.3, 0.8), lz * rng.uniform(0.2, 0.7)
    pocket_r, edge_r = rng.uniform(0.5, min(px, py) / 3), rng.uniform(0.3, min(lx, ly, lz) / 8)
    params = {"block": [round(v, 2) for v in (lx, ly, lz)], "pocket": [round(v, 2) for v in (px, py, pz)],
              "pocket_fillet": round(pocket_r, 2), "edge_fillet": round(edge_r, 2)}

    def make():
        p = bd.fillet(bd.Box(lx, ly, lz).edges(), radius=edge_r)
        cut = bd.fillet(bd.Box(px, py, pz).edges().filter_by(bd.Axis.Z), radius=pocket_r)
        return p - bd.Pos(0, 0, lz / 2 - pz / 2) * cut

    return "pocket_block", params, make


def slotted_bar(rng):
    """A bar with stadium slots through it and chamfered ends."""
    length, width, thick = rng.uniform(40, 150), rng.uniform(10, 30), rng.uniform(3, 10)
    slots = rng.randint(1, 3)
    slot_w = rng.uniform(2, width / 2)
    params = {"bar": [round(length, 2), round(width, 2), round(thick, 2)], "slots": slots, "slot_width": round(slot_w, 2)}

    def make():
        p = bd.Box(length, width, thick)
        pitch = length / (slots + 1)
        for k in range(slots):
            slot = bd.extrude(bd.SlotCenterToCenter(pitch * 0.5, slot_w), amount=thick, both=True)
            p = p - bd.Pos(-length / 2 + pitch * (k + 1), 0, 0) * slot
        ends = p.edges().filter_by(bd.Axis.Y).group_by(bd.Axis.X)
        return bd.chamfer(ends[0] + ends[-1], length=min(thick, width) / 4)

    return "slotted_bar", params, make


ATTEMPTS = 4
FAMILIES = [screw, nut_or_washer, catalogue_flange, catalogue_gear, plate, turned, bracket, pocket_block, slotted_bar]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--seed", type=int, required=True)
    ap.add_argument("--count", type=int, default=24)
    ap.add_argument("--out", required=True)
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    rng = random.Random(args.seed)
    parts, failed = [], []
    for k in range(args.count):
        family = FAMILIES[k % len(FAMILIES)]
        name = f"h{args.seed}_{k:02d}_{family.__name__}"
        path = os.path.join(args.out, name + ".step")
        for _attempt in range(ATTEMPTS):  # a draw the CAD kernel refuses is recorded and drawn again
            source, params, make = family(rng)
            try:
                shape = make()
                faces = len(shape.faces())
                if faces == 0 or not bd.export_step(shape, path):
                    raise ValueError("no faces or export failed")
            except Exception as e:
                failed.append({"name": name, "source": source, "parameters": params,
                               "error": f"{type(e).__name__}: {e}"})
                print(f"refused draw for {name}: {type(e).__name__}: {e}", file=sys.stderr)
                continue
            parts.append({"file": name + ".step", "source": source, "parameters": params, "faces": faces})
            print(f"{name}: {faces} faces", flush=True)
            break
    with open(os.path.join(args.out, "MANIFEST.json"), "w") as fh:
        json.dump({"seed": args.seed, "parts": parts, "failed": failed}, fh, indent=1)
        fh.write("\n")
    print(f"{len(parts)} parts written, {len(failed)} draws refused by the CAD kernel")


if __name__ == "__main__":
    main()
