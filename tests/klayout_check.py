#!/usr/bin/env python3
"""Independent read-back of a tactfab mask set with KLayout's Python package.

usage: klayout_check.py MASKS.gds SVG_DIR EXPECTED.json

Checks cells, layers, die bbox, merged tooth islands and their areas (top + compensators), the
nine disjoint electrodes and their areas, the two support strips, AREF-stepped dies inside the
wafer's usable radius, strange polygons, width/space, and that every SVG carries the same
polygons as its GDS layer (XOR area zero). Exits 1 on the first failed group, printing why.
"""
import json
import os
import re
import sys
import xml.etree.ElementTree as ET

import klayout.db as db  # pip install klayout

failures = []


def check(cond, msg):
    print(("ok   " if cond else "FAIL ") + msg)
    if not cond:
        failures.append(msg)


def main():
    gds, svg_dir, exp_path = sys.argv[1:4]
    exp = json.load(open(exp_path))
    ly = db.Layout()
    ly.read(gds)
    check(abs(ly.dbu - 0.001) < 1e-12, f"database unit 1 nm (got {ly.dbu} um)")
    cells = {c.name: c for c in ly.each_cell()}
    check(set(cells) == {"MIS_GRASPER_DIE", "MIS_GRASPER_TEST_DIE", "MIS_GRASPER_TOOTH", "MIS_GRASPER_WAFER"}, f"cells {sorted(cells)}")
    tops = [c.name for c in ly.top_cells()]
    check(tops == ["MIS_GRASPER_WAFER"], f"one top cell, the wafer (got {tops})")
    layers = {(i.layer, i.datatype) for i in ly.layer_infos()}
    for ld in [(1, 0), (2, 0), (3, 0), (10, 0), (63, 0), (64, 0), (65, 0)]:
        check(ld in layers, f"layer {ld[0]}/{ld[1]} present")

    die = cells["MIS_GRASPER_DIE"]
    wafer = cells["MIS_GRASPER_WAFER"]

    def region(cell, l, d=0):
        li = ly.find_layer(l, d)
        return db.Region(cell.begin_shapes_rec(li)) if li is not None else db.Region()

    um2 = 1e6  # dbu^2 per um^2
    L, W = exp["die_length_um"], exp["die_width_um"]
    ob = region(die, 64).bbox()
    check((ob.width(), ob.height()) == (round(L * 1000), round(W * 1000)) and (ob.left, ob.bottom) == (0, 0),
          f"die outline {ob.width() / 1000} x {ob.height() / 1000} um at the origin")

    # Front Si: merged islands big enough to be teeth (labels are far smaller).
    front = region(die, 1).merged()
    islands = [p for p in front.each() if p.area() > 1e6 * um2]
    check(len(islands) == exp["teeth"], f"{len(islands)} merged tooth islands, expected {exp['teeth']}")
    a, o, top = exp["comp_side_um"], exp["comp_overlap_um"], exp["top_um"]
    for p in islands:
        ok_area = abs(p.area() / um2 - exp["island_area_um2"]) < 1.0
        b = p.bbox()
        span = top + 2 * (a - o)
        ok_box = abs(b.width() / 1000 - span) < 0.003 and abs(b.height() / 1000 - span) < 0.003
        inset = round((a - o) * 1000)
        top_box = db.Region(db.Box(b.left + inset, b.bottom + inset, b.right - inset, b.top - inset))
        isl = db.Region(p)
        top_inside = (top_box - isl).is_empty() and abs(top_box.area() / um2 - top * top) < 1.0
        comps = [q for q in (isl - top_box).each()]
        ok_comps = len(comps) == 4 and all(abs(q.area() / um2 - (a * a - o * o)) < 0.5 for q in comps)
        if not (ok_area and ok_box and top_inside and ok_comps):
            check(False, f"island at {b}: area {p.area() / um2:.1f} (expected {exp['island_area_um2']:.1f}), "
                         f"box {ok_box}, top inside {top_inside}, compensators {[q.area() / um2 for q in comps]}")
            break
    else:
        check(True, f"every island holds its {top} um top and 4 compensators of {a:.3f} um (area {a * a - o * o:.1f} um2 outside the top)")

    # PVDF: nine disjoint islands with the expected areas.
    pv = region(die, 3).merged()
    el = db.Region([p for p in pv.each() if p.area() > 1e6 * um2])
    areas = sorted(p.area() / um2 for p in el.each())
    want = sorted(exp["electrode_areas_um2"])
    check(len(areas) == 9, f"{len(areas)} electrode islands, expected 9")
    check(len(areas) == len(want) and all(abs(x - y) < 1.0 for x, y in zip(areas, want)), f"electrode areas {areas} vs {want}")
    gap = round(exp["min_electrode_gap_um"] * 1000)
    check(el.space_check(gap).is_empty(), f"electrodes at least {gap / 1000} um apart")

    # Back Si: two 2.5 mm support strips along the full length.
    back = region(die, 2).merged()
    strips = [p for p in back.each() if p.area() > 1e6 * um2]
    sw = exp["support_width_um"]
    ok = len(strips) == 2 and all(abs(p.bbox().width() / 1000 - L) < 1e-6 and abs(p.bbox().height() / 1000 - sw) < 1e-6 and p.is_box() for p in strips)
    check(ok, f"two support strips {L} x {sw} um (got {[(p.bbox().width() / 1000, p.bbox().height() / 1000) for p in strips]})")
    ys = sorted(p.bbox().bottom for p in strips)
    check(ys == [0, round((W - sw) * 1000)], f"supports at y = 0 and y = W - w (got {ys})")

    # Wafer: AREF rows of dies, all inside the usable radius.
    n_dies = 0
    arrays = 0
    r2 = (exp["usable_radius_um"] * 1000) ** 2
    inside = True
    for inst in wafer.each_inst():
        if inst.cell.name != "MIS_GRASPER_DIE":
            continue
        if inst.is_regular_array():
            arrays += 1
            na, nb, va, vb = inst.na, inst.nb, inst.a, inst.b
        else:
            na, nb, va, vb = 1, 1, db.Vector(), db.Vector()
        for i in range(na):
            for j in range(nb):
                d = inst.trans.disp + va * i + vb * j
                for cx, cy in [(0, 0), (L, 0), (0, W), (L, W)]:
                    x, y = d.x + cx * 1000, d.y + cy * 1000
                    inside &= x * x + y * y <= r2 + 1
                n_dies += 1
    check(arrays >= 2 and n_dies > 0, f"{n_dies} dies in {arrays} AREF rows")
    check(inside, "every die lies inside the wafer less its edge exclusion")
    # The wafer map SVG: one rectangle per GDS die, the mark sites ringed.
    wroot = ET.parse(os.path.join(svg_dir, "mis-grasper-wafer.svg")).getroot()
    ns = "{http://www.w3.org/2000/svg}"
    groups = {g.get("id"): g for g in wroot.iter(ns + "g")}
    rects = list(groups["dies"].iter(ns + "rect")) if "dies" in groups else []
    rings = list(groups["marks"].iter(ns + "circle")) if "marks" in groups else []
    check(len(rects) == n_dies and wroot.get("data-dies") == str(n_dies) and len(rings) >= 1,
          f"wafer.svg: {len(rects)} dies (GDS {n_dies}), {len(rings)} mark sites ringed")
    # The wafer edge and usable circle sit on their own layer, not on the die outline.
    wo = region(wafer, 65).bbox()
    ru = exp["usable_radius_um"] * 1000
    check(wo.width() > 2 * ru and abs(wo.center().x) <= 1 and abs(wo.center().y) <= 1,
          f"wafer outline on 65/0, {wo.width() / 1000} um across, centred")
    li64 = ly.find_layer(64, 0)
    check(li64 is None or wafer.shapes(li64).is_empty(), "64/0 holds die outlines only (nothing drawn in the wafer cell)")

    # No strange polygons anywhere; width and space on the printing layers of the die and wafer marks.
    for (l, d) in sorted(layers):
        r = region(wafer, l, d)
        check(r.strange_polygon_check().is_empty(), f"layer {l}/{d}: no strange polygons ({r.count()} polygons)")
    for l in (1, 2, 3):
        r = region(wafer, l)
        wv = r.width_check(round(exp["min_width_um"] * 1000)).count()
        sv = r.space_check(round(exp["min_space_um"] * 1000)).count()
        check(wv == 0 and sv == 0, f"layer {l}/0: width >= {exp['min_width_um']} um and space >= {exp['min_space_um']} um (violations {wv}, {sv})")
    check(db.Texts(wafer.begin_shapes_rec(ly.find_layer(63, 0))).count() > 9, "non-printing TEXT annotations on 63/0")
    # Repeated over the wafer, the die's texts stay short (electrode names) so they do not run
    # into each other at wafer zoom; the die's description is the wafer cell's legend, once.
    die_texts = [t.text.string for t in die.shapes(ly.find_layer(63, 0)).each() if t.is_text()]
    check(die_texts and all(len(t) <= 4 for t in die_texts), f"die texts are short labels: {die_texts}")
    wafer_texts = [t.text.string for t in wafer.shapes(ly.find_layer(63, 0)).each() if t.is_text()]
    check(any(t.startswith("DIE TEETH") for t in wafer_texts)
          and any("WIRE)" in t for t in wafer_texts), f"the die's legend in the wafer cell: {wafer_texts}")

    # SVG per mask: same polygons as the GDS layer (mirror undone for mirrored masks).
    for name, ld, mirrored in exp["masks"]:
        path = os.path.join(svg_dir, f"mis-grasper-{name}.svg")
        root = ET.parse(path).getroot()
        # The die, and 2 mm under it for the scale bar.
        H = W + 2000.0
        size_ok = root.get("width") == f"{L / 1000:.6f}mm" and root.get("height") == f"{H / 1000:.6f}mm"
        check(size_ok and root.get("viewBox") == f"0 0 {L:.3f} {H:.3f}", f"{name}.svg size in mm, viewBox in um")
        scale = [g for g in root.iter("{http://www.w3.org/2000/svg}g") if g.get("id") == "scale"]
        bar = scale[0].find("{http://www.w3.org/2000/svg}rect") if scale else None
        label = scale[0].find("{http://www.w3.org/2000/svg}text") if scale else None
        check(bar is not None and label is not None
              and abs(float(bar.get("width")) / 1000 - float(label.text.split()[0])) < 1e-9
              and float(bar.get("y")) > W,
              f"{name}.svg: scale bar under the die, its label its length ({label.text if label is not None else None})")
        lnum, dnum = map(int, ld.split("/"))
        if name == "pvdf":
            notes = [g for g in root.iter("{http://www.w3.org/2000/svg}g") if g.get("id") == "notes"]
            names = [t.text for t in notes[0].iter("{http://www.w3.org/2000/svg}text")] if notes else []
            pads = list(notes[0].iter("{http://www.w3.org/2000/svg}rect")) if notes else []
            check(len(names) == 9 and len(pads) == 9 and notes[0].get("data-printing") == "no",
                  f"pvdf.svg: non-printing names and wire-pad outlines of the 9 islands ({names})")
        groups = [g for g in root.iter("{http://www.w3.org/2000/svg}g") if g.get("data-gds-layer") == ld]
        check(len(groups) == 1, f"{name}.svg: one group for layer {ld}")
        polys = []
        for pe in groups[0].iter("{http://www.w3.org/2000/svg}path"):
            for ring in re.findall(r"M([^MZ]*)Z", pe.get("d")):
                nums = [float(v) for v in re.findall(r"-?\d+\.\d{3}", ring)]
                pts = []
                for k in range(0, len(nums), 2):
                    x, y = nums[k], W - nums[k + 1]
                    if mirrored:
                        x = L - x
                    pts.append(db.Point(round(x * 1000), round(y * 1000)))
                polys.append(db.Polygon(pts))
        svg_r = db.Region(polys)
        gds_r = region(die, lnum, dnum)
        x = (svg_r ^ gds_r).area()
        check(x == 0 and abs(svg_r.area() - gds_r.area()) == 0 and svg_r.area() > 0,
              f"{name}.svg: {len(polys)} polygons, area {svg_r.area() / um2:.1f} um2, XOR with GDS {ld} = {x}")

    # Layer properties: every layer named, with the source KLayout maps onto the GDS layer.
    lyp = ET.parse(os.path.join(svg_dir, "mis-grasper.lyp")).getroot()
    sources = {p.findtext("source"): p.findtext("name") for p in lyp.findall("properties")}
    want_src = {f"{l}/{d}@1" for (l, d) in [(1, 0), (2, 0), (3, 0), (10, 0), (63, 0), (64, 0), (65, 0)]}
    check(set(sources) == want_src and all(sources.values()), f"lyp names every layer: {sources}")
    lv_ok = True
    try:
        import klayout.lay as lay
        lv = lay.LayoutView()
        lv.load_layout(gds, True)
        lv.load_layer_props(os.path.join(svg_dir, "mis-grasper.lyp"))
        names = sorted(n.name for n in lv.each_layer())
        lv_ok = len(names) == 7
    except ImportError:
        names = "klayout.lay not available"
    check(lv_ok, f"KLayout loads the lyp onto the layout: {names}")

    if failures:
        print(f"{len(failures)} CHECKS FAILED")
        sys.exit(1)
    print("ALL CHECKS PASSED")


if __name__ == "__main__":
    main()
