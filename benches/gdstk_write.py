#!/usr/bin/env python3
"""Times gdstk writing the flattened wafer polygons exported by examples/wafer_bench.rs.

usage: gdstk_write.py POLYS.json OUT.gds RUNS   (pip install gdstk)
Prints `gdstk_write_median_ms X` (library build from JSON is not timed).
"""
import json
import statistics
import sys
import time

import gdstk

polys = json.load(open(sys.argv[1]))
out, runs = sys.argv[2], int(sys.argv[3])
lib = gdstk.Library(unit=1e-6, precision=1e-9)
cell = lib.new_cell("WAFER_FLAT")
for p in polys:
    pts = [(x / 1000.0, y / 1000.0) for x, y in p["xy"][:-1]]
    cell.add(gdstk.Polygon(pts, layer=p["layer"], datatype=p["datatype"]))
ts = []
for _ in range(runs):
    t = time.perf_counter()
    lib.write_gds(out)
    ts.append((time.perf_counter() - t) * 1e3)
print(f"gdstk_polygons {len(polys)}")
print(f"gdstk_write_median_ms {statistics.median(ts):.3f}")
