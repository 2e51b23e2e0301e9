#!/usr/bin/python3
"""The Hertz cylinder of fissure's meshed contact benchmark (`benches/meshed_contact.rs`) in GetFEM 5.4.

Geometry and load as in fissure (`tests/meshed_contact_pairs.rs`, `meshes/hertz_cylinder.geo`):
half model x >= 0, elastic quarter disc R = 1 centred at (0, R) on the elastic block
[0, 5] x [-5, 0], both E = 1, nu = 0.3, plane strain (E* = E / (2 (1 - nu^2))); u_x = 0 on x = 0
(both bodies), u_y = 0 on the block's bottom; the cylinder held vertically by the contact only;
load P = pi b^2 E* / (4R) per unit length (b = 0.1) as the pressure P / (2R) on the cylinder's
top edge y = R. Coulomb friction mu = 0.3 (--mu; identical materials: the friction does not
change the Hertz pressure). Reference (Johnson, Contact Mechanics, 4.2): b = 0.1,
p0 = 2P / (pi b) = 0.02747.

Mesh: the same gmsh mesh as fissure's row: `meshes/hertz_cylinder.geo` with h_c and the far size
scaled by --scale (0.224: ~2e5 dofs, 0.1: ~1e6; the bench's rows `2d-2e5`, `2d-1e6`), meshed by
gmsh (one thread) in the MSH 2.2 format GetFEM 5.4 reads, into --dir (target/bench-meshes).
GetFEM's importer merges the two bodies' coincident points (the contact point), so the mesh is
imported twice and each copy keeps one body's cells: two meshes, two displacement variables,
no node shared (as fissure's two bodies).

Discretisation:
- P1 triangles (FEM_PK(2,1), `set_classical_fem(1)`), the dofs of fissure's tri3;
- elasticity: `add_isotropic_linearized_elasticity_brick` (plane strain Lame constants),
  integration degree 2;
- supports: `add_normal_Dirichlet_condition_with_multipliers` (P1 multipliers) on the symmetry
  edges and the block's bottom (u.n = 0 on edges normal to x and y);
- load: `add_source_term_brick` of the traction (0, -q) on the cylinder's top edge;
- contact: GetFEM's integral large sliding contact brick with friction
  (`add_integral_large_sliding_contact_brick_raytracing`, version 0, the non-symmetric one:
  Alart-Curnier augmented Lagrangian, raytracing pairing in the deformed configuration),
  slave = the cylinder's contact arc (multiplier lambda, a traction vector, P1 on the slave
  edges: `add_filtered_fem_variable`), master = the block's top; r = --r-factor (1) x E / h_c,
  release distance --release (0.05, ~50 h_c at 2e5 dofs, below the bodies' size), alpha = 1, no
  previous-step displacement (one static step from zero: the slip is u itself); contact
  integration degree 4 on the slave edges;
- the cylinder is held vertically by the contact only, and at u = 0 only the contact point
  touches, so the first tangent is singular: as in GetFEM's own demo_large_sliding_contact.py,
  a mass brick of coefficient --penalty (1e-9 x E) on the cylinder holds it (its force at the
  solution is ~1e-9 of P);
- solve: `Model.solve('max_iter', 50, 'max_res', 1e-9, 'lsolver', 'mumps')` (at 2e5 dofs the residual
  stalls at its round-off floor 2.1e-10 from iteration 25, so 1e-10 would run to the cap), GetFEM's Newton
  with its default line search, sequential MUMPS (Debian build) at every iteration.

Measured (on the converged lambda, on the slave edges with the contact integration method):
p0 = the largest |lambda| at a slave dof, b from the second moment of the pressure,
b^2 = 4 int p x^2 / int p (exact for the Hertz profile), and int p n_y against P/2 (equilibrium).

Run with Debian's python (`apt-get install python3-getfem`):
  /usr/bin/python3 bench/peers/getfem_hertz_cylinder.py --dofs 2e5
  /usr/bin/python3 bench/peers/getfem_hertz_cylinder.py --scale 1 --noisy     # the test's mesh
Prints one line per run: dofs (displacements + multipliers), seconds per phase, Newton
iterations, solve_total (everything up to the end of Newton, the figure compared with fissure's
"contact s"), peak memory, p0 and b against Hertz.
"""

import argparse
import math
import os
import resource
import subprocess
import sys
import time

import numpy as np

try:
    import getfem as gf
except ImportError:
    sys.exit("getfem not found: install python3-getfem and run with /usr/bin/python3")

E, NU, R, B = 1.0, 0.3, 1.0, 0.1
E_STAR = E / (2.0 * (1.0 - NU * NU))
P = math.pi * B * B * E_STAR / (4.0 * R)
P0 = 2.0 * P / (math.pi * B)
ROWS = {'2e5': 0.224, '1e6': 0.1}
# Physical groups of meshes/hertz_cylinder.geo as numbered by gmsh (surfaces, then curves).
CYLINDER, BLOCK = 1, 2
CYL_CONTACT, CYL_TOP, CYL_AXIS, BLOCK_TOP, BLOCK_AXIS, BLOCK_BOTTOM = 3, 4, 5, 6, 7, 8
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def peak_mb():
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def make_mesh(scale, directory):
    """The bench's .geo (sizes x scale) meshed by gmsh into MSH 2.2 (made once)."""
    geo = open(os.path.join(ROOT, 'meshes', 'hertz_cylinder.geo')).read().splitlines()
    out = []
    for line in geo:
        if line.strip().startswith('h_c = '):
            line = '  h_c = %.6f;' % (0.004 * scale)
        elif line.startswith('Field[2].SizeMax = '):
            line = 'Field[2].SizeMax = %.6f;' % (0.5 * scale)
        out.append(line)
    text = '\n'.join(out) + '\n'
    os.makedirs(directory, exist_ok=True)
    stem = os.path.join(directory, 'hertz_cylinder_%g_msh22' % scale)
    if not (os.path.exists(stem + '.geo') and open(stem + '.geo').read() == text and os.path.exists(stem + '.msh')):
        open(stem + '.geo', 'w').write(text)
        subprocess.run(['gmsh', '-2', '-format', 'msh22', '-nt', '1', stem + '.geo', '-o', stem + '.msh'],
                       check=True, stdout=subprocess.DEVNULL)
    return stem + '.msh'


def body_mesh(path, keep):
    """The gmsh mesh with only the cells of physical surface `keep`."""
    m = gf.Mesh('import', 'gmsh', path)
    other = BLOCK if keep == CYLINDER else CYLINDER
    cvs = m.region(other)[0]
    m.del_convex(np.unique(cvs))
    return m


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('--dofs', choices=sorted(ROWS), help="fissure's row (2e5: scale 0.224, 1e6: 0.1)")
    ap.add_argument('--scale', type=float, default=None, help='mesh sizes x scale (1: the test mesh)')
    ap.add_argument('--mu', type=float, default=0.3)
    ap.add_argument('--r-factor', type=float, default=1.0)
    ap.add_argument('--release', type=float, default=0.05)
    ap.add_argument('--penalty', type=float, default=1e-9)
    ap.add_argument('--start', type=float, default=1.0, help='initial rigid approach in b^2/(2R)')
    ap.add_argument('--max-res', type=float, default=1e-9)
    ap.add_argument('--dir', default=os.path.join(ROOT, 'target', 'bench-meshes'))
    ap.add_argument('--noisy', action='store_true')
    a = ap.parse_args()
    scale = a.scale if a.scale is not None else ROWS[a.dofs or '2e5']
    path = make_mesh(scale, a.dir)
    h_c = 0.004 * scale
    t = {}
    total = time.perf_counter()

    clock = time.perf_counter()
    m1, m2 = body_mesh(path, CYLINDER), body_mesh(path, BLOCK)
    mf1, mf2 = gf.MeshFem(m1, 2), gf.MeshFem(m2, 2)
    mf1.set_classical_fem(1)
    mf2.set_classical_fem(1)
    mfl = gf.MeshFem(m1, 2)
    mfl.set_classical_fem(1)
    mim1, mim2 = gf.MeshIm(m1, 2), gf.MeshIm(m2, 2)
    mimc1, mimc2 = gf.MeshIm(m1, 4), gf.MeshIm(m2, 4)
    t['mesh+fem'] = time.perf_counter() - clock

    clock = time.perf_counter()
    md = gf.Model('real')
    md.add_fem_variable('u1', mf1)
    md.add_fem_variable('u2', mf2)
    lam = E * NU / ((1 + NU) * (1 - 2 * NU))
    mu_l = E / (2 * (1 + NU))
    md.add_initialized_data('clambda', [lam])
    md.add_initialized_data('cmu', [mu_l])
    md.add_isotropic_linearized_elasticity_brick(mim1, 'u1', 'clambda', 'cmu')
    md.add_isotropic_linearized_elasticity_brick(mim2, 'u2', 'clambda', 'cmu')
    md.add_normal_Dirichlet_condition_with_multipliers(mim1, 'u1', 1, CYL_AXIS)
    md.add_normal_Dirichlet_condition_with_multipliers(mim2, 'u2', 1, BLOCK_AXIS)
    md.add_normal_Dirichlet_condition_with_multipliers(mim2, 'u2', 1, BLOCK_BOTTOM)
    md.add_initialized_data('F', [0.0, -P / (2.0 * R)])
    md.add_source_term_brick(mim1, 'u1', 'F', CYL_TOP)
    md.add_initialized_data('penalty', [a.penalty * E])
    md.add_mass_brick(mim1, 'u1', 'penalty')
    md.add_filtered_fem_variable('lambda1', mfl, CYL_CONTACT)
    md.add_initialized_data('r', [a.r_factor * E / h_c])
    md.add_initialized_data('f', [a.mu])
    md.add_initialized_data('alpha', [1.0])
    ind = md.add_integral_large_sliding_contact_brick_raytracing('r', a.release, 'f', 'alpha', 0)
    md.add_slave_contact_boundary_to_large_sliding_contact_brick(ind, mimc1, CYL_CONTACT, 'u1', 'lambda1')
    md.add_master_contact_boundary_to_large_sliding_contact_brick(ind, mimc2, BLOCK_TOP, 'u2')
    t['model'] = time.perf_counter() - clock

    clock = time.perf_counter()
    gf.util_trace_level(1 if a.noisy else 0)
    # Initial guess: the cylinder moved down rigidly by b^2 / (2R) (--start), so that the
    # first tangent already has the contact zone of about the right size.
    u1 = np.zeros(mf1.nbdof())
    u1[1::2] = -a.start * B * B / (2.0 * R)
    md.set_variable('u1', u1)
    args = ['max_iter', 50, 'max_res', a.max_res, 'lsolver', 'mumps']
    if a.noisy:
        args.append('noisy')
    its, _cond = md.solve(*args)
    t['newton'] = time.perf_counter() - clock
    solve_total = time.perf_counter() - total

    # p0, b and equilibrium from lambda on the slave edges.
    lam1 = md.variable('lambda1')
    p0 = float(np.max(np.hypot(lam1[0::2], lam1[1::2])))
    ip = gf.asm('generic', mimc1, 0, 'Norm(lambda1)', CYL_CONTACT, md)
    ipx2 = gf.asm('generic', mimc1, 0, 'Norm(lambda1)*sqr(X(1))', CYL_CONTACT, md)
    fy = gf.asm('generic', mimc1, 0, 'lambda1(2)', CYL_CONTACT, md)
    b = math.sqrt(4.0 * ipx2 / ip)
    ndofs = md.nbdof()
    n_u = mf1.nbdof() + mf2.nbdof()
    n_l = md.mesh_fem_of_variable('lambda1').nbdof()
    print('getfem scale=%g h_c=%.5f mu=%g dofs=%d (u %d + lambda %d + %d) %s newton_its=%d solve_total %.3f s '
          'peak_mb=%.0f p0=%.5f err=%+.2f%% b=%.5f err=%+.2f%% |int lambda_y|/(P/2)-1=%+.1e'
          % (scale, h_c, a.mu, ndofs, n_u, n_l, ndofs - n_u - n_l,
             ' '.join('%s %.3f' % kv for kv in t.items()), its, solve_total, peak_mb(),
             p0, 100 * (p0 / P0 - 1), b, 100 * (b / B - 1), abs(fy) / (P / 2) - 1))


if __name__ == '__main__':
    main()
