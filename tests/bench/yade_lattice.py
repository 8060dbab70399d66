# -*- coding: utf-8 -*-
"""YADE reference side of the bonded-lattice DEM throughput benchmark.

What it measures
    Wall-clock cost of S explicit time steps of a fully bonded, periodic
    simple-cubic sphere lattice in YADE, single-threaded. Reported figures are
    particle-steps/s and bond-steps/s. The problem mirrors
        anticrack bench dem --lattice n --steps S --threads 1
    so the two JSON lines can be compared side by side.

How to run
    yade -j1 -n -x tests/bench/yade_lattice.py --lattice 13 --steps 2000
    (-j1: one OpenMP thread, -n: no GUI, -x: exit when the script ends.)
    YADE prints a banner on stdout before the script starts, so the result is
    the LAST stdout line, which starts with '{"code":"yade"'. Grep for it:
        yade -j1 -n -x ... 2>/dev/null | grep '^{"code":"yade"'

Problem (keep identical to the C++ side)
    --lattice n  n x n x n spheres, radius R = 1 mm, centres at (2i+1) mm,
                 so nearest neighbours touch exactly; periodic cube of side
                 2n mm. Expected bonds: 3 n^3. Needs n >= 4 here: for n <= 2 a
                 pair touches through two periodic images at once, and for
                 n = 3 YADE's periodic collider rejects the (verlet-enlarged)
                 bounding boxes as larger than half the cell.
    --steps S    number of timed steps.
    --seed k     seed of the random initial velocities (default 12345).
    Material:    CohFrictMat, E = 1e9 Pa, density 1e4 kg/m^3, poisson = 1/3
                 (in YADE this is ks/kn, i.e. kappa = kn/ks = 3),
                 normalCohesion = shearCohesion = 1e6 Pa, friction angle
                 atan(0.5), momentRotationLaw on with alphaKr = alphaKtw = 2
                 (bending kr = alphaKr*ks*R1*R2, twist ktw = alphaKtw*ks*R1*R2).
                 Resulting bond constants (checked): kn = E*R = 1e6 N/m,
                 ks = kn/3, kr = ktw = 0.667 N m/rad, and strengths
                 normalAdhesion = shearAdhesion = cohesion * R^2 = 1 N
                 (YADE uses R^2, not pi R^2).
    Law:         Law2_ScGeom6D_CohFrictPhys_CohesionMoment, incremental form.
    Dynamics:    velocities uniform in +-1e-6 m/s per component, no gravity,
                 local (Cundall) damping 0.7, fixed dt = 0.3*PWaveTimeStep()
                 (PWaveTimeStep = R/sqrt(E/rho) = 3.16e-6 s -> dt = 9.49e-7 s).

Protocol
    Step 1 (untimed) detects the touching pairs with a 1.05 detection factor
    and bonds them (setCohesionNow); the factor is then reset to its default
    and the bond count is checked against 3 n^3. WARMUP more untimed steps
    follow, then exactly S steps are timed with O.run(S, True).
    After the run: bonds_broken = bonds before - intact bonds after, and
    "finite" says whether all positions/velocities are finite.
"""
import argparse
import json
import math
import os
import random
import sys
import time

from yade import O, utils
import yade.config

WARMUP = 10            # untimed steps after the bonding step
RADIUS = 1e-3          # m
YOUNG, DENSITY = 1e9, 1e4
DETECT = 1.05          # enlarged detection factor used for the bonding step only
DT_FACTOR = 0.3        # dt = DT_FACTOR * PWaveTimeStep()


def log(*a):
    print(*a, file=sys.stderr, flush=True)


# yade -x passes the arguments after the script name in sys.argv[1:]
ap = argparse.ArgumentParser(description="YADE bonded lattice benchmark")
ap.add_argument("--lattice", type=int, default=13)
ap.add_argument("--steps", type=int, default=1000)
ap.add_argument("--seed", type=int, default=12345)
args = ap.parse_args(sys.argv[1:])
n, S = args.lattice, args.steps
if n < 4:
    sys.exit("--lattice must be >= 4 (see docstring)")

# ---- scene -----------------------------------------------------------------
O.reset()
O.periodic = True
O.cell.setBox(2 * RADIUS * n, 2 * RADIUS * n, 2 * RADIUS * n)
mat = O.materials.append(CohFrictMat(
    young=YOUNG, poisson=1.0 / 3.0, density=DENSITY,
    frictionAngle=math.atan(0.5), isCohesive=True,
    normalCohesion=1e6, shearCohesion=1e6,
    momentRotationLaw=True, alphaKr=2.0, alphaKtw=2.0))

rng = random.Random(args.seed)
O.bodies.append([utils.sphere(((2 * i + 1) * RADIUS, (2 * j + 1) * RADIUS, (2 * k + 1) * RADIUS),
                              RADIUS, material=mat)
                 for i in range(n) for j in range(n) for k in range(n)])
for b in O.bodies:
    b.state.vel = Vector3(*(rng.uniform(-1e-6, 1e-6) for _ in range(3)))

O.engines = [
    ForceResetter(),
    InsertionSortCollider([Bo1_Sphere_Aabb(aabbEnlargeFactor=DETECT, label="bo1")]),
    InteractionLoop(
        [Ig2_Sphere_Sphere_ScGeom6D(interactionDetectionFactor=DETECT, label="ig2")],
        [Ip2_CohFrictMat_CohFrictMat_CohFrictPhys(setCohesionNow=True,
                                                  setCohesionOnNewContacts=False)],
        [Law2_ScGeom6D_CohFrictPhys_CohesionMoment(useIncrementalForm=True)]),
    NewtonIntegrator(damping=0.7, gravity=(0, 0, 0)),
]
O.dt = DT_FACTOR * utils.PWaveTimeStep()


def intact_bonds():
    # CohFrictPhys.cohesionBroken defaults to True (purely frictional contact);
    # setCohesionNow sets it False, the law sets it True again on failure.
    # (initCohesion is only a transient "bond me now" flag, not a bond marker.)
    return sum(1 for i in O.interactions if i.isReal and not i.phys.cohesionBroken)


# ---- bonding step (untimed) --------------------------------------------------
O.step()
bo1.aabbEnlargeFactor = -1.0          # back to defaults: no enlarged detection,
ig2.interactionDetectionFactor = 1.0  # existing bonds are kept by the law
bonds0 = intact_bonds()
n_real = sum(1 for i in O.interactions if i.isReal)
log("yade_lattice: n=%d particles=%d real interactions=%d bonds=%d (expected %d) dt=%.4g s"
    % (n, len(O.bodies), n_real, bonds0, 3 * n ** 3, O.dt))
if bonds0 != 3 * n ** 3:
    sys.exit("bond count %d != 3 n^3 = %d" % (bonds0, 3 * n ** 3))

O.run(WARMUP, True)

# ---- timed part --------------------------------------------------------------
# O.run(S, True) runs in YADE's own thread and polls for completion; the
# wait has a ~40 ms granularity, so choose S such that wall_s >> 0.04 s.
t0 = time.perf_counter()
O.run(S, True)
wall = time.perf_counter() - t0

# ---- checks and report ---------------------------------------------------------
bonds1 = intact_bonds()
finite = all(math.isfinite(x) for b in O.bodies
             for v in (b.state.pos, b.state.vel, b.state.angVel) for x in v)
log("yade_lattice: iter=%d wall=%.3f s bonds after=%d finite=%s"
    % (O.iter, wall, bonds1, finite))

result = {
    "code": "yade",
    "version": yade.config.version,
    "particles": len(O.bodies),
    "bonds": bonds1,
    "steps": S,
    "threads": int(os.environ.get("OMP_NUM_THREADS", "1")),
    "wall_s": round(wall, 4),
    "particle_steps_per_s": len(O.bodies) * S / wall,
    "bond_steps_per_s": bonds1 * S / wall,
    "bonds_broken": bonds0 - bonds1,
    "finite": finite,
    "dt": O.dt,
    "lattice": n,
    "interactions": sum(1 for i in O.interactions if i.isReal),
}
# compact separators so the line starts exactly with {"code":"yade"
sys.stdout.write(json.dumps(result, separators=(",", ":")) + "\n")
sys.stdout.flush()
