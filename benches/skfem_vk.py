#!/usr/bin/env python3
"""scikit-fem peer for tactfab's large-deflection (von Karman) plate rung.

Problem (SI): clamped 10 x 10 mm square plate, t = 100 um, isotropic E = 169 GPa, nu = 0.3,
D = E t^3 / (12 (1 - nu^2)), A = E t / (1 - nu^2). Every edge clamped (w = 0, normal slope 0) and
immovable in-plane (u = v = 0). Von Karman strain eps = (u_x + w_x^2/2, v_y + w_y^2/2,
u_y + v_x + w_x w_y), curvature kappa = (w_xx, w_yy, 2 w_xy); energy
1/2 int (eps^T A_mat eps + kappa^T D_mat kappa) dA - int q w dA (or - P w(centre)), with
A_mat = A [[1, nu, 0], [nu, 1, 0], [0, 0, (1 - nu)/2]] and D_mat the same with D.
Load cases: (1) uniform q with w_lin/t in PRESSURE_STEPS, w_lin = 0.00126532 q a^4 / D;
(2) centre point load P with w_lin/t in POINT_STEPS, w_lin = 0.0056120 P a^2 / D
(clamped alpha_q, alpha_P for a/b = 1, ../shared/reference/fe-validation.md).

Elements: w on ElementTriArgyris (C1 quintic: conforming, so the energy above is exact on the
discrete space and the centre deflection is a vertex dof), u, v on ElementVector(ElementTriP2()).
Mesh: MeshTri.init_sqsymmetric (a vertex at the centre, where the point load sits on the vertex
value dof) refined k times. Clamped: w, its first derivatives, its tangential second derivative and
w_xy vanish along an edge, and the edge normal-derivative dofs; the normal second derivative
(u_xx on x = const, u_yy on y = const) stays free -- it carries the edge moment.

Scaling: x/a, w/t, (u, v) a/t^2 and energy / (D t^2 / a^2). The energy keeps its form with unit
D_mat, A_mat times A t^2 / D (= 12) and q a^4 / (D t), P a^2 / (D t) as loads. skfem's Argyris basis
inverts a monomial Vandermonde matrix in global coordinates per element, which is hopeless in metres
(x^5 ~ 1e-10); on the unit square it and the Newton tolerance stay well conditioned.

Solver: Newton with the consistent tangent (residual and tangent share one quadrature, so the
tangent is exact; checked by central differences on a coarse mesh), load stepping through the listed
w_lin/t values, each step until the relative correction of w and of (u, v) is < TOL; SuperLU with a
symmetric ordering. Self-checks: tangent vs finite differences, the tiny-load limit against the
linear coefficient, the centre membrane force tensile. The linear limit is checked at
w_lin/t = TINY, not at the smallest listed load: membrane stiffening already takes 3 % of the
deflection at w_lin/t = 0.25 (pressure) and 8 % at 0.5 (point load); that is physics (the cubic
term, ~(w/t)^2), not error.

Usage: python3 benches/skfem_vk.py [max_refinement=4]
r = 1..max_refinement; r = 4 (18k dofs) takes ~35 s on 2 cores, r = 5 (71k dofs) ~4 min. The last
lines are machine-readable (`RESULT ...`), one per load case at the finest mesh: change = relative
change of w from the previous refinement, seconds = wall time of that load step's Newton iterations
(assembly, factorisation, solve; mesh/basis setup and earlier steps excluded).
"""

import sys
import time

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import splu
import skfem
from skfem import Basis, BilinearForm, ElementTriArgyris, ElementTriP2, ElementVector, LinearForm, MeshTri
from skfem.helpers import dd, ddot, dot, eye, grad, mul, prod, sym_grad, trace, transpose

E_PA, NU, T_M, SIDE_M = 169e9, 0.3, 100e-6, 0.01
D_NM = E_PA * T_M**3 / (12.0 * (1.0 - NU**2))
A_NPM = E_PA * T_M / (1.0 - NU**2)
C_MEM = A_NPM * T_M**2 / D_NM  # membrane weight in the scaled energy (12)
ALPHA_Q, ALPHA_P = 0.00126532, 0.0056120
PRESSURE_STEPS = (0.25, 0.5, 1.0, 2.0, 4.0)
POINT_STEPS = (0.5, 1.0, 2.0, 4.0)
TINY = 1e-3  # w_lin/t of the linear-limit self-check
INTORDER = 8  # (grad w)^2 terms are degree 8 per factor pair: enough, and shared by every form
TOL, MAX_NEWTON = 1e-10, 30


def hooke(e):
    """Isotropic plane-stress law with unit modulus, tensor strain in (same as the A_mat/A matrix)."""
    return (1.0 - NU) * e + NU * eye(trace(e), 2)


def membrane_force(gu, gw):
    """Scaled membrane force tensor N = C_MEM hooke(sym grad u + grad w grad w / 2)."""
    return C_MEM * hooke(0.5 * (gu + transpose(gu)) + 0.5 * prod(gw, gw))


@BilinearForm
def k_bend(dw, vw, _):
    """Bending: (1 - nu) w,ij v,ij + nu lap w lap v (= kappa^T D_mat kappa / D)."""
    return (1.0 - NU) * ddot(dd(dw), dd(vw)) + NU * trace(dd(dw)) * trace(dd(vw))


@BilinearForm
def k_mem(du, vu, _):
    """In-plane stiffness (state independent)."""
    return C_MEM * ddot(hooke(sym_grad(du)), sym_grad(vu))


@BilinearForm
def k_uw(dw, vu, p):
    """d R_u / d w: grad dw . hooke(sym grad vu) grad w."""
    return C_MEM * dot(grad(dw), mul(hooke(sym_grad(vu)), p.gw))


@BilinearForm
def k_ww(dw, vw, p):
    """d R_w / d w beyond bending: grad vw . G grad dw, G precomputed per quadrature point."""
    return dot(grad(vw), mul(p.G, grad(dw)))


@LinearForm
def r_u(vu, p):
    """Membrane residual N : grad vu."""
    return ddot(p.N, sym_grad(vu))


@LinearForm
def r_w(vw, p):
    """Membrane part of the bending residual: grad vw . N grad w."""
    return dot(grad(vw), mul(p.N, p.gw))


@LinearForm
def unit_pressure(vw, _):
    return vw


class Plate:
    """Bases, boundary conditions and the state-independent matrices on one mesh."""

    def __init__(self, k):
        self.mesh = MeshTri.init_sqsymmetric().refined(k)
        self.bw = Basis(self.mesh, ElementTriArgyris(), intorder=INTORDER)
        self.bu = Basis(self.mesh, ElementVector(ElementTriP2()), intorder=INTORDER)
        self.nw, self.N = self.bw.N, self.bw.N + self.bu.N
        on_x = lambda x: np.isclose(x[0], 0.0) | np.isclose(x[0], 1.0)
        on_y = lambda x: np.isclose(x[1], 0.0) | np.isclose(x[1], 1.0)
        fixed = np.concatenate([self.bw.get_dofs(on_x, skip=['u_xx']).all(),
                                self.bw.get_dofs(on_y, skip=['u_yy']).all(),
                                self.nw + self.bu.get_dofs().all()])
        self.free = np.setdiff1d(np.arange(self.N), fixed)
        c = int(np.argmin(np.sum((self.mesh.p - 0.5) ** 2, axis=0)))
        assert np.allclose(self.mesh.p[:, c], 0.5), "the mesh needs a vertex at the centre"
        self.centre = int(self.bw.nodal_dofs[0, c])
        self.centre_elems = np.nonzero(np.any(self.mesh.t == c, axis=0))[0]
        self.kb = k_bend.assemble(self.bw)
        self.km = k_mem.assemble(self.bu)
        self.f_pressure = np.concatenate([unit_pressure.assemble(self.bw), np.zeros(self.bu.N)])
        self.f_point = np.zeros(self.N)
        self.f_point[self.centre] = 1.0

    def fields(self, x):
        """grad w and N at the quadrature points."""
        gw = self.bw.interpolate(x[:self.nw]).grad
        return gw, membrane_force(self.bu.interpolate(x[self.nw:]).grad, gw)

    def residual(self, x):
        gw, n = self.fields(x)
        rw = self.kb @ x[:self.nw] + r_w.assemble(self.bw, gw=gw, N=n)
        return np.concatenate([rw, r_u.assemble(self.bu, N=n)])

    def tangent(self, x):
        gw, n = self.fields(x)
        # d(N grad w)/dw: C_MEM[(1 + nu)/2 gw gw^T + (1 - nu)/2 |gw|^2 I] (hooke of sym(gw dw^T)
        # applied to gw, expanded) plus the initial-stress part N.
        g = C_MEM * (0.5 * (1.0 + NU) * prod(gw, gw) + 0.5 * (1.0 - NU) * eye(dot(gw, gw), 2)) + n
        kww = self.kb + k_ww.assemble(self.bw, G=g)
        kuw = k_uw.assemble(self.bw, self.bu, gw=gw)
        return sp.bmat([[kww, kuw.T], [kuw, self.km]], format='csc')

    def centre_membrane_force(self, x):
        """N_xx, N_yy (N/m) averaged over the elements at the centre vertex."""
        _, n = self.fields(x)
        dx = self.bw.dx[self.centre_elems]
        avg = [np.sum(n[i, i][self.centre_elems] * dx) / np.sum(dx) for i in range(2)]
        return np.array(avg) * D_NM / SIDE_M**2


def newton(plate, x, load):
    """Newton from x to equilibrium under `load`; returns (x, iterations)."""
    for it in range(1, MAX_NEWTON + 1):
        r = plate.residual(x) - load
        k = plate.tangent(x)[plate.free][:, plate.free]
        dx = np.zeros_like(x)
        # The tangent is symmetric positive definite (tensile membrane): a symmetric ordering with
        # no pivoting; SuperLU's default partial pivoting undoes the ordering (10-40x the fill).
        lu = splu(k.tocsc(), permc_spec='MMD_AT_PLUS_A', diag_pivot_thresh=0.0,
                  options=dict(SymmetricMode=True))
        dx[plate.free] = -lu.solve(r[plate.free])
        x = x + dx
        nw = plate.nw
        rel_w = np.linalg.norm(dx[:nw]) / np.linalg.norm(x[:nw])
        norm_u = np.linalg.norm(x[nw:])
        rel_u = np.linalg.norm(dx[nw:]) / norm_u if norm_u > 0 else np.inf
        if max(rel_w, rel_u) < TOL:
            return x, it
    raise RuntimeError(f"Newton did not converge in {MAX_NEWTON} iterations (w {rel_w:.1e}, u {rel_u:.1e})")


def run_case(plate, load, alpha, steps):
    """Load steps through `steps` (w_lin/t); per step (w/t, iterations, seconds, x)."""
    x, out = np.zeros(plate.N), []
    for s in steps:
        t0 = time.perf_counter()
        x, its = newton(plate, x, load * s / alpha)
        out.append((x[plate.centre], its, time.perf_counter() - t0, x))
    return out


def check_tangent(k=1, h=1e-5):
    """Relative difference of K d and the central difference of the residual at a random state."""
    plate = Plate(k)
    rng = np.random.default_rng(1)
    x, d = np.zeros(plate.N), np.zeros(plate.N)
    x[plate.free] = rng.standard_normal(plate.free.size)
    d[plate.free] = rng.standard_normal(plate.free.size)
    fd = (plate.residual(x + h * d) - plate.residual(x - h * d)) / (2 * h)
    kd = plate.tangent(x) @ d
    return np.linalg.norm((fd - kd)[plate.free]) / np.linalg.norm(kd[plate.free])


def main():
    max_k = int(sys.argv[1]) if len(sys.argv) > 1 else 4
    ks = list(range(1, max_k + 1))
    cases = [("pressure", "f_pressure", ALPHA_Q, PRESSURE_STEPS), ("point", "f_point", ALPHA_P, POINT_STEPS)]
    t_start = time.perf_counter()
    print(f"scikit-fem {skfem.__version__}, von Karman, Argyris w + P2 (u, v), clamped immovable square "
          f"a = {SIDE_M * 1e3:g} mm, t = {T_M * 1e6:g} um, E = {E_PA:.4g} Pa, nu = {NU}, D = {D_NM:.6g} N m, "
          f"A = {A_NPM:.6g} N/m, intorder {INTORDER}, Newton tol {TOL:g}")
    fd_err = check_tangent()
    print(f"self-check tangent vs central differences of the residual (r=1, random state): rel diff {fd_err:.2e}")

    res = {name: [] for name, *_ in cases}  # per k: list of (w/t, its, s, x)
    print(f"\n{'case':<9} {'r':>2} {'dofs':>7} {'setup_s':>8} {'newton its per step':>22} {'step_s':>26}")
    for k in ks:
        t0 = time.perf_counter()
        plate = Plate(k)
        setup = time.perf_counter() - t0
        for name, attr, alpha, steps in cases:
            out = run_case(plate, getattr(plate, attr), alpha, steps)
            res[name].append(out)
            its = " ".join(f"{o[1]:>2}" for o in out)
            secs = " ".join(f"{o[2]:.2f}" for o in out)
            print(f"{name:<9} {k:>2} {plate.N:>7} {setup:>8.2f} {its:>22} {secs:>26}", flush=True)
        if k == ks[-1]:
            finest = plate

    print(f"\n{'case':<9} {'wlin/t':>7} " + " ".join(f"{'w/t r=' + str(k):>12}" for k in ks)
          + f" {'rel_change':>11} {'order':>6} {'w/wlin':>8}")
    for name, _, _, steps in cases:
        for j, s in enumerate(steps):
            ws = [res[name][i][j][0] for i in range(len(ks))]
            ch = abs(ws[-1] - ws[-2]) / abs(ws[-1]) if len(ws) > 1 else float('nan')
            # observed order from the last three meshes (h halves per refinement); pre-asymptotic
            # where a bending boundary layer of width ~ sqrt(D / N) is not yet resolved
            order = np.log2(abs(ws[-2] - ws[-3]) / abs(ws[-1] - ws[-2])) if len(ws) > 2 else float('nan')
            print(f"{name:<9} {s:>7g} " + " ".join(f"{w:>12.8f}" for w in ws)
                  + f" {ch:>11.2e} {order:>6.2f} {ws[-1] / s:>8.5f}")

    tiny = run_case(finest, finest.f_pressure, ALPHA_Q, (TINY,))[0][0] / TINY
    tiny_p = run_case(finest, finest.f_point, ALPHA_P, (TINY,))[0][0] / TINY
    print(f"\nself-check linear limit (w_lin/t = {TINY:g}, r={ks[-1]}): w/w_lin - 1 = {tiny - 1:.2e} (pressure), "
          f"{tiny_p - 1:.2e} (point)")
    for name, _, _, steps in cases:
        first = res[name][-1][0]
        print(f"self-check {name} at w_lin/t = {steps[0]:g}: w/w_lin - 1 = {first[0] / steps[0] - 1:.2e}")
        for s, o in zip(steps, res[name][-1]):
            nx, ny = finest.centre_membrane_force(o[3])
            print(f"  centre membrane force, w_lin/t = {s:g}: N_xx = {nx:.5g} N/m, N_yy = {ny:.5g} N/m "
                  f"({'tensile' if min(nx, ny) > 0 else 'NOT TENSILE'})")
    print(f"\ntotal {time.perf_counter() - t_start:.1f} s")
    for name, _, _, steps in cases:
        for j, s in enumerate(steps):
            ws = [res[name][i][j][0] for i in range(len(ks))]
            ch = abs(ws[-1] - ws[-2]) / abs(ws[-1]) if len(ws) > 1 else float('nan')
            print(f"RESULT case={name} wlin_over_t={s:g} w_over_t={ws[-1]:.8f} change={ch:.3e} "
                  f"dofs={finest.N} seconds={res[name][-1][j][2]:.4f}")


if __name__ == "__main__":
    main()
