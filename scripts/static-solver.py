#!/usr/bin/env python3
"""Static linear solutions of perifrac's discrete peridynamic models, for studying surface
corrections in seconds rather than dynamic runs (bench/NOTES.md, 2026-11-27).

The same discrete model as the engine (cube lattice, delta = 3 lambda, partial volumes beta,
omega = delta / |xi|) linearised: bond extensions e = B u, the energy 1/2 e^T M e, the stiffness
B^T M B, solved with prescribed grips or clamps (scipy's sparse LU). Problems, as the validation
problems define them (host/validation/):
  bar         tension bar: free length 4 W between grips of 3 layers moved u_x = eps x; E from
              the grips' force over the gauge's strain (the central width), nu from its lateral strain
  bending     the same bar bent between grips (u_x = k x z, u_z = -k x^2 / 2): EI over E W^4 / 12
  cantilever  the validation's beam, L = LH h, clamped by 3 layers under a uniform body force: the
              tip deflection against Timoshenko's, and the deflection along the beam split into its
              bending and shear parts and a rotation and offset at the clamp (least squares)
  torsion     the bar between grips, the right one turned about the axis: GJ over Saint-Venant's
              G k a^4 (k = 0.14058, a square)
  uniform     every particle of the bar's body (grips included) moved by uniform strains: the
              energy over the exact
  stable      the largest eigenvalue of a 12 x 8 x 8 block's stiffness over the uncorrected
              model's (the stable step scales as its inverse square root), and its mode by depth
Models:
  lps             the engine's LPS without correction
  lps-axis        with the opt-in per-axis factors (surface_correction.h, --rounds, default 2)
  lps-axis-dev    those and a per-particle deviatoric scale that makes the six modes right on average
  pals            the position-aware linear solid (two 6 x 6 solves per particle)
  pals-maxent     the same constraints met by exp(l.g) weights (never negative)
  pals-odd        pals with the dilatation's odd moments also zero (16 multipliers)
  pals-dil        pals's dilatation with the LPS deviatoric part
  pals-dil-axis   pals's dilatation with the per-axis factors on the deviatoric part alone
                  (--axis-scale's V scales their deviation from 1)
  pmb, pmb-axis   bond-based, without and with the default correction (--rounds, default 3;
                  --parallel-q Q puts the factor's increase on bonds parallel to the surface)
  pmb-moments     a factor per bond from the per-axis ones, least squares so that the bonds'
                  stiffness at their midpoints has the interior's zeroth and first moments in every
                  particle's window (--moments-bounds LO HI to bound them)
--axis-scale D V scales the lps-axis factors' deviation from 1 (dilatation, deviatoric part).
--alpha A blends a pals model's weights with the LPS's: A pals + (1 - A) lps.
--ghosts: any model with a fictitious layer of 3 particles outside every face, whose
displacements are extrapolated linearly along the face's normal from the two outermost layers
(edges and corners: along each normal in turn); the ghosts complete the real particles' families
and carry no energy of their own, and their stiffness is carried back onto the real particles
they are extrapolated from (T^T H T). --ghosts fit: no layer; each particle completes its own
family with ghosts displaced by the linear field least-squares fitted to its real family (what
an engine can do for any particle arrangement).
Needs numpy and scipy (Debian: python3-numpy python3-scipy).
"""
import argparse
import math

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spl

LAMBDA, DELTA = 1.0, 3.0


def beta(r):
    return np.where(r <= DELTA - 0.5 * LAMBDA, 1.0, (DELTA + 0.5 * LAMBDA - r) / LAMBDA)


def offsets():
    reach = DELTA + 0.5 * LAMBDA
    k = int(math.ceil(reach))
    return np.array([(a, b, c) for a in range(-k, k + 1) for b in range(-k, k + 1) for c in range(-k, k + 1)
                     if (a, b, c) != (0, 0, 0) and math.sqrt(a * a + b * b + c * c) * LAMBDA < reach], float)


class Body:
    """A box of nx x ny x nz cubes with its bonds listed once per direction."""

    def __init__(self, nx, ny, nz, origin):
        grid = np.stack(np.meshgrid(np.arange(nx), np.arange(ny), np.arange(nz), indexing="ij"), -1).reshape(-1, 3)
        self.idx = grid
        self.pos = (grid + 0.5) * LAMBDA + np.asarray(origin, float)
        self.n = len(grid)
        self.vol = np.full(self.n, LAMBDA ** 3)
        dims = np.array([nx, ny, nz])
        bi, bj = [], []
        for o in offsets().astype(int):
            q = grid + o
            ok = np.all((q >= 0) & (q < dims), 1)
            bi.append(np.nonzero(ok)[0])
            bj.append((q[ok, 0] * ny + q[ok, 1]) * nz + q[ok, 2])
        self.bi, self.bj = np.concatenate(bi), np.concatenate(bj)
        xi = self.pos[self.bj] - self.pos[self.bi]
        self.r = np.linalg.norm(xi, axis=1)
        self.nv = xi / self.r[:, None]
        self.xi = xi
        self.bw = beta(self.r) * self.vol[self.bj]
        self.nb = len(self.bi)
        rows = np.repeat(np.arange(self.nb), 6)
        cols = np.stack([3 * self.bi, 3 * self.bi + 1, 3 * self.bi + 2, 3 * self.bj, 3 * self.bj + 1, 3 * self.bj + 2],
                        1).ravel()
        self.B = sp.csr_matrix((np.concatenate([-self.nv, self.nv], 1).ravel(), (rows, cols)), (self.nb, 3 * self.n))

    def per_particle(self, values, width=None):
        out = np.zeros((self.n,) if width is None else (self.n, width))
        np.add.at(out, self.bi, values)
        return out


def interior_sums():
    o = offsets() * LAMBDA
    ro = np.linalg.norm(o, axis=1)
    w = beta(ro) * LAMBDA ** 3
    return {"m": np.sum(DELTA / ro * ro ** 2 * w), "bond_sum": np.sum(ro * w),
            "axial4": np.sum((o[:, 0] / ro) ** 4 * ro * w)}


def axis_factors(b, weight_of, axial, power, rounds, shape=None):
    """The fixed point of surface_correction.h: per-axis factors, the ellipse of the ends' means."""
    g = np.ones((b.n, 3))
    G = np.ones(b.nb)
    for _ in range(rounds):
        sums = b.per_particle((G * weight_of)[:, None] * b.nv ** power, 3)
        g = np.minimum(g * axial / sums, 8.0)
        mean = 0.5 * (g[b.bi] + g[b.bj])
        ellipse = 1 / np.sqrt(np.sum((b.nv / mean) ** 2, 1))
        G = ellipse if shape is None else 1 + (ellipse - 1) * shape
    return G


def quartic_monomials(n):
    """The 15 monomials n_x^a n_y^b n_z^c, a + b + c = 4, of unit vectors n."""
    return np.stack([n[:, 0] ** a * n[:, 1] ** c * n[:, 2] ** (4 - a - c)
                     for a in range(5) for c in range(5 - a)], 1)


def hat(coord, k, count):
    """Particle k's window along one axis of a box of `count` cells: a hat of half-width 1 cell,
    flat out to the box's faces at the end cells, so that the windows add up to 1 inside."""
    x = coord - (k + 0.5)
    w = np.maximum(0.0, 1 - np.abs(x))
    w = np.where((k == 0) & (x < 0) & (coord >= 0), 1.0, w)
    w = np.where((k == count - 1) & (x > 0) & (coord <= count), 1.0, w)
    return np.where((k >= 0) & (k < count), w, 0.0)


def moment_factors(b, kappa, start, bounds=None, order=1):
    """pmb-moments: a factor per bond (both directions), least squares from `start`, such that the
    bonds' stiffness kappa r^2 n n n n placed at their midpoints has, in every particle's window,
    the interior's tensor times the window's volume and (order 1) first moment (bench/NOTES.md,
    2026-11-29). Bounded: a damped least squares within `bounds`."""
    dims = b.idx.max(0) + 1
    mid = 0.5 * (b.idx[b.bi] + b.idx[b.bj]) + 0.5  # in cells, the box from 0
    mono = quartic_monomials(b.nv) * (kappa * b.r ** 2)[:, None]
    o = offsets()
    ro = np.linalg.norm(o, axis=1)
    k_of_r = dict(zip(np.round(b.r, 6), kappa))
    k_interior = np.array([k_of_r[r] for r in np.round(ro, 6)])
    T = np.sum(quartic_monomials(o / ro[:, None]) * (k_interior * ro ** 2)[:, None], 0)  # an interior particle's
    below = np.floor(mid - 0.5).astype(int)  # the window below each midpoint, per axis; the one above is + 1
    ks = [np.stack([below[:, a], below[:, a] + 1], 1) for a in range(3)]
    rows, cols, vals = [], [], []
    for corner in np.ndindex(2, 2, 2):
        kk = [ks[a][:, corner[a]] for a in range(3)]
        w = np.prod([hat(mid[:, a], kk[a], dims[a]) for a in range(3)], 0)
        e = np.nonzero(w > 0)[0]
        window = ((kk[0] * dims[1] + kk[1]) * dims[2] + kk[2])[e] * 60
        base = w[e, None] * mono[e]
        for a in range(-1, 3):  # the zeroth moment, then the first along x, y, z
            part = base if a < 0 else base * (mid[e, a] - (kk[a][e] + 0.5))[:, None]
            for c in range(15):
                rows.append(window + 15 * (a + 1) + c)
                cols.append(e)
                vals.append(part[:, c])
    A = sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), (60 * b.n, b.nb))
    xs = [np.linspace(0, d, 200 * d + 1) for d in dims]
    moment = [[[np.trapz(hat(xs[a], k, dims[a]) * (xs[a] - k - 0.5) ** p, xs[a]) for k in range(dims[a])]
               for p in range(2)] for a in range(3)]
    target = np.zeros((b.n, 4, 15))
    for a in range(-1, 3):
        f = np.ones(b.n)
        for c in range(3):
            f = f * np.asarray(moment[c][1 if c == a else 0])[b.idx[:, c]]
        target[:, a + 1] = f[:, None] * T
    pair = np.unique(np.minimum(b.bi, b.bj) * b.n + np.maximum(b.bi, b.bj), return_inverse=True)[1]
    P = sp.csr_matrix((np.ones(b.nb), (np.arange(b.nb), pair)), (b.nb, pair.max() + 1))
    AP, t = (A @ P).tocsr() / np.abs(T).max(), target.ravel() / np.abs(T).max()
    g0 = (P.T @ start) / np.asarray(P.sum(0)).ravel()
    if not order:  # the zeroth moments' rows only
        keep = (np.arange(60 * b.n) % 60) < 15
        AP, t = AP[keep], t[keep]
    if bounds:
        from scipy.optimize import lsq_linear
        damp = 1e-2
        g = lsq_linear(sp.vstack([AP, damp * sp.identity(AP.shape[1])]).tocsr(), np.concatenate([t, damp * g0]),
                       bounds=bounds, lsmr_tol="auto", max_iter=200).x
    else:
        g = g0 + spl.lsqr(AP, t - AP @ g0, damp=1e-3, atol=1e-10, btol=1e-10, iter_lim=20000)[0]
    print(f"moments: residual {np.linalg.norm(t - AP @ g0):.3g} -> {np.linalg.norm(t - AP @ g):.3g}, "
          f"factors {g.min():.3f} .. {g.max():.3f}, mean {g.mean():.3f}")
    return P @ g


def solve_moments(b, weight, basis, components, target):
    """Per particle, the multipliers l with sum_j weight (1 + l.basis) components = target."""
    k = basis.shape[1]
    A = np.zeros((b.n, k, k))
    np.add.at(A, b.bi, weight[:, None, None] * components[:, :, None] * basis[:, None, :])
    rhs = target - b.per_particle(weight[:, None] * components, k)
    lam = np.linalg.solve(A, rhs[:, :, None])[:, :, 0]
    return 1 + np.sum(lam[b.bi] * basis, 1)


def maxent_moments(b, weight, components, target, iterations=60):
    """The weights exp(l.components) meeting the same constraints (Newton on the convex dual)."""
    k = components.shape[1]
    lam = np.zeros((b.n, k))
    for _ in range(iterations):
        f = np.exp(np.clip(np.sum(lam[b.bi] * components, 1), -30, 30))
        grad = b.per_particle((weight * f)[:, None] * components, k) - target
        hess = np.zeros((b.n, k, k))
        np.add.at(hess, b.bi, (weight * f)[:, None, None] * components[:, :, None] * components[:, None, :])
        lam -= np.clip(np.linalg.solve(hess + 1e-12 * np.eye(k), grad[:, :, None])[:, :, 0], -2, 2)
    return np.exp(np.clip(np.sum(lam[b.bi] * components, 1), -30, 30))


def state_weights(b, model, args):
    """wd, wv: theta = sum wd |xi| e beta V, W = K theta^2 / 2 + mu sum wv (e^d)^2 beta V."""
    s = interior_sums()
    omega = DELTA / b.r
    own_m = b.per_particle(omega * b.r ** 2 * b.bw)[b.bi]
    lps = (3 * omega / own_m, 7.5 * omega / own_m)
    if model == "lps":
        return lps
    if model.startswith("lps-axis"):
        G = axis_factors(b, b.r * b.bw, s["bond_sum"] / 3, 2, args.rounds or 2)
        scale_d, scale_v = args.axis_scale  # the factors' deviation from 1 scaled (1 1: the engine's)
        Gd, Gv = 1 + scale_d * (G - 1), 1 + scale_v * (G - 1)
        md = b.per_particle(omega * Gd * b.r ** 2 * b.bw)[b.bi]
        mv = b.per_particle(omega * Gv * b.r ** 2 * b.bw)[b.bi]
        wd, wv = 3 * omega * Gd / md, 7.5 * omega * Gv / mv
        if model == "lps-axis-dev":
            e = deviatoric_modes(b.nv)
            got = b.per_particle((wv * b.r ** 2 * b.bw)[:, None] * e ** 2, 6)
            wv = wv * (8.0 / np.sum(got, 1))[b.bi]  # the six modes' targets, 3 x 2/3 + 3 x 2, add to 8
        return wd, wv
    n = b.nv
    g = np.stack([n[:, 0] ** 2, n[:, 1] ** 2, n[:, 2] ** 2, 2 * n[:, 0] * n[:, 1], 2 * n[:, 0] * n[:, 2],
                  2 * n[:, 1] * n[:, 2]], 1)
    h = g * np.array([1, 1, 1, 0.5, 0.5, 0.5])
    q = deviatoric_modes(n) ** 2
    wd0, wv0 = 3 * omega / s["m"], 7.5 * omega / s["m"]
    t_d, t_v = np.array([1, 1, 1, 0, 0, 0.0]), np.array([2 / 3, 2 / 3, 2 / 3, 2, 2, 2.0])
    if model == "pals-maxent":
        wd = wd0 * maxent_moments(b, wd0 * b.r ** 2 * b.bw, h, t_d)
        wv = wv0 * maxent_moments(b, wv0 * b.r ** 2 * b.bw, q, t_v)
    else:
        if model == "pals-odd":
            cubic = np.stack([n[:, a] * n[:, c] * n[:, d] for a in range(3) for c in range(a, 3)
                              for d in range(c, 3)], 1) * (b.r / DELTA)[:, None]
            wd = wd0 * solve_moments(b, wd0 * b.r ** 2 * b.bw, np.concatenate([g, cubic], 1),
                                     np.concatenate([h, cubic], 1), np.concatenate([t_d, np.zeros(10)]))
        else:
            wd = wd0 * solve_moments(b, wd0 * b.r ** 2 * b.bw, g, h, t_d)
        if model == "pals-dil-axis":  # the per-axis factors on the deviatoric part alone
            G = 1 + args.axis_scale[1] * (axis_factors(b, b.r * b.bw, s["bond_sum"] / 3, 2, args.rounds or 2) - 1)
            wv = 7.5 * omega * G / b.per_particle(omega * G * b.r ** 2 * b.bw)[b.bi]
        elif model == "pals-dil":
            wv = lps[1]
        else:
            wv = wv0 * solve_moments(b, wv0 * b.r ** 2 * b.bw, q, q, t_v)
    a = args.alpha
    return a * wd + (1 - a) * lps[0], a * wv + (1 - a) * lps[1]


def deviatoric_modes(n):
    third = 1.0 / 3.0
    return np.stack([n[:, 0] ** 2 - third, n[:, 1] ** 2 - third, n[:, 2] ** 2 - third, 2 * n[:, 0] * n[:, 1],
                     2 * n[:, 0] * n[:, 2], 2 * n[:, 1] * n[:, 2]], 1)


def stiffness(b, model, args, owners=None):
    """The stiffness and the material's (E, nu); `owners`: the particles whose energy counts (all)."""
    M, E, nu = bond_space(b, model, args, owners)
    return (b.B.T @ M @ b.B).tocsr(), E, nu


def bond_space(b, model, args, owners=None):
    """The energy's matrix over b's bond extensions (1/2 e^T M e) and the material's (E, nu)."""
    own = np.ones(b.n) if owners is None else owners.astype(float)
    if model.startswith("pmb"):
        E, nu = 72e9, 0.25
        s = interior_sums()
        c = 18 * (E / (3 * (1 - 2 * nu))) / s["bond_sum"]
        G = np.ones(b.nb)
        if model == "pmb-axis":
            shape = None
            if args.parallel_q:
                m1 = b.per_particle(b.bw[:, None] * b.xi, 3)
                size = np.linalg.norm(m1, axis=1)
                normal = m1 / np.maximum(size, 1e-30)[:, None]
                weight = np.minimum(size / size.max(), 1.0)
                cos_i = np.sum(b.nv * normal[b.bi], 1) ** 2 * weight[b.bi]
                cos_j = np.sum(b.nv * normal[b.bj], 1) ** 2 * weight[b.bj]
                shape = (1 - 0.5 * (cos_i + cos_j)) ** args.parallel_q
            G = axis_factors(b, b.r * b.bw, s["axial4"], 4, args.rounds or 3, shape)
        if model == "pmb-moments":
            G = moment_factors(b, c * b.bw * b.vol[b.bi] / (2 * b.r), axis_factors(b, b.r * b.bw, s["axial4"], 4, 3),
                               args.moments_bounds, args.moments_order)
        return sp.diags(own[b.bi] * c * G * b.bw * b.vol[b.bi] / (2 * b.r)).tocsr(), E, nu
    E, nu = 70e9, 0.3
    K, mu = E / (3 * (1 - 2 * nu)), E / (2 * (1 + nu))
    wd, wv = state_weights(b, model, args)
    theta = sp.csr_matrix((wd * b.r * b.bw, (b.bi, np.arange(b.nb))), (b.n, b.nb))
    dev = sp.identity(b.nb) - sp.csr_matrix((b.r / 3, (np.arange(b.nb), b.bi)), (b.nb, b.n)) @ theta
    M = theta.T @ sp.diags(own * K * b.vol) @ theta + dev.T @ sp.diags(own[b.bi] * 2 * mu * wv * b.bw * b.vol[b.bi]) @ dev
    return M.tocsr(), E, nu


def ghost_stiffness(dims, origin, model, args, g=3):
    """The stiffness over the real particles of an nx x ny x nz box with a ghost layer (--ghosts)."""
    dims = np.asarray(dims)
    ext = Body(*(dims + 2 * g), np.asarray(origin, float) - g * LAMBDA)
    real = np.all((ext.idx >= g) & (ext.idx < dims + g), 1)
    H, E, nu = stiffness(ext, model, args, real)

    def weights(j, n):  # (source layer, weight) along one axis: the line through the two outer layers
        if j < g:
            return [(0, 1.0 - (j - g)), (1, float(j - g))]
        if j >= g + n:
            d = j - (g + n - 1)
            return [(n - 1, 1.0 + d), (n - 2, -float(d))]
        return [(j - g, 1.0)]

    rows, cols, vals = [], [], []
    for e, (i, j, k) in enumerate(ext.idx):
        for a, wa in weights(i, dims[0]):
            for c, wc in weights(j, dims[1]):
                for d, wd in weights(k, dims[2]):
                    src = (a * dims[1] + c) * dims[2] + d
                    rows += [3 * e, 3 * e + 1, 3 * e + 2]
                    cols += [3 * src, 3 * src + 1, 3 * src + 2]
                    vals += [wa * wc * wd] * 3
    T = sp.csr_matrix((vals, (rows, cols)), (3 * ext.n, 3 * int(np.prod(dims))))
    return (T.T @ H @ T).tocsr(), E, nu


def fit_ghost_stiffness(dims, origin, model, args, g=3):
    """--ghosts fit: each real particle's missing bonds (those of the interior's family that end
    outside the box) are completed with ghosts of its own, displaced by the linear field fitted to
    its real family (u_g = u_i + G_i xi, G_i = sum_j w_j (u_j - u_i) xi_ij^T K_i^-1, K_i = sum_j
    w_j xi_ij xi_ij^T, w = omega beta V): needs no faces, so it serves tets and Voronoi cells too.
    The ghosts own no energy; the real particles' energy over real and ghost bonds is the
    extended body's with the ghost bonds' extensions taken through G_i."""
    dims = np.asarray(dims)
    ext = Body(*(dims + 2 * g), np.asarray(origin, float) - g * LAMBDA)
    real = np.all((ext.idx >= g) & (ext.idx < dims + g), 1)
    M, E, nu = bond_space(ext, model, args, real)
    real_index = np.full(ext.n, -1)
    real_index[real] = np.arange(real.sum())
    n_real = int(real.sum())
    # The real family of each real particle: its bonds within the box.
    b = Body(*dims, origin)
    w = (DELTA / b.r) ** args.fit_power * b.bw
    rows, cols, vals = [], [], []
    inner = real[ext.bi] & real[ext.bj]
    k = np.nonzero(inner)[0]
    for c in range(3):  # real bonds: n . (u_j - u_i)
        rows += [k, k]
        cols += [3 * real_index[ext.bj[k]] + c, 3 * real_index[ext.bi[k]] + c]
        vals += [ext.nv[k, c], -ext.nv[k, c]]
    to_ghost = real[ext.bi] & ~real[ext.bj]
    order = np.argsort(b.bi, kind="stable")
    start = np.searchsorted(b.bi[order], np.arange(n_real + 1))
    ghost_rows = np.nonzero(to_ghost)[0]
    owner = real_index[ext.bi[ghost_rows]]
    for i in np.unique(owner):
        mine = order[start[i]:start[i + 1]]  # i's real bonds in b
        xi, wj, j = b.xi[mine], w[mine], b.bj[mine]
        basis = xi if args.fit_order == 1 else np.concatenate(
            [xi, np.stack([xi[:, a] * xi[:, c] for a in range(3) for c in range(a, 3)], 1)], 1)
        Ainv = np.linalg.inv((basis * wj[:, None]).T @ basis)
        rr = ghost_rows[owner == i]
        # (ghost bonds, real bonds): w_j xi_o^T [A^-1 p(xi_ij)]_(linear part): the gradient at i;
        # order 3: the whole quadratic field continued, w_j p(xi_o)^T A^-1 p(xi_ij)
        xo = ext.xi[rr]
        if args.fit_order == 3:
            po = np.concatenate([xo, np.stack([xo[:, a] * xo[:, c] for a in range(3) for c in range(a, 3)], 1)], 1)
            coef = po @ (Ainv @ (basis * wj[:, None]).T)
        else:
            coef = xo @ (Ainv @ (basis * wj[:, None]).T)[:3]
        for c in range(3):
            a = coef * ext.nv[rr, c][:, None]
            rows += [np.repeat(rr, len(j)), rr]
            cols += [np.tile(3 * j + c, len(rr)), np.full(len(rr), 3 * i + c)]
            vals += [a.ravel(), -a.sum(1)]
    Bfit = sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), (ext.nb, 3 * n_real))
    return (Bfit.T @ M @ Bfit).tocsr(), E, nu


def body_stiffness(b, dims, origin, args):
    """The model's stiffness of body b (an nx x ny x nz box at `origin`), with ghosts if asked."""
    if args.ghosts == "layer":
        return ghost_stiffness(dims, origin, args.model, args)
    if args.ghosts == "fit":
        return fit_ghost_stiffness(dims, origin, args.model, args)
    return stiffness(b, args.model, args)


def solve(H, fixed, u_fixed, load=None):
    free = ~fixed
    u = np.where(fixed, u_fixed, 0.0)
    rhs = -(H[free][:, fixed] @ u[fixed]) + (0 if load is None else load[free])
    u[free] = spl.spsolve(H[free][:, free].tocsc(), rhs)
    return u


def fit(x, y):
    return np.polyfit(x, y, 1)[0]


def bar(args, bending=False):
    n, grip = args.n, 3
    nx = 4 * n + 2 * grip
    origin = (-0.5 * nx * LAMBDA, -0.5 * n * LAMBDA, -0.5 * n * LAMBDA)
    b = Body(nx, n, n, origin)
    H, E, nu = body_stiffness(b, (nx, n, n), origin, args)
    in_grip = (b.idx[:, 0] < grip) | (b.idx[:, 0] >= nx - grip)
    fixed = np.repeat(in_grip, 3)
    x, z = b.pos[:, 0], b.pos[:, 2]
    u0 = np.zeros(3 * b.n)
    if bending:
        u0[0::3], u0[2::3] = 1e-4 * x * z, -0.5e-4 * x * x
    else:
        u0[0::3] = 1e-4 * x
    u = solve(H, fixed, u0)
    f = H @ u
    right, left = b.idx[:, 0] >= nx - grip, b.idx[:, 0] < grip
    gauge = np.abs(x) < 0.5 * n * LAMBDA
    W = n * LAMBDA
    if bending:
        moment = 0.5 * (np.sum(f[0::3][right] * z[right]) - np.sum(f[0::3][left] * z[left]))
        cols = np.stack([x[gauge] * z[gauge], x[gauge], z[gauge], np.ones(gauge.sum())], 1)
        curvature = np.linalg.lstsq(cols, u[0::3][gauge], rcond=None)[0][0]
        print(f"bending {args.model} n={n}: EI / (E W^4/12) = {moment / curvature / (E * W ** 4 / 12):.4f}")
        return
    stress = 0.5 * (f[0::3][right].sum() - f[0::3][left].sum()) / (W * W)
    axial = fit(x[gauge], u[0::3][gauge])
    lateral = 0.5 * (fit(b.pos[gauge, 1], u[1::3][gauge]) + fit(z[gauge], u[2::3][gauge]))
    modulus = stress / axial
    print(f"bar {args.model} n={n}: E {modulus / 1e9:.2f} GPa, elongation error {(E / modulus - 1) * 100:+.2f}%, "
          f"nu {-lateral / axial:.4f}")


def torsion(args):
    """The square bar between grips, the right one turned by a small angle about the bar's axis:
    GJ from the grips' torque over the gauge's twist per length (the slope of the particles'
    rotation angle against x over the central width), against Saint-Venant's G k a^4."""
    n, grip = args.n, 3
    nx = 4 * n + 2 * grip
    origin = (-0.5 * nx * LAMBDA, -0.5 * n * LAMBDA, -0.5 * n * LAMBDA)
    b = Body(nx, n, n, origin)
    H, E, nu = body_stiffness(b, (nx, n, n), origin, args)
    right, left = b.idx[:, 0] >= nx - grip, b.idx[:, 0] < grip
    fixed = np.repeat(left | right, 3)
    x, y, z = b.pos[:, 0], b.pos[:, 1], b.pos[:, 2]
    phi = 1e-4
    u0 = np.zeros(3 * b.n)
    u0[1::3] = np.where(right, -phi * z, 0.0)
    u0[2::3] = np.where(right, phi * y, 0.0)
    u = solve(H, fixed, u0)
    f = H @ u
    torque = np.sum(y[right] * f[2::3][right] - z[right] * f[1::3][right])
    gauge = np.abs(x) < 0.5 * n * LAMBDA
    r2 = y * y + z * z
    ok = gauge & (r2 > 0)
    angle = (y[ok] * u[2::3][ok] - z[ok] * u[1::3][ok]) / r2[ok]
    rate = fit(x[ok], angle)
    a = n * LAMBDA
    reference = E / (2 * (1 + nu)) * 0.14058 * a ** 4
    print(f"torsion {args.model} n={n}: GJ / (G k a^4) = {torque / rate / reference:.4f}")


def clamp_extrapolation(b, n, clamp, order, layers):
    """The map from the beam's displacements to every particle's where the clamp layers move with
    the beam's field continued behind the face: along each row of particles (fixed y, z) the
    polynomial of `order` through u = 0 at the face (x = 0) fitted to the row's first `layers`
    beam particles, evaluated at the clamp particles."""
    xs = (np.arange(layers) + 0.5) * LAMBDA
    pinv = np.linalg.pinv(np.stack([xs ** q for q in range(1, order + 1)], 1))
    beam = np.nonzero(b.idx[:, 0] >= clamp)[0]
    column = np.full(b.n, -1)
    column[beam] = np.arange(len(beam))
    rows, cols, vals = [], [], []
    for p, (i, j, k) in enumerate(b.idx):
        if i >= clamp:
            sources, weights = [p], [1.0]
        else:
            x = (i - clamp + 0.5) * LAMBDA
            sources = [((clamp + t) * n + j) * n + k for t in range(layers)]
            weights = np.array([x ** q for q in range(1, order + 1)]) @ pinv
        for q, wt in zip(sources, weights):
            for d in range(3):
                rows.append(3 * p + d)
                cols.append(3 * column[q] + d)
                vals.append(wt)
    return sp.csr_matrix((vals, (rows, cols)), shape=(3 * b.n, 3 * len(beam)))


def cantilever(args):
    n, clamp = args.n, args.clamp_layers
    nl = args.length_over_height * n
    h = n * LAMBDA
    origin = (-clamp * LAMBDA, -0.5 * h, -0.5 * h)
    b = Body(nl + clamp, n, n, origin)
    H, E, nu = body_stiffness(b, (nl + clamp, n, n), origin, args)
    in_clamp = np.repeat(b.idx[:, 0] < clamp, 3)
    load = np.zeros(3 * b.n)
    load[1::3] = -b.vol  # a body force of 1 per unit volume along -y
    if args.clamp_fit:
        P = clamp_extrapolation(b, n, clamp, *args.clamp_fit)
        load[in_clamp] = 0
        u = P @ spl.spsolve((P.T @ H @ P).tocsc(), P.T @ load)
    else:
        u = solve(H, in_clamp, np.zeros(3 * b.n), load)
    # Each layer's mean deflection against Timoshenko's bending and shear parts at its centre.
    w = np.array([-u[1::3][b.idx[:, 0] == clamp + k].mean() for k in range(nl)])
    L, A, inertia = nl * LAMBDA, h * h, h ** 4 / 12
    kappa, x = 10 * (1 + nu) / (12 + 11 * nu), (np.arange(nl) + 0.5) * LAMBDA
    bending = A * (x ** 4 - 4 * L * x ** 3 + 6 * L * L * x * x) / (24 * E * inertia)
    shear = A * (L * x - 0.5 * x * x) / (kappa * E / (2 * (1 + nu)) * A)
    ref = bending[-1] + shear[-1]
    print(f"cantilever {args.model} n={n} L/h={args.length_over_height}: tip {w[-1]:.4e} against Timoshenko's "
          f"{ref:.4e}: {(w[-1] / ref - 1) * 100:+.1f}%")
    # The deflection along the beam as c_b bending + c_s shear + theta_0 x + w_0: the tip's error
    # split into the beam's bending and shear stiffness (1 / c - 1) and a rotation and offset at the
    # clamp, each in points of the tip's reference.
    c = np.linalg.lstsq(np.stack([bending, shear, x, np.ones_like(x)], 1), w, rcond=None)[0]
    fitted = c[0] * bending + c[1] * shear + c[2] * x + c[3]
    print(f"  split (points of the tip): bending {(c[0] - 1) * bending[-1] / ref * 100:+.1f} (EI x {1 / c[0]:.3f}), "
          f"shear {(c[1] - 1) * shear[-1] / ref * 100:+.1f} (GA x {1 / c[1]:.2f}), "
          f"rotation at the clamp {c[2] * x[-1] / ref * 100:+.1f}, offset {c[3] / ref * 100:+.1f}; "
          f"largest residual {np.abs(fitted - w).max() / ref * 100:.2f}")


def uniform(args):
    b = Body(4 * args.n + 6, args.n, args.n, (0, 0, 0))  # the bar's body, grips included
    H, E, nu = body_stiffness(b, (4 * args.n + 6, args.n, args.n), (0, 0, 0), args)
    K, mu = E / (3 * (1 - 2 * nu)), E / (2 * (1 + nu))
    for name, eps in [("uniaxial x", np.diag([1.0, 0, 0])), ("shear xy", np.array([[0, .5, 0], [.5, 0, 0], [0, 0, 0]])),
                      ("mixed", np.array([[1, .5, .2], [.5, -.3, .1], [.2, .1, .4]]))]:
        eps = 1e-4 * eps
        u = (b.pos @ eps.T).ravel()
        dev = eps - np.trace(eps) / 3 * np.eye(3)
        exact = b.n * LAMBDA ** 3 * (0.5 * K * np.trace(eps) ** 2 + mu * np.sum(dev * dev))
        print(f"uniform {args.model} {name}: energy over the exact {0.5 * u @ (H @ u) / exact:.6f}")


def stable(args):
    """The stable step's measure: the largest eigenvalue of the stiffness of a 12 x 8 x 8 block
    (equal lumped masses) with the model as asked against the same model without ghosts or
    factors, and where the eigenvector of the largest lives (its weight by depth below the
    surface, 0 = the outer layer). dt scales as the inverse square root of the ratio."""
    dims = (12, 8, 8)
    b = Body(*dims, (0, 0, 0))
    plain = argparse.Namespace(**{**vars(args), "ghosts": None, "model": args.model.split("-")[0]})
    H0 = body_stiffness(b, dims, (0, 0, 0), plain)[0].toarray()
    top0 = np.linalg.eigvalsh(H0)[-1]
    H = body_stiffness(b, dims, (0, 0, 0), args)[0].toarray()
    w, v = np.linalg.eigh(0.5 * (H + H.T))
    depth = np.minimum.reduce([b.idx[:, a] for a in range(3)] + [np.array(dims)[a] - 1 - b.idx[:, a] for a in range(3)])
    weight = (v[:, -1] ** 2).reshape(-1, 3).sum(1)
    by_depth = ", ".join(f"{weight[depth == d].sum():.3f}" for d in range(int(depth.max()) + 1))
    # Gershgorin's bound per particle (its rows' largest absolute sum) over the uncorrected's largest.
    rows = np.abs(H).sum(1).reshape(-1, 3).max(1) / np.abs(H0).sum(1).max()
    over = ", ".join(f"{int(np.sum((rows > 2) & (depth == d)))}" for d in range(int(depth.max()) + 1))
    print(f"stable {args.model} ghosts={args.ghosts} fit-order={args.fit_order}: largest eigenvalue "
          f"{w[-1] / top0:.2f} times the uncorrected (dt x {math.sqrt(top0 / w[-1]):.2f}); its mode by depth {by_depth}; "
          f"particles whose rows pass twice the uncorrected's largest, by depth: {over} of {b.n}")


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("problem", choices=["bar", "bending", "cantilever", "torsion", "uniform", "stable"])
    p.add_argument("--n", type=int, default=8, help="particles across")
    p.add_argument("--model", default="lps", choices=["lps", "lps-axis", "lps-axis-dev", "pals", "pals-maxent", "pals-dil-axis",
                                                       "pals-odd", "pals-dil", "pmb", "pmb-axis", "pmb-moments"])
    p.add_argument("--rounds", type=int, default=0, help="the per-axis factors' rounds (0: the engine's)")
    p.add_argument("--alpha", type=float, default=1.0, help="pals models: A pals + (1 - A) lps")
    p.add_argument("--parallel-q", type=float, default=0.0, help="pmb-axis: the factor on bonds parallel to the surface")
    p.add_argument("--fit-power", type=float, default=1.0,
                   help="--ghosts fit: the fit's weights beta V (delta / |xi|)^P (1: the influence function)")
    p.add_argument("--fit-order", type=int, default=1, choices=[1, 2, 3],
                   help="--ghosts fit: 2 fits quadratic terms too and extrapolates with the gradient at the "
                        "particle; 3 continues the whole quadratic field")
    p.add_argument("--axis-scale", type=float, nargs=2, default=[1.0, 1.0], metavar=("D", "V"),
                   help="lps-axis: the factors' deviation from 1 scaled by D in the dilatation, V in the "
                        "deviatoric part (1 1: the engine's)")
    p.add_argument("--moments-bounds", type=float, nargs=2, metavar=("LO", "HI"),
                   help="pmb-moments: bound the factors (default: unbounded least squares)")
    p.add_argument("--moments-order", type=int, default=1, choices=[0, 1],
                   help="pmb-moments: 0 matches the zeroth moments only")
    p.add_argument("--length-over-height", type=int, default=5, help="cantilever: L / h")
    p.add_argument("--clamp-layers", type=int, default=3, help="cantilever: the clamp's layers of particles")
    p.add_argument("--clamp-fit", type=int, nargs=2, metavar=("ORDER", "LAYERS"),
                   help="cantilever: the clamp layers move with the beam's field continued behind the face "
                        "(a polynomial of ORDER through u = 0 there, fitted along each row to its first "
                        "LAYERS beam particles) instead of held fixed")
    p.add_argument("--ghosts", nargs="?", const="layer", choices=["layer", "fit"],
                   help="layer: a fictitious layer outside every face; fit: each particle's own ghosts on "
                        "its family's fitted linear field (see above)")
    args = p.parse_args()
    {"bar": bar, "bending": lambda a: bar(a, True), "cantilever": cantilever, "torsion": torsion,
     "uniform": uniform, "stable": stable}[args.problem](args)


if __name__ == "__main__":
    main()
