"""Independent re-solve of tactfab's solid rung with scikit-fem (issue 16).

Usage:
    pip install -r benches/requirements.txt        # scikit-fem, pypardiso (MKL PARDISO)
    cargo run --release --example solid_export -- process/mis-grasper.yaml centre-1n 0 /tmp/c0.json
    python3 benches/solid_peer.py /tmp/c0.json [more exports ...] [--intorder N] [--json OUT]
    python3 benches/solid_peer.py selftest       # the peer alone against closed forms

Reads the export of `examples/solid_export.rs` (its doc comment gives the format): node positions,
27-node connectivity in tactfab's order, materials (6 x 6 C in die axes), zero constraints,
pressure faces and point forces, the film and its electrodes. Everything else is its own: a
`MeshHex2` (tactfab's node order mapped to scikit-fem's, checked by every element's volume
against tactfab's), scikit-fem's triquadratic Lagrange basis and Gauss rule (intorder 5: 3 x 3 x
3 points, as tactfab; `--intorder 7` takes 4 x 4 x 4), linear elasticity assembled from
sigma = C eps (where the export's `shear` is "tied", the transverse shears of the parallelepiped
elements tied by the peer's own tying points, test and numpy assembly), the pressures integrated over the loaded faces by its own face quadrature, the
constraints condensed, PARDISO (symmetric positive definite, MKL, through pypardiso) or scipy's
SuperLU without it, and the read-outs from its own stresses at its own quadrature points:
the deflection -u_z at the read-out node, each electrode's charge Q = sign (1/t) integral of
D3 = d31 s1 + d32 s2 + d33 s3 over the film under it (a point inside k mirror images counts k
times), the support films' compressive forces, the reactions K u - f per constraint group, the
silicon's largest principal stress at the Gauss points.

Prints each quantity, tactfab against the peer and their relative difference, the largest
difference of the displacement fields and of the load vectors, and each code's dofs, wall time
and peak memory (tactfab's as its export measured them: median of its runs, VmHWM; the peer's:
one run, ru_maxrss, JSON reading excluded from the time but not from the memory).
"""

import argparse
import json
import resource
import sys
import time

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from skfem import (Basis, BilinearForm, ElementHex2, ElementVector, FacetBasis, LinearForm,
                   MeshHex2, asm, condense)

# scikit-fem's local order of ElementHex2's 27 nodes: their reference points in [0, 1]^3 (the 8
# vertices, then the midpoints of RefHex's edges and facets and the centre, in that order).
SKFEM_REF = np.asarray(ElementHex2.doflocs)
# tactfab's local node a + 3 b + 9 c sits at reference (a, b, c) / 2 in [0, 1]^3.
TACTFAB_OF_SKFEM = (2 * SKFEM_REF[:, 0] + 6 * SKFEM_REF[:, 1] + 18 * SKFEM_REF[:, 2]).astype(int)
assert sorted(TACTFAB_OF_SKFEM) == list(range(27))


def peak_rss_mb():
    """Peak resident memory of this process so far (ru_maxrss is in kB on Linux)."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def voigt_of_grad(g):
    """Voigt strain (xx, yy, zz, yz, xz, xy), engineering shears, of a displacement gradient."""
    return [g[0, 0], g[1, 1], g[2, 2], g[1, 2] + g[2, 1], g[0, 2] + g[2, 0], g[0, 1] + g[1, 0]]


# tactfab's tied transverse shear (`"shear": "tied"` in the export): on each parallelepiped brick
# gamma_xz at a point is the linear interpolation in xi of its values on the lines xi = -+1/sqrt 3
# at the point's own eta, zeta, gamma_yz likewise in eta. Written here from that definition, in
# scikit-fem's reference cube [0, 1]^3: the lines at 1/2 -+ 1/(2 sqrt 3).
TIE = (0.5 - 0.5 / np.sqrt(3.0), 0.5 + 0.5 / np.sqrt(3.0))


def tie_weights(s):
    """Linear Lagrange weights at reference coordinates s of the two tying lines TIE."""
    return (TIE[1] - s) / (TIE[1] - TIE[0]), (s - TIE[0]) / (TIE[1] - TIE[0])


def parallelepipeds(mesh, element_dofs):
    """True for each element whose 27 nodes are an affine image of the reference cube's (the
    peer's own test: least-squares affine fit, residual under 1e-9 of the element's size)."""
    x = mesh.doflocs[:, element_dofs]  # (3, 27, nelem)
    a = np.c_[np.ones(27), SKFEM_REF]  # (27, 4)
    pinv = np.linalg.pinv(a)
    coef = np.einsum("ak,dkn->dan", pinv, x)  # (3, 4, nelem)
    fit = np.einsum("ka,dan->dkn", a, coef)
    size = np.abs(coef[:, 1:, :]).sum(axis=1).max(axis=0)
    return np.abs(fit - x).max(axis=(0, 1)) <= 1e-9 * size


def tied_bases(mesh, elem, x_ref, w, els):
    """Bases on elements `els` at the points x_ref (3, nqp) and at their four tying points: the
    same points with xi set to each tying line (for gamma_xz), then eta (gamma_yz)."""
    out = [Basis(mesh, elem, quadrature=(x_ref, w), elements=els)]
    for axis in (0, 1):
        for t in TIE:
            xt = x_ref.copy()
            xt[axis] = t
            out.append(Basis(mesh, elem, quadrature=(xt, w), elements=els))
    return out


def tied_voigt(grads, x_ref):
    """Voigt strain at the points from gradients at [points, xz-, xz+, yz-, yz+] (each
    (3, 3, ...)): the normal strains and gamma_xy at the point, gamma_xz and gamma_yz tied."""
    e = voigt_of_grad(grads[0])
    wx, wy = tie_weights(x_ref[0]), tie_weights(x_ref[1])
    gxz = [g[0, 2] + g[2, 0] for g in grads[1:3]]
    gyz = [g[1, 2] + g[2, 1] for g in grads[3:5]]
    e[4] = wx[0] * gxz[0] + wx[1] * gxz[1]
    e[3] = wy[0] * gyz[0] + wy[1] * gyz[1]
    return e


def tied_stiffness(mesh, c, els, intorder, n_dofs, chunk=400):
    """K of the tied elements `els` (one material, 6 x 6 C): sum over the points of
    dV eps_i^T C eps_j with the tied strains of every basis function, assembled by numpy."""
    elem = ElementVector(ElementHex2())
    c = np.asarray(c)
    rows, cols, vals = [], [], []
    for start in range(0, len(els), chunk):
        part = els[start:start + chunk]
        q = Basis(mesh, elem, intorder=intorder, elements=part)
        bases = tied_bases(mesh, elem, q.X, q.W, part)
        # (nfun, 6, nel, nqp) tied strains of every basis function.
        e = np.array([tied_voigt([b.basis[i][0].grad for b in bases], q.X)
                      for i in range(q.Nbfun)])
        e = np.moveaxis(e, (2, 0, 3, 1), (0, 1, 2, 3))  # (nel, nfun, nqp, 6)
        ce = np.einsum("enqk,mk->enqm", e, c)
        wdx = e * bases[0].dx[:, None, :, None]
        nel, nf = e.shape[0], e.shape[1]
        k = np.matmul(wdx.reshape(nel, nf, -1), ce.reshape(nel, nf, -1).transpose(0, 2, 1))
        d = q.element_dofs  # (nfun, nel)
        rows.append(np.broadcast_to(d.T[:, :, None], k.shape).ravel())
        cols.append(np.broadcast_to(d.T[:, None, :], k.shape).ravel())
        vals.append(k.ravel())
    return sp.coo_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                         shape=(n_dofs, n_dofs)).tocsr()


def stiffness_form(c, nthreads):
    """a(u, v) = eps(v)^T C eps(u) for a constant 6 x 6 C (entries under 1e-12 of the largest,
    rotation round-off, skipped)."""
    c = np.asarray(c)
    cut = 1e-12 * np.abs(c).max()
    rows = [[(j, c[i, j]) for j in range(6) if abs(c[i, j]) > cut] for i in range(6)]

    def form(u, v, w):
        eu, ev = voigt_of_grad(u.grad), voigt_of_grad(v.grad)
        out = 0.0
        for i, row in enumerate(rows):
            if row:
                out = out + ev[i] * sum(cij * eu[j] for j, cij in row)
        return out
    return BilinearForm(form, nthreads=nthreads)


@LinearForm
def pressure_form(v, w):
    """Consistent nodal forces of a pressure p pushing into the material: -p n . v."""
    return -w["p"] * (w.n[0] * v[0] + w.n[1] * v[1] + w.n[2] * v[2])


def solve_spd(a, b):
    """K x = b for symmetric positive definite K: PARDISO (mtype 2, upper triangle) when
    pypardiso is installed, else scipy's SuperLU (slow and memory-hungry at 1e5 3-D dofs).
    Returns x and the solver's name."""
    try:
        import pypardiso
    except ImportError:
        print("  (pypardiso not installed: scipy's SuperLU)")
        return spla.spsolve(a.tocsc(), b), "scipy SuperLU"
    solver = pypardiso.PyPardisoSolver(mtype=2)
    solver.set_iparm(10, 8)   # pivot perturbation 1e-8 (MKL's default for symmetric)
    solver.set_iparm(11, 0)   # no scaling, no matching: not needed for SPD
    solver.set_iparm(13, 0)
    upper = sp.triu(a, format="csr")
    upper.sort_indices()
    solver.factorize(upper)
    x = solver.solve(upper, b)
    # One step of iterative refinement on the same factor, as tactfab does.
    x += solver.solve(upper, b - a @ x)
    solver.free_memory(everything=True)
    return x, "MKL PARDISO, SPD, one refinement step"


def principal_max(s):
    """Largest eigenvalue of each symmetric stress tensor s (3, 3, ...)."""
    t = np.moveaxis(s.reshape(3, 3, -1), -1, 0)
    return np.linalg.eigvalsh(t)[:, -1]


VOIGT_PAIRS = [(0, 0), (1, 1), (2, 2), (1, 2), (0, 2), (0, 1)]


def cubic_tensor(c11, c12, c44):
    """The 4th-order stiffness C_ijkl of a cubic crystal in its crystal axes."""
    c = np.zeros((3, 3, 3, 3))
    for i in range(3):
        for j in range(3):
            c[i, i, j, j] = c11 if i == j else c12
            if i != j:
                c[i, j, i, j] = c[i, j, j, i] = c44
    return c


def voigt_matrix(c):
    """6 x 6 Voigt matrix of a 4th-order stiffness (engineering shears)."""
    return np.array([[c[i, j, k, l] for (k, l) in VOIGT_PAIRS] for (i, j) in VOIGT_PAIRS])


def silicon_check(c_voigt):
    """The silicon's C from the export against a cubic crystal rotated by the peer itself: read
    C11 = C33', C12 = C13', C44 = C44' (a rotation about z keeps them), rotate the tensor
    C'_ijkl = a_ip a_jq a_kr a_ls C_pqrs by 0 and 45 deg about [001], and return the angle that
    matches and the largest difference relative to C11."""
    c = np.asarray(c_voigt)
    base = cubic_tensor(c[2, 2], c[0, 2], c[3, 3])
    best = None
    for deg in (0.0, 45.0):
        t = np.radians(deg)
        a = np.array([[np.cos(t), np.sin(t), 0], [-np.sin(t), np.cos(t), 0], [0, 0, 1]])
        rot = np.einsum("ip,jq,kr,ls,pqrs->ijkl", a, a, a, a, base)
        d = np.abs(voigt_matrix(rot) - c).max() / c[2, 2]
        if best is None or d < best[1]:
            best = (deg, d)
    return best


def face_forces(mesh, sb, els, ax, at, pressure_pa):
    """Consistent nodal forces of uniform pressures (positive into the material) on the faces
    X_ax = at of elements `els` (scikit-fem's reference cube [0, 1]^3): f_a = -p integral of
    N_a n dA with n dA = (x_,p x x_,q) dp dq oriented outward, 3 x 3 Gauss points on the face.
    Written out here because scikit-fem's FacetBasis inverts the element map by Newton and does
    not reach its 1e-12 tolerance on some of the sloped tooth bricks."""
    g, w = np.polynomial.legendre.leggauss(3)
    g, w = 0.5 * g + 0.5, 0.5 * w
    p_ax, q_ax = [d for d in range(3) if d != ax]
    xref = np.zeros((3, 9))
    xref[ax] = at
    xref[p_ax] = np.repeat(g, 3)
    xref[q_ax] = np.tile(g, 3)
    wq = np.repeat(w, 3) * np.tile(w, 3)
    elem = ElementHex2()
    phi, dphi = zip(*[elem.lbasis(xref, i) for i in range(27)])
    phi, dphi = np.array(phi), np.array(dphi)  # (27, 9), (27, 3, 9)
    nodes = sb.element_dofs[:, els]  # (27, n)
    x = mesh.doflocs[:, nodes]  # (3, 27, n)
    tp = np.einsum("dkn,kq->dnq", x, dphi[:, p_ax])
    tq = np.einsum("dkn,kq->dnq", x, dphi[:, q_ax])
    normal = np.cross(tp, tq, axis=0)  # (3, n, 9)
    # Outward: away from the element's centre (its interior node, local node 26).
    away = np.einsum("dkn,kq->dnq", x, phi) - x[:, 26, :, None]
    normal *= np.sign(np.sum(normal * away, axis=0))[None]
    fe = -np.einsum("n,q,kq,dnq->kdn", pressure_pa, wq, phi, normal)  # (27, 3, n)
    f = np.zeros(3 * mesh.doflocs.shape[1])
    for d in range(3):
        np.add.at(f, 3 * nodes + d, fe[:, d])
    return f


class PeerSolve:
    """The export's model solved in scikit-fem, with its read-outs (SI inside)."""

    def __init__(self, ex, intorder=5, nthreads=2):
        self.times = {}
        t = time.perf_counter()
        self.ex = ex
        nodes_m = np.asarray(ex["nodes_um"], dtype=float) * 1e-6
        el = np.asarray(ex["elements"], dtype=np.int64)  # (nelem, 27), tactfab's order
        t27 = np.ascontiguousarray(el[:, TACTFAB_OF_SKFEM].T)  # (27, nelem), scikit-fem's
        mesh = MeshHex2(np.ascontiguousarray(nodes_m.T), t27)
        sb = Basis(mesh, ElementHex2(), intorder=intorder)
        # Export node -> scikit-fem node: the scalar basis lists each element's 27 nodes in the
        # order t27 gave them.
        perm = np.full(len(nodes_m), -1, dtype=np.int64)
        perm[t27] = sb.element_dofs
        assert (perm >= 0).all(), "a node of no element"
        assert np.array_equal(perm[t27], sb.element_dofs), "inconsistent node map"
        self.node_move_m = np.abs(mesh.doflocs[:, perm].T - nodes_m).max()
        assert self.node_move_m < 1e-12, f"node positions moved by {self.node_move_m} m"
        assert (sb.dx > 0).all(), "an inverted element: the node order is wrong"
        vol = sb.dx.sum(axis=1) * 1e18
        ref = np.asarray(ex["element_volume_um3"])
        self.volume_diff = np.abs(vol - ref).max() / ref.max()
        self.mesh, self.perm = mesh, perm
        self.material = np.asarray(ex["material"], dtype=int)
        self.vb = Basis(mesh, ElementVector(ElementHex2()), intorder=intorder)
        self.sb = sb
        self.times["mesh"] = time.perf_counter() - t

        # Stiffness, one material at a time; the tied elements (parallelepipeds, when the export's
        # shear is "tied") by the peer's own tied assembly.
        t = time.perf_counter()
        self.shear = ex.get("shear", "displacement")
        self.tied = np.zeros(len(self.material), dtype=bool)
        if self.shear == "tied":
            self.tied = parallelepipeds(mesh, sb.element_dofs)
        k = None
        for m, mat in enumerate(ex["materials"]):
            for tied in (False, True):
                els = np.nonzero((self.material == m) & (self.tied == tied))[0]
                if len(els) == 0:
                    continue
                if tied:
                    km = tied_stiffness(mesh, mat["c_pa"], els, intorder, self.vb.N)
                else:
                    b = Basis(mesh, ElementVector(ElementHex2()), intorder=intorder, elements=els)
                    km = asm(stiffness_form(mat["c_pa"], nthreads), b)
                k = km if k is None else k + km
        self.k = k.tocsr()
        self.times["assembly"] = time.perf_counter() - t

        # Loads: pressures over the loaded facets (found by their vertices), point forces.
        t = time.perf_counter()
        f = np.zeros(self.vb.N)
        f2v = {tuple(sorted(fv)): i for i, fv in enumerate(mesh.facets.T)}
        boundary = set(mesh.boundary_facets().tolist())
        by_face = {}
        for p in ex["pressures"]:
            ax = "xyz".index(p["face"][1])
            at = 1.0 if p["face"][0] == "+" else 0.0
            verts = [mesh.t[i, p["element"]] for i in range(8) if SKFEM_REF[i, ax] == at]
            assert f2v[tuple(sorted(verts))] in boundary, "a loaded face inside the body"
            by_face.setdefault((ax, at), []).append((p["element"], p["pressure_pa"]))
        for (ax, at), loaded in by_face.items():
            els = np.array([e for e, _ in loaded])
            pr = np.array([q for _, q in loaded])
            f += face_forces(mesh, sb, els, ax, at, pr)
        for pt in ex["points"]:
            for c in range(3):
                f[3 * perm[pt["node"]] + c] += pt["force_n"][c]
        self.f = f
        # Constraints: every listed dof at zero.
        cons = np.asarray(ex["constrained"], dtype=np.int64).reshape(-1, 3)
        self.cons_dof = 3 * perm[cons[:, 0]] + cons[:, 1]
        self.cons_group = cons[:, 2]
        self.times["loads"] = time.perf_counter() - t

        t = time.perf_counter()
        a, b, _, inner = condense(self.k, f, D=self.cons_dof)
        x, self.solver = solve_spd(a, b)
        u = np.zeros(self.vb.N)
        u[inner] = x
        self.u = u
        self.free_dofs = len(inner)
        self.residual = np.linalg.norm(a @ x - b) / np.linalg.norm(b)
        self.times["solve"] = time.perf_counter() - t

        t = time.perf_counter()
        self.read()
        self.times["readout"] = time.perf_counter() - t

    def u_at(self, p_m):
        """Displacement (m) at a point (m): the first element whose node box holds it and whose
        map x(X) = p Newton inverts inside [0, 1]^3, interpolated with its 27 basis functions."""
        elem = ElementHex2()
        nodes = self.sb.element_dofs
        x = self.mesh.doflocs[:, nodes]  # (3, 27, nelem)
        tol = 1e-9 * np.abs(self.mesh.doflocs).max()
        near = np.nonzero(np.all((x.min(axis=1) <= p_m[:, None] + tol)
                                 & (x.max(axis=1) >= p_m[:, None] - tol), axis=0))[0]
        for e in near:
            xr = np.full((3, 1), 0.5)
            for _ in range(30):
                phi, dphi = zip(*[elem.lbasis(xr, i) for i in range(27)])
                phi, dphi = np.array(phi)[:, 0], np.array(dphi)[:, :, 0]  # (27,), (27, 3)
                r = x[:, :, e] @ phi - p_m
                jac = x[:, :, e] @ dphi  # dx_d / dX_j
                step = np.linalg.solve(jac, r)
                xr = xr - step[:, None]
                if np.abs(step).max() < 1e-14:
                    break
            if np.all(xr > -1e-9) and np.all(xr < 1 + 1e-9) and np.abs(r).max() < tol:
                phi = np.array([elem.lbasis(xr, i)[0][0] for i in range(27)])
                return np.array([self.u[3 * nodes[:, e] + c] @ phi for c in range(3)])
        raise ValueError(f"no element holds {p_m} m")

    def read(self):
        ex, vb = self.ex, self.vb
        film = ex["film"]
        # Deflection at the read-out point: a node of the mesh.
        self.deflection_um = -self.u_at(np.asarray(ex["deflection_point_um"]) * 1e-6)[2] * 1e6

        # Stresses at every quadrature point of every element; the tied elements' transverse
        # shears from their tying points.
        grad = vb.interpolate(self.u).grad  # (3, 3, nelem, nqp)
        eps = voigt_of_grad(grad)
        if self.tied.any():
            els = np.nonzero(self.tied)[0]
            bases = tied_bases(self.mesh, ElementVector(ElementHex2()), vb.X, vb.W, els)
            te = tied_voigt([b.interpolate(self.u).grad for b in bases], vb.X)
            for r in (3, 4):
                eps[r] = eps[r].copy()
                eps[r][els] = te[r]
        c = np.asarray([m["c_pa"] for m in ex["materials"]])[self.material]  # (nelem, 6, 6)
        sig = [sum(c[:, i, j][:, None] * eps[j] for j in range(6)) for i in range(6)]
        x_um = vb.global_coordinates().value * 1e6  # (3, nelem, nqp)
        dv = vb.dx  # (nelem, nqp), m^3
        zc = x_um[2].mean(axis=1)
        pvdf = np.array([m["name"] == "pvdf" for m in ex["materials"]])[self.material]
        support_film = pvdf & (zc > 0.0) & (zc < film["support_film_top_um"])
        floor_film = pvdf & (zc > film["floor_film_bottom_um"]) & (zc < film["plate_bottom_um"])
        s1, s2 = (sig[0], sig[1]) if film["drawn_axis"] == "x" else (sig[1], sig[0])
        d3 = (film["d31_pc_per_n"] * s1 + film["d32_pc_per_n"] * s2
              + film["d33_pc_per_n"] * sig[2])  # pC/m^2
        t_f = film["thickness_um"] * 1e-6
        self.charge_pc = []
        self.electrode_elements_match = True
        for e in ex["electrodes"]:
            layer = floor_film if e["side"] == "middle" else support_film
            count = np.zeros_like(dv)
            for r in e["images_um"]:
                count += ((x_um[0] >= r[0]) & (x_um[0] <= r[2])
                          & (x_um[1] >= r[1]) & (x_um[1] <= r[3]))
            count *= layer[:, None]
            self.charge_pc.append(e["sign"] * np.sum(count * d3 * dv) / t_f)
            uniform = count.min(axis=1) == count.max(axis=1)
            mine = {(int(i), int(count[i, 0])) for i in np.nonzero(uniform & (count[:, 0] > 0))[0]}
            mine_cut = set(np.nonzero(~uniform)[0].tolist())
            theirs = {(int(i), int(k)) for i, k in e["elements"]}
            if mine != theirs or mine_cut != set(e.get("cut_elements", [])):
                self.electrode_elements_match = False
        # Support forces: the films' compression, split at the die's centre line, then the
        # whole die from the part solved (as tactfab reports them).
        comp = -sig[2] * dv / t_f * support_film[:, None]
        lower = x_um[1] < film["die_centre_y_um"]
        f1, f2 = np.sum(comp * lower), np.sum(comp * ~lower)
        k = 2.0 if ex["mirror_x_um"] is not None else 1.0
        if ex["mirror_y_um"] is not None:
            self.support_n = (f1 * k, f1 * k)
        else:
            self.support_n = (f1 * k, f2 * k)
        # Reactions K u - f per group.
        r = self.k @ self.u - self.f
        self.reactions_n = {}
        for gi, name in enumerate(ex["groups"]):
            sel = self.cons_dof[self.cons_group == gi]
            self.reactions_n[name] = [float(r[sel[sel % 3 == c]].sum()) for c in range(3)]
        self.applied_n = [float(self.f[c::3].sum()) for c in range(3)]
        # Silicon's largest principal stress.
        si = np.array([m["name"] == "silicon" for m in ex["materials"]])[self.material]
        st = np.array([[sig[0], sig[5], sig[4]], [sig[5], sig[1], sig[3]],
                       [sig[4], sig[3], sig[2]]])[:, :, si]
        self.max_principal_mpa = float(principal_max(st).max()) * 1e-6

    def field_difference(self):
        """max |u_peer - u_tactfab| / max |u_tactfab| over every node and component."""
        ut = np.asarray(self.ex["results"]["u_m"])
        up = self.u.reshape(-1, 3)[self.perm]
        return np.abs(up - ut).max() / np.abs(ut).max()

    def load_difference(self):
        """max |f_peer - f_tactfab| / max |f_tactfab| over the load vectors' entries."""
        ft = np.zeros((len(self.perm), 3))
        for n, c, v in self.ex["results"]["load_vector_n"]:
            ft[n, c] = v
        fp = self.f.reshape(-1, 3)[self.perm]
        return np.abs(fp - ft).max() / np.abs(ft).max()


def rel(a, b, scale=None):
    s = abs(a) if scale is None else scale
    return (b - a) / s if s > 0 else float("nan")


def report(ex, peer, t_read):
    r = ex["results"]
    span = ex.get("span_element_um", ex["element_um"])
    print(f"== {ex['scene']} level {ex['level']} (h {ex['element_um']:.0f} um, "
          f"{span:.0f} across the span), mirrors x "
          f"{ex['mirror_x_um']}, y {ex['mirror_y_um']}: {len(ex['elements'])} elements, "
          f"{len(ex['nodes_um'])} nodes")
    print(f"  node map: positions equal to {peer.node_move_m:.1e} m; element volumes against "
          f"tactfab's {peer.volume_diff:.1e} (of the largest); load vectors differ by "
          f"{peer.load_difference():.1e}; electrode film elements "
          f"{'the same' if peer.electrode_elements_match else 'DIFFER'}")
    si = [m for m in ex["materials"] if m["name"] == "silicon"][0]
    deg, d = silicon_check(si["c_pa"])
    print(f"  silicon C in die axes: the cubic crystal rotated {deg:.0f} deg about [001] by the "
          f"peer's own tensor rotation, to {d:.1e} of C11")
    print(f"  peer solve: {peer.solver}, relative residual {peer.residual:.1e}; transverse "
          f"shear {peer.shear}" + (f", tied on {int(peer.tied.sum())} of {len(peer.tied)} "
                                   "elements (the peer's own parallelepiped test)"
                                   if peer.shear == "tied" else ""))
    rows = [("deflection_at_load", "um", r["deflection_at_load_um"], peer.deflection_um, None)]
    names = [e["name"] for e in ex["electrodes"]]
    sides = [e["side"] for e in ex["electrodes"]]
    for i, name in enumerate(names):
        kind = [abs(q) for q, s in zip(r["charge_pc"], sides) if (s == "middle") == (sides[i] == "middle")]
        rows.append((f"charge_{name}", "pC", r["charge_pc"][i], peer.charge_pc[i], max(kind)))
    rows.append(("support1", "N", r["support1_n"], peer.support_n[0], None))
    rows.append(("support2", "N", r["support2_n"], peer.support_n[1], None))
    for name, v in r["reactions_n"]:
        for c in range(3):
            scale = max(abs(x) for x in peer.applied_n)
            rows.append((f"reaction_{name}_{'xyz'[c]}", "N", v[c], peer.reactions_n[name][c], scale))
    rows.append(("max_principal", "MPa", r["max_principal_mpa"], peer.max_principal_mpa, None))
    print(f"  {'quantity':24} {'unit':4} {'tactfab':>16} {'scikit-fem':>16} {'rel. diff':>10}")
    worst = 0.0
    for name, unit, a, b, scale in rows:
        d = rel(a, b, scale)
        if name.startswith("reaction") and abs(a) < 1e-9 * (scale or 1):
            d = (b - a) / scale  # a component that is zero: relative to the load
        worst = max(worst, abs(d)) if np.isfinite(d) else worst
        print(f"  {name:24} {unit:4} {a:16.9g} {b:16.9g} {d:10.1e}")
    print(f"  displacement field: max |u_peer - u_tactfab| / max |u| = {peer.field_difference():.1e}")
    print(f"  largest relative difference of a quantity: {worst:.1e} (charges relative to the "
          f"largest of their kind, reaction components to the load)")
    tsum = sum(peer.times.values())
    print(f"  {'code':10} {'free dofs':>10} {'wall s':>8} {'peak MB':>8}  parts")
    print(f"  {'tactfab':10} {r['free_dofs']:>10} {r['seconds']:8.2f} "
          f"{(r.get('peak_rss_mb') or float('nan')):8.0f}  median of {r['runs']}; last run: "
          + ", ".join(f"{k} {v:.2f}" for k, v in r.get("phases_s", [])))
    parts = ", ".join(f"{k} {v:.2f}" for k, v in peer.times.items())
    print(f"  {'scikit-fem':10} {peer.free_dofs:>10} {tsum:8.2f} {peak_rss_mb():8.0f}  {parts} "
          f"(JSON read {t_read:.2f} s not counted)")
    return {
        "scene": ex["scene"], "level": ex["level"], "worst_rel_diff": worst,
        "field_diff": peer.field_difference(), "tactfab_s": r["seconds"], "peer_s": tsum,
        "peer_times": peer.times, "tactfab_dofs": r["free_dofs"], "peer_dofs": peer.free_dofs,
        "tactfab_peak_mb": r.get("peak_rss_mb"), "peer_peak_mb": peak_rss_mb(),
        "rows": [(n, u, a, b) for n, u, a, b, _ in rows],
    }


def three_mesh(f3, f2, f1, r=2 ** 0.5):
    """tactfab's three-mesh estimate (src/fe/convergence.rs, ThreeMesh) written again: Richardson's
    limit at the observed order (equal ratios r), and the error of each value as
    max(|f - f_ext|, |f_ext - f1|, |f1 - f2| / (r - 1)). Returns (f_ext, p, errors of f3, f2, f1);
    without monotone convergence the first-order term alone."""
    e21, e32 = f2 - f1, f3 - f2
    floor = abs(e21) / (r - 1)
    ext, p = f1, None
    if e21 != 0 and e32 / e21 > 1:
        p = np.log(e32 / e21) / np.log(r)
        ext = f1 + (f1 - f2) / (r ** p - 1)
    floor = max(floor, abs(ext - f1))
    return ext, p, [max(abs(f - ext), floor) for f in (f3, f2, f1)]


def summary(results):
    """Per scene with three consecutive levels: each quantity's three-mesh error per level (the
    peer's values; tactfab's agree to round-off) beside each code's wall time for that level."""
    by_scene = {}
    for r in results:
        by_scene.setdefault(r["scene"], {})[r["level"]] = r
    for scene, levels in by_scene.items():
        ls = sorted(levels)
        if len(ls) < 3 or ls[-1] - ls[-3] != 2:
            continue
        rs = [levels[k] for k in ls[-3:]]
        print(f"== {scene}: three-mesh errors on levels {ls[-3:]} (ratio sqrt 2), and the cost "
              f"of each level")
        print(f"  {'quantity':20} {'extrapolated':>13} {'order':>6} "
              + " ".join(f"{'err L' + str(k):>9}" for k in ls[-3:]))
        for name in ("deflection_at_load", "charge_M2", "charge_S12", "charge_M3"):
            vals = [dict((n, b) for n, _, _, b in r["rows"])[name] for r in rs]
            ext, p, errs = three_mesh(*vals)
            order = f"{p:6.2f}" if p is not None else "     -"
            print(f"  {name:20} {ext:13.6g} {order} "
                  + " ".join(f"{e / abs(ext):9.2e}" for e in errs))
        print(f"  {'level':>5} {'dofs':>8} {'tactfab s':>10} {'peer s':>8} {'ratio':>6} "
              f"{'tactfab MB':>10} {'peer MB':>8}")
        for k, r in zip(ls[-3:], rs):
            print(f"  {k:5d} {r['peer_dofs']:8d} {r['tactfab_s']:10.2f} {r['peer_s']:8.2f} "
                  f"{r['peer_s'] / r['tactfab_s']:6.1f} {r['tactfab_peak_mb'] or float('nan'):10.0f} "
                  f"{r['peer_peak_mb']:8.0f}")


def selftest():
    """The peer on its own, against closed forms: (1) a patch test, u = G x imposed on the
    boundary of a distorted 3 x 2 x 2 block of 27-node bricks with an anisotropic C (silicon in
    <110> die axes, built here from C11, C12, C44): the interior must carry u = G x and the stress
    C eps everywhere; (2) uniform pressure p on the top of a block on frictionless supports
    (u_z = 0 at the bottom, u_x = 0 at x = 0, u_y = 0 at y = 0): sigma_zz = -p, the rest zero.
    Returns the largest errors relative to the exact field."""
    from skfem import MeshHex1
    c = voigt_matrix(np.einsum("ip,jq,kr,ls,pqrs->ijkl", *[np.array(
        [[np.sqrt(.5), np.sqrt(.5), 0], [-np.sqrt(.5), np.sqrt(.5), 0], [0, 0, 1]])] * 4,
        cubic_tensor(165.7e9, 63.9e9, 79.6e9)))
    mesh = MeshHex2.from_mesh(MeshHex1.init_tensor(np.linspace(0, 3e-3, 4),
                                                   np.linspace(0, 2e-3, 3),
                                                   np.linspace(0, 1e-4, 3)))
    rng = np.random.default_rng(7)
    x = mesh.doflocs.copy()
    inner = ~np.any([np.isclose(x[d], x[d].min()) | np.isclose(x[d], x[d].max())
                     for d in range(3)], axis=0)
    x[:, inner] += rng.uniform(-0.15, 0.15, (3, inner.sum())) * np.array([[1e-3], [1e-3], [5e-5]])
    mesh = MeshHex2(x, mesh.t)
    vb = Basis(mesh, ElementVector(ElementHex2()), intorder=5)
    k = asm(stiffness_form(c, 0), vb)
    g = np.array([[1e-4, 2e-5, -3e-5], [4e-5, -2e-4, 1e-5], [-1e-5, 3e-5, 5e-5]])
    exact = (g @ mesh.doflocs).T.reshape(-1)  # dof 3 n + c
    bnd = vb.get_dofs().flatten()
    u = np.zeros(vb.N)
    u[bnd] = exact[bnd]
    a, b, _, free = condense(k, np.zeros(vb.N), x=u, D=bnd)
    u[free] = spla.spsolve(a.tocsc(), b)
    patch_u = np.abs(u - exact).max() / np.abs(exact).max()
    grad = vb.interpolate(u).grad
    eps = voigt_of_grad(grad)
    sig = [sum(c[i, j] * eps[j] for j in range(6)) for i in range(6)]
    sig_exact = c @ np.array(voigt_of_grad(g))
    patch_s = max(np.abs(sig[i] - sig_exact[i]).max() for i in range(6)) / np.abs(sig_exact).max()

    p = 1e5
    top = mesh.facets_satisfying(lambda y: np.isclose(y[2], 1e-4))
    fb = FacetBasis(mesh, ElementVector(ElementHex2()), facets=top, intorder=5)
    f = asm(pressure_form, fb, p=np.full((len(top), fb.X.shape[-1]), p))
    # The written-out face integration against scikit-fem's FacetBasis on the same faces.
    sb = Basis(mesh, ElementHex2(), intorder=5)
    f2 = np.zeros(vb.N)
    for e in mesh.f2t[0, top]:
        # Which reference face of this element lies on the top (the mesh's own orientation).
        for ax in range(3):
            for at in (0.0, 1.0):
                verts = mesh.t[SKFEM_REF[:8, ax] == at, e]
                if np.allclose(mesh.doflocs[2, verts], 1e-4):
                    f2 += face_forces(mesh, sb, np.array([e]), ax, at, np.array([p]))
    faces = np.abs(f2 - f).max() / np.abs(f).max()
    fixed = np.concatenate([
        vb.get_dofs(lambda y: np.isclose(y[2], 0.0)).all("u^3"),
        vb.get_dofs(lambda y: np.isclose(y[0], 0.0)).all("u^1"),
        vb.get_dofs(lambda y: np.isclose(y[1], 0.0)).all("u^2")])
    u = np.zeros(vb.N)
    a, b, _, free = condense(k, f, D=fixed)
    u[free] = spla.spsolve(a.tocsc(), b)
    grad = vb.interpolate(u).grad
    eps = voigt_of_grad(grad)
    sig = [sum(c[i, j] * eps[j] for j in range(6)) for i in range(6)]
    want = [0, 0, -p, 0, 0, 0]
    press = max(np.abs(sig[i] - want[i]).max() for i in range(6)) / p
    print(f"selftest: patch test u {patch_u:.1e}, stress {patch_s:.1e}; uniform pressure "
          f"stress {press:.1e} (relative to the exact field); face forces against FacetBasis "
          f"{faces:.1e}")
    strip = tied_strip()
    # Returned as an error only past its bound (the element's own error is 1.6e-4 there).
    return max(patch_u, patch_s, press, faces, 0.0 if abs(strip) < 3e-4 else 1.0)


def tied_strip():
    """(3) The peer's tied element against a closed form: a strip 10 mm x 0.5 mm x 100 um
    (isotropic, nu = 0), both ends clamped, u_y held on both sides, 1 kPa on top, on ten 1 mm
    bricks, one through the thickness: its mid-span deflection against the clamped Timoshenko
    beam, p L^4 / (384 D) + p L^2 / (8 kappa G t) with kappa = 5/6. The plain bricks lock (about
    -3.7 %), the tied ones do not. Returns the tied error."""
    length, width, t, e_pa, p = 10e-3, 0.5e-3, 100e-6, 169e9, 1e3
    # The lattice of 27-node bricks in tactfab's node order (reference axes along x, y, z, as the
    # export's; scikit-fem's own tensor meshes may permute them), mapped to scikit-fem's order.
    nx = 10
    lat = [np.linspace(0, length, 2 * nx + 1), np.linspace(0, width, 3), np.linspace(0, t, 3)]
    nodes = np.array([[x, y, z] for z in lat[2] for y in lat[1] for x in lat[0]])
    node = lambda i, j, k: i + (2 * nx + 1) * (j + 3 * k)
    el = np.array([[node(2 * e + n % 3, (n // 3) % 3, n // 9) for n in range(27)]
                   for e in range(nx)])
    mesh = MeshHex2(np.ascontiguousarray(nodes.T), np.ascontiguousarray(el[:, TACTFAB_OF_SKFEM].T))
    vb = Basis(mesh, ElementVector(ElementHex2()), intorder=5)
    c = e_pa * np.diag([1.0, 1.0, 1.0, 0.5, 0.5, 0.5])  # nu = 0: G = E / 2
    els = np.arange(mesh.t.shape[1])
    assert parallelepipeds(mesh, Basis(mesh, ElementHex2(), intorder=5).element_dofs).all()
    top = mesh.facets_satisfying(lambda y: np.isclose(y[2], t))
    fb = FacetBasis(mesh, ElementVector(ElementHex2()), facets=top, intorder=5)
    f = asm(pressure_form, fb, p=np.full((len(top), fb.X.shape[-1]), p))
    fixed = np.concatenate([
        vb.get_dofs(lambda y: np.isclose(y[0], 0.0) | np.isclose(y[0], length)).flatten(),
        vb.get_dofs(lambda y: np.isclose(y[1], 0.0) | np.isclose(y[1], width)).all("u^2")])
    fixed = np.unique(fixed)
    at = np.argmin(np.linalg.norm(vb.doflocs[:, ::3].T - [length / 2, width / 2, t / 2], axis=1))
    d = 1e6 * (p * length ** 4 / (384 * e_pa * t ** 3 / 12) + p * length ** 2 / (8 * 5 / 6 * e_pa / 2 * t))
    out = {}
    for name, k in (("plain", asm(stiffness_form(c, 0), vb)),
                    ("tied", tied_stiffness(mesh, c, els, 5, vb.N))):
        u = np.zeros(vb.N)
        a, b, _, free = condense(k, f, D=fixed)
        u[free] = spla.spsolve(a.tocsc(), b)
        out[name] = -1e6 * u[3 * at + 2]
    print(f"selftest: tied strip {out['tied']:.6f} um, plain {out['plain']:.6f} um, Timoshenko "
          f"{d:.6f} um: tied {out['tied'] / d - 1:+.1e}, plain {out['plain'] / d - 1:+.1e}")
    return out["tied"] / d - 1


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("exports", nargs="+", help="JSON files written by examples/solid_export.rs "
                    "(with --summary: comparisons written by --json)")
    ap.add_argument("--summary", action="store_true",
                    help="only the three-mesh summary of earlier --json outputs")
    ap.add_argument("--intorder", type=int, default=5,
                    help="scikit-fem quadrature order (5: 3x3x3 Gauss points, tactfab's rule)")
    ap.add_argument("--threads", type=int, default=2,
                    help="scikit-fem assembly threads (PARDISO takes MKL's default, all cores)")
    ap.add_argument("--json", help="write the comparison here")
    args = ap.parse_args()
    out = []
    if args.exports == ["selftest"]:
        return 0 if selftest() < 1e-9 else 1
    if args.summary:
        for path in args.exports:
            with open(path) as fh:
                out.extend(json.load(fh))
        summary(out)
        return 0
    for path in args.exports:
        t = time.perf_counter()
        with open(path) as fh:
            ex = json.load(fh)
        t_read = time.perf_counter() - t
        assert ex["format"] == "tactfab-solid-export 1", ex.get("format")
        peer = PeerSolve(ex, intorder=args.intorder, nthreads=args.threads)
        out.append(report(ex, peer, t_read))
        del peer
    summary(out)
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(out, fh, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
