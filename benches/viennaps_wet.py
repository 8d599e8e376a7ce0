"""The peer of examples/etch_sim_bench.rs: the same tooth cell (drawn polygons) and rate table
etched with ViennaPS's WetEtching model (3-D level set, stencil local Lax-Friedrichs), timed.

    cargo run --release --example etch_sim_bench -- 1 --export DIR
    python3 benches/viennaps_wet.py DIR [--grid-um G]
    cargo run --release --example etch_sim_bench -- 1 --viennaps DIR

Reads DIR/cell.json, writes DIR/mask.gds (the cell's polygons, um user units) and
DIR/viennaps.json: the corner deviation along the tooth diagonal (> 0 outwards, as tactfab's),
the mid-edge undercut, and the wall time. The top edge is read from the silicon surface mesh:
silicon surface points within half a cell of z = 0 are the tooth top still under the mask.

The free-mesa corner check (the closed form sqrt 2 R110 t of the uncompensated convex corner):

    python3 benches/viennaps_wet.py DIR --mesa 300 --time-h 1.5 --grid-um 2 [--scheme S] [--alpha A]

etches a quarter of a free SIDE um square mesa (its centre lines are the domain's reflective
sides at x = y = 0, the mesa's edge SIDE/2 from them, the domain SIDE wide) with R100 24, R110
42, R111 0.8 um/h and R311 on the {100}-{111} line (so tactfab's table without a {311} entry is
the same function) and writes DIR/viennaps.json with its corner. --scheme names a
viennaps.SpatialScheme (default STENCIL_LOCAL_LAX_FRIEDRICHS_1ST_ORDER, as ViennaPS's
cantileverWetEtching example), --alpha sets AdvectionParameters.dissipationAlpha.
"""

import json
import math
import struct
import sys
import time

import viennals as ls
import viennals.d3 as ls3
import viennaps
import viennaps.d3 as psd
from viennaps import AdvectionParameters, BoundaryType, Material, SpatialScheme


def gds(path, polygons, extra=()):
    """A minimal GDSII file: one structure, one boundary per polygon on layer 1 (and each of
    `extra` on layer 2: it only widens the domain's bounds), 1 nm grid."""

    def rec(kind, dtype, payload=b""):
        return struct.pack(">HBB", 4 + len(payload), kind, dtype) + payload

    def real8(x):
        # GDSII excess-64 base-16 real.
        if x == 0:
            return b"\0" * 8
        sign = 0x80 if x < 0 else 0
        x = abs(x)
        exp = 64
        while x >= 1:
            x /= 16
            exp += 1
        while x < 1 / 16:
            x *= 16
            exp -= 1
        mant = int(x * (1 << 56))
        return struct.pack(">B", sign | exp) + mant.to_bytes(7, "big")

    out = rec(0x00, 0x02, struct.pack(">h", 600))
    out += rec(0x01, 0x02, struct.pack(">12h", *([0] * 12)))
    out += rec(0x02, 0x06, b"CELL")
    out += rec(0x03, 0x05, real8(1e-3) + real8(1e-9))
    out += rec(0x05, 0x02, struct.pack(">12h", *([0] * 12)))
    out += rec(0x06, 0x06, b"TOOTHCEL")
    for layer, poly in [(1, q) for q in polygons] + [(2, q) for q in extra]:
        pts = [(round(x * 1000), round(y * 1000)) for x, y in poly]
        if pts[0] != pts[-1]:
            pts.append(pts[0])
        out += rec(0x08, 0x00)
        out += rec(0x0D, 0x02, struct.pack(">h", layer))
        out += rec(0x0E, 0x02, struct.pack(">h", 0))
        out += rec(0x10, 0x03, b"".join(struct.pack(">ii", x, y) for x, y in pts))
        out += rec(0x11, 0x00)
    out += rec(0x07, 0x00)
    out += rec(0x04, 0x00)
    with open(path, "wb") as f:
        f.write(out)


def opt(name, default):
    return sys.argv[sys.argv.index(name) + 1] if name in sys.argv else default


def mesa_cell(side_um, time_h):
    """A quarter of a free square mesa, its centre at the origin (see the module comment)."""
    h = side_um / 2
    return {
        "cell_um": [side_um, side_um],
        "grid_um": 2.0,
        "time_h": time_h,
        "tooth_top_um": side_um,
        "rates_um_per_h": {"r100": 24.0, "r110": 42.0, "r111": 0.8, "r311": 24.0 + (0.8 - 24.0) / 3},
        "polygons": [[[0, 0], [h, 0], [h, h], [0, h]]],
        "quarter_mesa": True,
    }


def main():
    d = sys.argv[1]
    viennaps.Logger.setLogLevel(viennaps.LogLevel.WARNING)
    if "--mesa" in sys.argv:
        cell = mesa_cell(float(opt("--mesa", 300)), float(opt("--time-h", 1.5)))
    else:
        cell = json.load(open(f"{d}/cell.json"))
    grid = float(opt("--grid-um", cell["grid_um"]))
    lx, ly = cell["cell_um"]
    half = cell["tooth_top_um"] / 2
    r = cell["rates_um_per_h"]
    quarter = cell.get("quarter_mesa", False)
    # The quarter mesa's domain: a speck on layer 2 at the far corner sets the bounds.
    extra = [[[lx - 1, ly - 1], [lx, ly - 1], [lx, ly], [lx - 1, ly]]] if quarter else []
    gds(f"{d}/mask.gds", cell["polygons"], extra)

    t0 = time.perf_counter()
    mask = psd.GDSGeometry(grid)
    mask.setBoundaryConditions(
        [BoundaryType.REFLECTIVE_BOUNDARY, BoundaryType.REFLECTIVE_BOUNDARY, BoundaryType.INFINITE_BOUNDARY]
    )
    # --pad-um P: a free mesa (the closed-form corner check) rather than a cell filled to its
    # mirror sides.
    pad = float(sys.argv[sys.argv.index("--pad-um") + 1]) if "--pad-um" in sys.argv else 0.0
    mask.setBoundaryPadding(pad, pad)
    psd.GDSReader(mask, f"{d}/mask.gds").apply()
    bounds = mask.getBounds()
    # mask=False: the drawn polygons are the oxide (light field), not holes in it.
    mask_ls = mask.layerToLevelSet(1, 0.0, 4 * grid, False, False)
    domain = psd.Domain()
    domain.insertNextLevelSetAsMaterial(mask_ls, Material.Mask)
    psd.MakePlane(domain, 0.0, Material.Si, True).apply()
    per_s = 1 / 3600.0
    model = psd.WetEtching(
        direction100=[0.707106781187, 0.707106781187, 0.0],
        direction010=[-0.707106781187, 0.707106781187, 0.0],
        rate100=r["r100"] * per_s,
        rate110=r["r110"] * per_s,
        rate111=r["r111"] * per_s,
        rate311=r["r311"] * per_s,
        materialRates=[(Material.Si, -1.0)],
    )
    params = AdvectionParameters()
    scheme = opt("--scheme", "STENCIL_LOCAL_LAX_FRIEDRICHS_1ST_ORDER")
    params.spatialScheme = getattr(SpatialScheme, scheme)
    if "--alpha" in sys.argv:
        params.dissipationAlpha = float(opt("--alpha", 1.0))
    process = psd.Process()
    process.setDomain(domain)
    process.setProcessModel(model)
    process.setProcessDuration(cell["time_h"] * 3600.0)
    process.setParameters(params)
    process.apply()
    seconds = time.perf_counter() - t0

    # The silicon surface (the last level set), as a mesh; its points at the top level.
    # The silicon alone: the top level set (silicon and the mask under it) less the mask.
    sets = domain.getLevelSets()
    si = ls3.Domain(sets[-1])
    ls3.BooleanOperation(si, sets[0], ls.BooleanOperationEnum.RELATIVE_COMPLEMENT).apply()
    mesh = ls.Mesh()
    ls3.ToSurfaceMesh(si, mesh).apply()
    nodes = mesh.getNodes()
    x0, y0 = bounds[0], bounds[2]
    zs = [z for _, _, z in nodes]
    print(f"silicon surface: {len(nodes)} points, z {min(zs):.1f} .. {max(zs):.1f} um", file=sys.stderr)
    top = [(x - x0, y - y0) for x, y, z in nodes if z > -0.5 * grid]
    if quarter:
        pass  # the mesa's centre is the origin
    elif pad > 0:
        # A free mesa: its upper-right quarter, from its centre.
        c = cell["centre_um"]
        top = [(x - c[0], y - c[1]) for x, y in top if x >= c[0] and y >= c[1]]
    else:
        # The simulated tooth's quarter is the cell's lower-left half (the diagonal
        # neighbour's is the upper-right one).
        top = [(x, y) for x, y in top if x + y < 0.5 * (lx + ly)]
    diag = [(x + y) / math.sqrt(2) for x, y in top if abs(x - y) < grid]
    # The corner below the top: the farthest silicon surface point along the diagonal in
    # slabs one cell thick, from the mask down (a {110} bevel through the corner puts it |z|
    # farther out at depth z, so s(z) - |z| is where that bevel meets the mask plane).
    profile = []
    if quarter:
        depth = max(-z for _, _, z in nodes)
        k = 0
        while (k + 0.5) * grid < depth:
            zc = -k * grid
            pts = [(x + y) / math.sqrt(2) for x, y, z in nodes
                   if abs(x - y) < grid and abs(z - zc) <= 0.5 * grid]
            if pts:
                profile.append([zc, max(pts) - half * math.sqrt(2)])
            k += 1
    edge = [x for x, y in top if y < grid]
    out = {
        "version": str(viennaps.version),
        "grid_um": grid,
        "scheme": scheme,
        "dissipation_alpha": params.dissipationAlpha,
        "time_h": cell["time_h"],
        "seconds": seconds,
        "corner_deviation_um": (max(diag) - half * math.sqrt(2)) if diag else None,
        "edge_undercut_um": (half - max(edge)) if edge else None,
        "bounds_um": list(bounds),
        "corner_at_depth_um": profile,
    }
    json.dump(out, open(f"{d}/viennaps.json", "w"), indent=1)
    print(json.dumps(out))


if __name__ == "__main__":
    main()
