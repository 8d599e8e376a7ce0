#!/usr/bin/env python3
"""scikit-fem (Morley element) on the plate that `examples/fe_bench.rs` times in tactfab.

Problem (identical in both codes): clamped 10 x 10 mm square plate, isotropic E = 169 GPa, nu = 0.3,
t = 100 um (D = E t^3 / (12 (1 - nu^2))), 1 N point load at the centre; reference
alpha_P = w D / (P b^2) = 0.0056120 (/work/shared/reference/fe-validation.md, clamped, a/b = 1).

Mesh: MeshTri.init_sqsymmetric (union-jack, a vertex at the centre) refined k times. The Morley
vertex dofs are point values, so the Dirac load at the centre vertex is the unit vector on that dof
(checked once against Basis.point_source, which costs a point search on every call); the deflection
at the centre is the same dof. Clamped: every boundary dof (vertex values and edge normal
derivatives) is zero. Solver: skfem.solve's default (scipy spsolve, SuperLU).

Timed per run (wall clock, median of the runs): mesh + basis + assembly + load + condense + solve +
read-out ("total", what tactfab's times include) and assembly + condense + solve alone.

Usage: python3 benches/skfem_plate.py [repeats=5] [max_refinements=7]
A mesh whose first run takes over SLOW_S seconds is run once. The last lines are machine-readable
(`RESULT ...`) for fe_bench.rs.
"""

import sys
import time

import numpy as np
import skfem
from skfem import BilinearForm, Basis, ElementTriMorley, MeshTri, condense, solve
from skfem.helpers import dd, ddot, trace

E_PA, NU, T_M = 169e9, 0.3, 100e-6
D_NM = E_PA * T_M**3 / (12.0 * (1.0 - NU**2))
SIDE_M = 0.01
FORCE_N = 1.0
ALPHA_REF = 0.0056120
SLOW_S = 10.0


@BilinearForm
def plate_bending(u, v, _):
    """Kirchhoff bending energy, isotropic: D ((1 - nu) w,ij v,ij + nu lap w lap v)."""
    ddu, ddv = dd(u), dd(v)
    return D_NM * ((1.0 - NU) * ddot(ddu, ddv) + NU * trace(ddu) * trace(ddv))


def mesh(k):
    return MeshTri.init_sqsymmetric().refined(k).scaled(SIDE_M)


def centre_dof(basis, m):
    c = int(np.argmin(np.sum((m.p - SIDE_M / 2) ** 2, axis=0)))
    assert np.allclose(m.p[:, c], SIDE_M / 2), "the mesh needs a vertex at the centre"
    return int(basis.nodal_dofs[0, c])


def run(k):
    """One full solve; returns (alpha, dofs, total_s, assemble_solve_s)."""
    t0 = time.perf_counter()
    m = mesh(k)
    basis = Basis(m, ElementTriMorley())
    t1 = time.perf_counter()
    stiffness = plate_bending.assemble(basis)
    load = np.zeros(basis.N)
    ic = centre_dof(basis, m)
    load[ic] = FORCE_N
    w = solve(*condense(stiffness, load, D=basis.get_dofs()))
    w_centre_m = w[ic]
    t2 = time.perf_counter()
    return w_centre_m * D_NM / (FORCE_N * SIDE_M**2), basis.N, t2 - t0, t2 - t1


def check_point_load(k=2):
    """The vertex-dof load equals skfem's point_source at the centre (not timed)."""
    m = mesh(k)
    basis = Basis(m, ElementTriMorley())
    f = basis.point_source(np.array([SIDE_M / 2, SIDE_M / 2]))
    unit = np.zeros(basis.N)
    unit[centre_dof(basis, m)] = 1.0
    assert np.abs(f - unit).max() < 1e-9, "point_source differs from the vertex dof"


def main():
    repeats = int(sys.argv[1]) if len(sys.argv) > 1 else 5
    max_k = int(sys.argv[2]) if len(sys.argv) > 2 else 7
    check_point_load()
    print(f"scikit-fem {skfem.__version__}, Morley, clamped square 10 mm, E = {E_PA:.4g} Pa, nu = {NU}, "
          f"t = {T_M * 1e6:.0f} um, D = {D_NM:.6g} N m, P = {FORCE_N} N at the centre, alpha_ref = {ALPHA_REF}")
    print(f"{'mesh':<20} {'dofs':>8} {'runs':>5} {'total_ms':>11} {'asm+solve_ms':>13} {'alpha':>12} {'rel_err':>10}")
    rows = []
    run(1)  # warm-up: imports, first-call caches
    for k in range(1, max_k + 1):
        first = run(k)
        results = [first]
        if first[2] < SLOW_S:
            results += [run(k) for _ in range(repeats - 1)]
        alpha, dofs = first[0], first[1]
        total_ms = 1e3 * float(np.median([r[2] for r in results]))
        asm_ms = 1e3 * float(np.median([r[3] for r in results]))
        err = abs(alpha - ALPHA_REF) / ALPHA_REF
        rows.append((k, dofs, total_ms, asm_ms, err))
        print(f"{'sqsymmetric r=' + str(k):<20} {dofs:>8} {len(results):>5} {total_ms:>11.1f} {asm_ms:>13.1f} "
              f"{alpha:>12.8f} {err:>10.3e}", flush=True)
    for target in (0.01, 0.001):
        hit = [r for r in rows if r[4] <= target]
        if hit:
            best = min(hit, key=lambda r: r[2])
            print(f"smallest time to {target:.1%}: {best[2]:.1f} ms total, {best[3]:.1f} ms assemble+solve "
                  f"(r={best[0]}, {best[1]} dofs)")
            print(f"RESULT target={target} total_ms={best[2]:.4f} asm_solve_ms={best[3]:.4f} dofs={best[1]}")
        else:
            print(f"smallest time to {target:.1%}: not reached up to r={max_k}")
            print(f"RESULT target={target} none")


if __name__ == "__main__":
    main()
