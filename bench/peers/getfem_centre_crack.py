#!/usr/bin/python3
"""The 2D centre-crack benchmark of fissure (`benches/xfem.rs`, rows 2d-centre-*) in GetFEM 5.4.

Geometry and load as in fissure: plate [-5, 5] x [-10, 10], centre crack 2a = 2 along y = 0
(a/b = 0.2), E = 1, nu = 0.3, plane strain, sigma = 1 on top and bottom, rigid modes held by
two corner points (u = 0 at (-5, -10), u_y = 0 at (5, -10)). Reference:
K_I = sigma sqrt(pi a) F, F = 1.02448 (Feddersen, Tada handbook).

Discretisation (chosen to match fissure's defaults):
- Cartesian quad mesh nx x ny (odd counts so that the crack runs between node rows), Q1
  elements (FEM_QK(2,1)), the same mesh and standard dofs as fissure's quad4 rows;
- X-FEM with level sets: primary y, secondary |x| - 1 (Q1 level sets), cut by
  MeshLevelSet.adapt(); Heaviside-type enrichment by MeshFem('levelset') (GetFEM doubles
  the dofs of cut elements), plus the four near-tip functions GlobalFunction('crack', 0..3)
  times the Q1 partition of unity on every node within --tip-radius (0.3) of a tip
  (geometric enrichment, fissure's tip_radius);
- integration: 2x2 Gauss on plain cells, 4x4 Gauss (degree 6) on the cells near the tips,
  IM_TRIANGLE(6) on the sub-triangles of cut cells, and GetFEM's quasi-polar singular rule
  built from IM_GAUSS_PARALLELEPIPED(2,8) on the sub-triangles touching a tip (fissure: 2x2,
  degree 6, degree 2/6 sub-cells, almost-polar degree 8);
- corner points by add_pointwise_constraints_with_multipliers;
- solve: Model.assembly('build_all') then gf.linsolve_mumps on the tangent matrix (MUMPS
  forced: GetFEM's default solver choice returned a zero solution above ~300k dofs here);
  with --solver mumps (or auto, superlu), Model.solve('lsolver', SOLVER) instead (GetFEM's
  usual path: Newton on the linear problem, which assembles again to check the residual;
  'auto' is GetFEM's default choice of solver);
- SIF: GetFEM's Python interface has no SIF routine (the C++ interaction integral of
  getfem_crack_sif.h is not exported), so K_I comes from the J integral in its domain form,
  assembled with GetFEM's weak form language (asm_generic) on the level-set integration:
    J = int (grad(u)^T sigma - W I) grad(q) . e1 dA,  W = sigma:grad(u)/2,
  e1 the propagation direction, q = max(0, 1 - r/R), R = --sif-radius (0.5, fissure's
  sif_radius), and K_I = sqrt(J E / (1 - nu^2)) (K_II = 0 by symmetry).

Run with Debian's python (`apt-get install python3-getfem`):
  /usr/bin/python3 bench/peers/getfem_centre_crack.py --dofs 1e5
  /usr/bin/python3 bench/peers/getfem_centre_crack.py --dofs 4e5
Prints one line per run: dofs, seconds per phase, total, peak memory, K_I error per tip.
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

E, NU, SIGMA, A = 1.0, 0.3, 1.0, 1.0
X0, X1, Y0, Y1 = -5.0, 5.0, -10.0, 10.0
TOP, BOTTOM, RING = 1, 2, 3


def feddersen(r):
    return (1.0 - 0.025 * r * r + 0.06 * r**4) * math.sqrt(1.0 / math.cos(math.pi * r / 2.0))


def divisions(dofs):
    """nx x ny (odd, ny = 2 nx + 1: square cells) with 2 (nx + 1)(ny + 1) close to `dofs`."""
    nx = int(round(math.sqrt(dofs / 4.0))) - 1
    if nx % 2 == 0:
        nx += 1
    return nx, 2 * nx + 1


def peak_mb():
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def run(nx, ny, tip_radius, sif_radius, solver):
    gf.util_trace_level(0)
    gf.util_warning_level(0)
    lam = E * NU / ((1 + NU) * (1 - 2 * NU))
    mu = E / (2 * (1 + NU))
    tips = [(1.0, 1.0), (-1.0, -1.0)]  # (x of the tip, propagation direction along x)
    h = (X1 - X0) / nx
    t = {}
    total = time.perf_counter()

    clock = time.perf_counter()
    m = gf.Mesh('cartesian', np.linspace(X0, X1, nx + 1), np.linspace(Y0, Y1, ny + 1))
    m.set_region(TOP, m.outer_faces_with_direction([0.0, 1.0], 0.01))
    m.set_region(BOTTOM, m.outer_faces_with_direction([0.0, -1.0], 0.01))
    t['mesh'] = time.perf_counter() - clock

    clock = time.perf_counter()
    ls = gf.LevelSet(m, 1, 'X(2)', 'abs(X(1)) - %.17g' % A)
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
    for xt, _ in tips:
        near |= (pts[0] - xt) ** 2 + pts[1] ** 2 <= tip_radius**2
    ck = [gf.GlobalFunction('crack', i) for i in range(4)]
    mf_sing = gf.MeshFem('global function', m, ls, ck, 1)
    mf_tip = gf.MeshFem('product', mf_pu, mf_sing)
    mf_tip.set_enriched_dofs(np.nonzero(near)[0])
    mf_u = gf.MeshFem('sum', mf_tip, mf_ls)
    mf_u.set_qdim(2)
    mim = gf.MeshIm('levelset', mls, 'all', gf.Integ('IM_TRIANGLE(6)'), gf.Integ('IM_GAUSS_PARALLELEPIPED(2,8)'))
    mim.set_integ(gf.Integ('IM_GAUSS_PARALLELEPIPED(2,3)'))
    reach = tip_radius + 2.0 * h
    tip_cells = np.unique(np.concatenate([m.convexes_in_box([xt - reach, -reach], [xt + reach, reach]) for xt, _ in tips]))
    mim.set_integ(gf.Integ('IM_GAUSS_PARALLELEPIPED(2,6)'), tip_cells)
    mim.adapt()
    mim_face = gf.MeshIm(m, gf.Integ('IM_GAUSS_PARALLELEPIPED(2,3)'))
    n_dofs = mf_u.nbdof()
    t['enrich+integ'] = time.perf_counter() - clock

    clock = time.perf_counter()
    md = gf.Model('real')
    md.add_fem_variable('u', mf_u)
    md.add_initialized_data('lambda', [lam])
    md.add_initialized_data('mu', [mu])
    md.add_isotropic_linearized_elasticity_brick(mim, 'u', 'lambda', 'mu')
    md.add_source_term_brick(mim_face, 'u', '[0, %.17g]' % SIGMA, TOP)
    md.add_source_term_brick(mim_face, 'u', '[0, %.17g]' % -SIGMA, BOTTOM)
    md.add_initialized_data('cpts', [X0, Y0, X0, Y0, X1, Y0])
    md.add_initialized_data('cdirs', [1.0, 0.0, 0.0, 1.0, 0.0, 1.0])
    md.add_pointwise_constraints_with_multipliers('u', 'cpts', 'cdirs')
    if solver != 'direct':
        md.solve('lsolver', solver)
        t['assembly+solve'] = time.perf_counter() - clock
    else:
        md.assembly('build_all')
        K = md.tangent_matrix()
        F = md.rhs()
        t['assembly'] = time.perf_counter() - clock
        clock = time.perf_counter()
        X = gf.linsolve_mumps(K, F)
        X = np.asarray(X).ravel()
        t['solve'] = time.perf_counter() - clock
        r = np.asarray(K.mult(X)).ravel() - F
        residual = np.linalg.norm(r) / np.linalg.norm(F)
        md.to_variables(X)
        if not residual < 1e-8:
            sys.exit('MUMPS solve not accurate: relative residual %.2e' % residual)
    U = md.variable('u')
    if not np.any(U):
        sys.exit('GetFEM returned a zero solution')

    clock = time.perf_counter()
    ks = []
    for xt, d in tips:
        cells = m.convexes_in_box([xt - sif_radius - 2 * h, -sif_radius - 2 * h],
                                  [xt + sif_radius + 2 * h, sif_radius + 2 * h])
        m.set_region(RING, cells.reshape(1, -1))
        p = '[%.17g;0]' % xt
        rr = 'Norm(X-%s)' % p
        gq = '(-Heaviside(%.17g-%s)/(%s*%.17g))*(X-%s)' % (sif_radius, rr, rr, sif_radius, p)
        sig = '(lambda*Trace(Grad_u)*Id(2)+mu*(Grad_u+Grad_u\'))'
        expr = "((Grad_u'*%s - 0.5*(%s:Grad_u)*Id(2))*%s).[%.17g;0]" % (sig, sig, gq, d)
        J = gf.asm_generic(mim, 0, expr, RING, md)
        ks.append(math.copysign(math.sqrt(abs(J) * E / (1 - NU * NU)), J))
        m.delete_region(RING)
    t['sif'] = time.perf_counter() - clock
    t['total'] = time.perf_counter() - total

    ref = SIGMA * math.sqrt(math.pi * A) * feddersen(A / (X1 - X0) * 2.0)
    errs = ['%+.3f%%' % (100.0 * (k / ref - 1.0)) for k in ks]
    phases = ' '.join('%s %.3f' % (k, v) for k, v in t.items())
    print('getfem solver=%s nx=%d ny=%d dofs=%d %s s peak_mb=%.0f K_I=%s err=%s'
          % (solver, nx, ny, n_dofs, phases, peak_mb(), ','.join('%.5f' % k for k in ks), ','.join(errs)))
    sys.stdout.flush()


def main():
    p = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    p.add_argument('--dofs', type=float, action='append', help='target dof count (repeatable; default 1e5)')
    p.add_argument('--nx', type=int, help='cells along x (odd; overrides --dofs; ny = 2 nx + 1)')
    p.add_argument('--tip-radius', type=float, default=0.3)
    p.add_argument('--sif-radius', type=float, default=0.5)
    p.add_argument('--solver', default='direct', choices=['direct', 'mumps', 'auto', 'superlu'],
                   help="direct: Model.assembly + linsolve_mumps (default); otherwise Model.solve('lsolver', SOLVER)")
    a = p.parse_args()
    if a.nx:
        runs = [(a.nx, 2 * a.nx + 1)]
    else:
        runs = [divisions(d) for d in (a.dofs or [1e5])]
    for nx, ny in runs:
        run(nx, ny, a.tip_radius, a.sif_radius, a.solver)


if __name__ == '__main__':
    main()
