#!/usr/bin/python3
"""The closed inclined frictional crack of fissure's contact benchmark (`benches/contact.rs`) in GetFEM 5.4.

Geometry and load as in fissure (`tests/common/contact.rs::inclined_crack`): plate [-2, 2]^2,
straight crack of half-length a = 0.2 at beta = 45 degrees centred at (0.0123, 0.0071), E = 1,
nu = 0.3, plane strain, traction (0, -1) on top and (0, 1) on bottom (sigma = 1 compression),
rigid modes held by two corner points (u = 0 at (-2, -2), u_y = 0 at (2, -2)), Coulomb friction
mu = 0.3 on the crack faces (--mu). References: |K_II| = 0.2801 (mu = 0.3) and 0.4001 (mu = 0),
the crack closed with pressure sigma cos^2 beta = 0.5.

Discretisation (chosen to match fissure's defaults, as in getfem_centre_crack.py):
- Cartesian quad mesh n x n (--n; 161 ~ 5e4 dofs, 321 ~ 2e5, 707 ~ 1e6), Q1 elements
  (FEM_QK(2,1)), the same mesh and standard dofs as fissure's rows;
- X-FEM with level sets: primary (x - c).n_c (the crack line), secondary |(x - c).d| - a (Q1
  level sets), cut by MeshLevelSet.adapt(); Heaviside-type enrichment by MeshFem('levelset'),
  plus the four near-tip functions GlobalFunction('crack', 0..3) times the Q1 partition of
  unity on every node within --tip-radius (0.05) of a tip (geometric enrichment);
- integration: 2x2 Gauss on plain cells, 4x4 Gauss (degree 6) on the cells near the tips,
  IM_TRIANGLE(6) on the sub-triangles of cut cells, the quasi-polar rule from
  IM_GAUSS_PARALLELEPIPED(2,8) on the sub-triangles touching a tip; on the crack itself
  MeshIm('levelset', mls, 'boundary', IM_TRIANGLE(6)) (the faces of the sub-triangles lying on
  the zero level set, degree-6 Gauss on each piece);
- contact: an independent multiplier lambda (the traction on the + face, a 2-vector) in a
  piecewise constant space (FEM_QK(2,0), both components) on every cell the crack crosses
  (cells found by clipping the segment against the cells); Alart-Curnier augmented Lagrangian
  written in GetFEM's weak form language on the crack integration method, with
  [u] = Xfem_plus(u) - Xfem_minus(u), n = Normal (unit normal of the level set, from the - to
  the + side), t = (-n_2, n_1):
      u-equation:       - int_crack lambda . [v]
      lambda-equation:  - (1/r) int_crack (lambda - P(lambda - r [u])) . mu_test
  P: normal part pn = pos_part(lambda.n - r [u].n) (>= 0: compression), tangential part the
  projection of lambda.t - r [u].t on [-mu pn, mu pn] (written with pos_part), r = --r-factor
  (1) x E / h. The problem is a single static step, so the slip is the tangential jump.
  Nonlinear terms by Model.add_nonlinear_term (GWFL differentiates them for the tangent);
- corner points by add_pointwise_constraints_with_multipliers;
- solve: Model.solve('max_iter', 50, 'max_res', --max-res (1e-10), 'lsolver', 'mumps') --
  GetFEM's Newton with its default line search, MUMPS (sequential, Debian build) at every
  iteration; initial guess u = 0, lambda = 0;
- SIF: GetFEM's Python interface has no SIF routine, so G comes from the J integral in its
  domain form, assembled with asm_generic on the level-set integration, plus the crack-face
  term of the contact tractions:
      J = int_A (grad(u)^T sigma - W I) grad(q) . e1 dA - int_crack q lambda . d[u]/de1 ds
  e1 the propagation direction, q = max(0, 1 - r/R), R = --sif-radius (0.06, fissure's
  sif_radius). The face term is the friction work (the normal part vanishes while closed).
  The crack is closed (K_I = 0; the script prints the largest normal opening to check), so
  |K_II| = sqrt(J E / (1 - nu^2)); the sign of K_II is not computed (no interaction integral
  in the Python interface). The J is also evaluated at 2R as a path-independence check.

Run with Debian's python (`apt-get install python3-getfem`):
  /usr/bin/python3 bench/peers/getfem_inclined_contact.py --n 161
  /usr/bin/python3 bench/peers/getfem_inclined_contact.py --dofs 2e5 --mu 0
Prints one line per run: dofs (displacement + multipliers), seconds per phase, Newton
iterations, total, peak memory, |K_II| per tip and its error against the reference, mean
pressure on the crack.
"""

import argparse
import math
import resource
import sys
import time

import numpy as np

try:
    import getfem as gf
except ImportError:
    sys.exit("getfem not found: install python3-getfem and run with /usr/bin/python3")

E, NU, SIGMA = 1.0, 0.3, 1.0
X0, X1 = -2.0, 2.0
A, BETA, CTR = 0.2, math.radians(45.0), (0.0123, 0.0071)
TOP, BOTTOM, RING = 1, 2, 3
REF = {0.0: 0.4001, 0.3: 0.2801}
ROWS = {'5e4': 161, '2e5': 321, '1e6': 707}


def peak_mb():
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def crossed_cells(m, p0, p1, h):
    """Cells whose closed box the segment p0-p1 crosses with a positive length."""
    lo = np.minimum(p0, p1) - h
    hi = np.maximum(p0, p1) + h
    cand = np.asarray(m.convexes_in_box(lo.tolist(), hi.tolist()), dtype=int).ravel()
    pids, idx = m.pid_from_cvid(cand)
    pts = m.pts()
    keep = []
    d = p1 - p0
    for k, cv in enumerate(cand):
        xy = pts[:, pids[idx[k]:idx[k + 1]]]
        bl, bh = xy.min(axis=1), xy.max(axis=1)
        t0, t1 = 0.0, 1.0
        for j in range(2):
            if abs(d[j]) < 1e-300:
                if p0[j] < bl[j] or p0[j] > bh[j]:
                    t0, t1 = 1.0, 0.0
                continue
            ta, tb = (bl[j] - p0[j]) / d[j], (bh[j] - p0[j]) / d[j]
            t0, t1 = max(t0, min(ta, tb)), min(t1, max(ta, tb))
        if t1 - t0 > 1e-12:
            keep.append(cv)
    return np.array(keep, dtype=int)


def run(n, mu_f, tip_radius, sif_radius, r_factor, max_res, noisy):
    gf.util_trace_level(0)
    gf.util_warning_level(0)
    lam = E * NU / ((1 + NU) * (1 - 2 * NU))
    mu = E / (2 * (1 + NU))
    d = np.array([math.cos(BETA), math.sin(BETA)])
    nc = np.array([-math.sin(BETA), math.cos(BETA)])
    c = np.array(CTR)
    tips = [(c + A * d, d), (c - A * d, -d)]  # (tip, propagation direction)
    h = (X1 - X0) / n
    t = {}
    total = time.perf_counter()

    clock = time.perf_counter()
    m = gf.Mesh('cartesian', np.linspace(X0, X1, n + 1), np.linspace(X0, X1, n + 1))
    m.set_region(TOP, m.outer_faces_with_direction([0.0, 1.0], 0.01))
    m.set_region(BOTTOM, m.outer_faces_with_direction([0.0, -1.0], 0.01))
    t['mesh'] = time.perf_counter() - clock

    clock = time.perf_counter()
    phi = '(X(1)-%.17g)*%.17g+(X(2)-%.17g)*%.17g' % (c[0], nc[0], c[1], nc[1])
    psi = 'abs((X(1)-%.17g)*%.17g+(X(2)-%.17g)*%.17g)-%.17g' % (c[0], d[0], c[1], d[1], A)
    ls = gf.LevelSet(m, 1, phi, psi)
    mls = gf.MeshLevelSet(m)
    mls.add(ls)
    mls.adapt()
    t['levelset+cut'] = time.perf_counter() - clock

    clock = time.perf_counter()
    mf_pre = gf.MeshFem(m)
    mf_pre.set_fem(gf.Fem('FEM_QK(2,1)'))
    mf_ls = gf.MeshFem('levelset', mls, mf_pre)
    mf_pu = gf.MeshFem(m)
    mf_pu.set_classical_fem(1)
    pts = mf_pu.basic_dof_nodes()
    near = np.zeros(pts.shape[1], dtype=bool)
    for p, _ in tips:
        near |= (pts[0] - p[0]) ** 2 + (pts[1] - p[1]) ** 2 <= tip_radius**2
    ck = [gf.GlobalFunction('crack', i) for i in range(4)]
    mf_sing = gf.MeshFem('global function', m, ls, ck, 1)
    mf_tip = gf.MeshFem('product', mf_pu, mf_sing)
    mf_tip.set_enriched_dofs(np.nonzero(near)[0])
    mf_u = gf.MeshFem('sum', mf_tip, mf_ls)
    mf_u.set_qdim(2)
    mim = gf.MeshIm('levelset', mls, 'all', gf.Integ('IM_TRIANGLE(6)'), gf.Integ('IM_GAUSS_PARALLELEPIPED(2,8)'))
    mim.set_integ(gf.Integ('IM_GAUSS_PARALLELEPIPED(2,3)'))
    reach = tip_radius + 2.0 * h
    tip_cells = np.unique(np.concatenate([m.convexes_in_box((p - reach).tolist(), (p + reach).tolist()) for p, _ in tips]))
    mim.set_integ(gf.Integ('IM_GAUSS_PARALLELEPIPED(2,6)'), tip_cells)
    mim.adapt()
    mim_face = gf.MeshIm(m, gf.Integ('IM_GAUSS_PARALLELEPIPED(2,3)'))
    mim_crack = gf.MeshIm('levelset', mls, 'boundary', gf.Integ('IM_TRIANGLE(6)'))
    mim_crack.set_integ(gf.Integ('IM_GAUSS_PARALLELEPIPED(2,3)'))
    mim_crack.adapt()
    cut = crossed_cells(m, c - A * d, c + A * d, h)
    mf_l = gf.MeshFem(m, 2)
    mf_l.set_fem(gf.Fem('FEM_QK(2,0)'), cut)
    n_u, n_l = mf_u.nbdof(), mf_l.nbdof()
    t['enrich+integ'] = time.perf_counter() - clock

    clock = time.perf_counter()
    md = gf.Model('real')
    md.add_fem_variable('u', mf_u)
    md.add_fem_variable('lambda', mf_l)
    md.add_initialized_data('lambda_e', [lam])
    md.add_initialized_data('mu_e', [mu])
    md.add_initialized_data('r', [r_factor * E / h])
    md.add_initialized_data('f', [mu_f])
    md.add_isotropic_linearized_elasticity_brick(mim, 'u', 'lambda_e', 'mu_e')
    md.add_source_term_brick(mim_face, 'u', '[0, %.17g]' % -SIGMA, TOP)
    md.add_source_term_brick(mim_face, 'u', '[0, %.17g]' % SIGMA, BOTTOM)
    md.add_initialized_data('cpts', [X0, X0, X0, X0, X1, X0])
    md.add_initialized_data('cdirs', [1.0, 0.0, 0.0, 1.0, 0.0, 1.0])
    md.add_pointwise_constraints_with_multipliers('u', 'cpts', 'cdirs')
    md.add_macro('jmp', 'Xfem_plus(u)-Xfem_minus(u)')
    md.add_macro('tjmp', 'Xfem_plus(Test_u)-Xfem_minus(Test_u)')
    md.add_macro('tng', '[-Normal(2);Normal(1)]')
    md.add_macro('pn', 'pos_part(lambda.Normal-r*(jmp.Normal))')
    md.add_macro('at', 'lambda.tng-r*(jmp.tng)')
    md.add_macro('pt', 'at-pos_part(at-f*pn)+pos_part(-at-f*pn)')
    md.add_linear_term(mim_crack, '-lambda.tjmp')
    md.add_nonlinear_term(mim_crack, '-(1/r)*((lambda.Normal-pn)*(Test_lambda.Normal)+(lambda.tng-pt)*(Test_lambda.tng))')
    t['model'] = time.perf_counter() - clock

    clock = time.perf_counter()
    opts = ['max_iter', 50, 'max_res', max_res, 'lsolver', 'mumps']
    if noisy:
        opts = ['noisy'] + opts
    res = md.solve(*opts)
    nit, conv = (res if isinstance(res, tuple) else (res, None))
    t['newton'] = time.perf_counter() - clock
    t_solve = time.perf_counter() - total
    if conv is not None and not conv:
        sys.exit('Newton did not converge in %d iterations' % nit)
    U = md.variable('u')
    if not np.any(U):
        sys.exit('GetFEM returned a zero solution')

    clock = time.perf_counter()
    length = gf.asm_generic(mim_crack, 0, '1', -1, md)
    pressure = gf.asm_generic(mim_crack, 0, 'lambda.Normal', -1, md) / length
    opening = gf.asm_generic(mim_crack, 0, 'pos_part(jmp.Normal)', -1, md) / length
    slip = gf.asm_generic(mim_crack, 0, 'abs(jmp.tng)', -1, md) / length
    cell_p = np.asarray(md.variable('lambda')).reshape(-1, 2) @ nc  # P0: one value per cut cell
    centres = mf_l.basic_dof_nodes()[:, ::2]
    away = np.ones(centres.shape[1], dtype=bool)
    for p, _ in tips:
        away &= np.hypot(centres[0] - p[0], centres[1] - p[1]) > tip_radius + h  # no tip-enriched node
    sig = '(lambda_e*Trace(Grad_u)*Id(2)+mu_e*(Grad_u+Grad_u\'))'
    ks, drift = [], []
    for p, e in tips:
        js = []
        for rad in (sif_radius, 2.0 * sif_radius):
            reach = rad + 2.0 * h
            cells = m.convexes_in_box((p - reach).tolist(), (p + reach).tolist())
            m.set_region(RING, np.asarray(cells).reshape(1, -1))
            pv = '[%.17g;%.17g]' % (p[0], p[1])
            ev = '[%.17g;%.17g]' % (e[0], e[1])
            rr = 'Norm(X-%s)' % pv
            gq = '(-Heaviside(%.17g-%s)/(%s*%.17g))*(X-%s)' % (rad, rr, rr, rad, pv)
            q = 'pos_part(1-%s/%.17g)' % (rr, rad)
            dom = "((Grad_u'*%s - 0.5*(%s:Grad_u)*Id(2))*%s).%s" % (sig, sig, gq, ev)
            face = '%s*(lambda.((Xfem_plus(Grad_u)-Xfem_minus(Grad_u))*%s))' % (q, ev)
            J = gf.asm_generic(mim, 0, dom, RING, md) - gf.asm_generic(mim_crack, 0, face, RING, md)
            js.append(J)
            m.delete_region(RING)
        ks.append(math.copysign(math.sqrt(abs(js[0]) * E / (1 - NU * NU)), js[0]))
        drift.append(js[1] / js[0] - 1.0)
    t['sif'] = time.perf_counter() - clock
    t['total'] = time.perf_counter() - total

    ref = REF.get(mu_f)
    errs = ','.join('%+.2f%%' % (100.0 * (k / ref - 1.0)) for k in ks) if ref else 'n/a'
    phases = ' '.join('%s %.3f' % (k, v) for k, v in t.items())
    print('getfem n=%d mu=%g dofs=%d (u %d + lambda %d + 3) %s s newton_its=%s solve_total %.3f s peak_mb=%.0f '
          '|K_II|=%s err=%s J(2R)/J(R)-1=%s pressure=%.5f cells [%.4f, %.4f] beyond_tip_cells [%.4f, %.4f] opening=%.1e slip=%.3e'
          % (n, mu_f, n_u + n_l + 3, n_u, n_l, phases, nit, t_solve, peak_mb(), ','.join('%.5f' % k for k in ks),
             errs, ','.join('%+.2e' % x for x in drift), pressure, cell_p.min(), cell_p.max(),
             cell_p[away].min(), cell_p[away].max(), opening, slip))
    sys.stdout.flush()


def main():
    p = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    p.add_argument('--n', type=int, help='cells per side (default 161)')
    p.add_argument('--dofs', help="fissure's row label: 5e4 (n = 161), 2e5 (321), 1e6 (707)")
    p.add_argument('--mu', type=float, default=0.3, help='Coulomb friction coefficient (0.3)')
    p.add_argument('--tip-radius', type=float, default=0.05)
    p.add_argument('--sif-radius', type=float, default=0.06)
    p.add_argument('--r-factor', type=float, default=1.0, help='augmentation r = FACTOR * E / h (1)')
    p.add_argument('--max-res', type=float, default=1e-10, help='Newton residual target (1e-10)')
    p.add_argument('--noisy', action='store_true', help='print the Newton residuals')
    a = p.parse_args()
    if a.n:
        n = a.n
    elif a.dofs:
        n = ROWS[a.dofs]
    else:
        n = 161
    run(n, a.mu, a.tip_radius, a.sif_radius, a.r_factor, a.max_res, a.noisy)


if __name__ == '__main__':
    main()
