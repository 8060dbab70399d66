// Dense random packings by radius expansion: the "prepared loose or dense" rock and sediment
// samples of Elyashiv et al. 2020 (Potyondy & Cundall 2004, Int. J. Rock Mech. Min. Sci. 41:1329, §3.1,
// material genesis steps 1-3; PFC's radius expansion, YADE's isotropic compaction).
//
// The friction coefficient active while the packing forms sets its density: frictionless spheres
// reach random close packing, phi ~ 0.64 with an isostatic mechanical coordination of 6; rough
// spheres lock early, towards random loose packing, phi ~ 0.55-0.56 and a mechanical coordination
// approaching 4 for mu >= 1 (Silbert 2010, Soft Matter 6:2918; Song, Wang & Makse 2008, Nature
// 453:629; Agnolin & Roux 2007, Phys. Rev. E 76:061302). Measured here (N = 1000, radii +-20 %,
// p = 1e-4 E_c, seed 1): phi = 0.644 / 0.594 / 0.575 / 0.561 and z* = 6.03 / 4.84 / 4.30 / 4.12 for
// mu = 0 / 0.2 / 0.5 / 1, in 15300 / 6830 / 17610 / 38550 steps (`anticrack check` on a dense
// random packing scene prints these statistics; tests/dem/test_dense_packing.cpp checks N = 500).
//
// Method (in a scratch DemSystem; the caller's system only receives the result):
//  1. Radii r_i = f s_i with s_i uniform in [mean - half_width, mean + half_width] and f such that
//     the spheres fill initial_solid_fraction of the box; centres by random sequential insertion
//     without overlaps (std::mt19937_64 seeded with spec.seed; along open axes inside the box).
//  2. Growth with the engine (DemSystem::step): no gravity, Cundall local damping, contact friction
//     formation_friction, fixed frictionless walls at the box faces of open axes (Potyondy &
//     Cundall's frictionless vessel). After every step all radii are multiplied by 1 + g (masses by
//     (1 + g)^3, inertias by (1 + g)^5: solid spheres of the material's density). Every 10 steps a
//     servo on the mean stress p (Love-Weber along periodic axes, wall stress along open axes) sets
//        g = clamp(servo_gain (p_goal - p) / (10 S), -g_cap, g_cap),
//     S = sum_contacts k_n (R_i + R_j)^2 / (3 V), the affine stiffness dp/dg of the touching contacts
//     (g = g_cap while nothing touches): servo_gain is the fraction of the pressure error an affine
//     packing would correct per 10 steps.
//  3. Two goals in turn. Consolidation: p_goal = consolidation_pressure (default 1e-2 E, overlaps
//     ~2 % with the linear law), g_cap = max_growth_per_step. Then unloading: p_goal =
//     target_pressure, g_cap = max_growth_per_step / 10 (slow enough that the pressure follows
//     without dynamic overshoot).
//     A goal is reached when |p - p_goal| <= pressure_tolerance p_goal and the load-bearing spheres
//     are quiescent, kinetic energy <= kinetic_energy_ratio x elastic contact energy, for 100 steps
//     in a row. Why consolidate: damped dynamics near the jamming point relax extremely slowly (a
//     frictionless packing creeping at 1e-4 E is still not static after 4e4 steps), while a packing
//     compressed well past jamming comes to rest in a few thousand steps and, unloaded, stays in
//     its basin (the compress/decompress protocol of O'Hern et al. 2003, Phys. Rev. E 68:011306);
//     frictional packings lose contacts on unloading and creep back to rest at the target. The
//     formation friction still sets the density (figures above).
//  4. The overlaps are kept: the packing is in equilibrium under target_pressure, Potyondy &
//     Cundall's step 3 ("install a specified isotropic stress", small so that the stress locked in
//     by the bonds is small). Overlaps are ~2 p / E_c of the radius (report.max_overlap_ratio). The
//     tangential spring forces are not transferred (the caller's contacts start with zero shear
//     force), so a frictional packing may settle slightly when first run without bonds.
//  5. Sizing (size_by): fill_box keeps the box and the count, so the common radius factor is what
//     the formation reached (report.radius_scale; dense_packing_particle_count gives the count for
//     radii close to the spec's); keep_radii scales packing and box about box_lower so that the radii
//     are the spec's (report.box_upper). The scaling is homothetic: stresses, relative overlaps and
//     coordination do not change (linear and Hertz-Mindlin laws alike).
//
// Rattlers (see DensePackingReport::mechanical_coordination) keep whatever velocity they have, since
// local damping acts through the force on a sphere; they are left out of the quiescence test and of
// mechanical_coordination.
// The energy-balance check of the scratch system is switched off (radius growth does work that no
// ledger term books); the time step safety factor is 0.9 for the linear law (the engine's estimate
// sqrt(m / K) sums the stiffness of every Verlet candidate, touching or not, so dt omega_max stays
// well below leapfrog's limit 2; an unstable step would end in the engine's non-finite-state
// NumericalError) and the engine's default for Hertz-Mindlin, whose estimate counts touching
// contacts only.
//
// The spheres are appended to system.particles (material spec.material, zero velocities) and
// system.domain becomes the final box with spec.periodic. No bonds are made: every load-bearing
// contact overlaps, so DemSystem::bond_touching_pairs with any gap tolerance bonds it. No walls are
// added to the caller's system. Particles already in the system are left alone and must not reach
// into the final box.
#pragma once

#include "dem/sample/ballistic_deposition.h" // RadiusDistribution
#include "dem/core/system.h"

#include <array>
#include <cstdint>

namespace anticrack::dem
{
  /// Which of box and radii the packing keeps exactly (the other follows from the solid fraction).
  enum class PackingSize
  {
    fill_box,  ///< final box = the spec's box; radii = distribution times a common factor
    keep_radii ///< radii exactly the spec's; the box keeps its shape and lower corner, scaled
  };

  struct DensePackingSpec
  {
    Index particle_count = 1000;            ///< spheres in the packing [-], >= 1
    RadiusDistribution radius;              ///< uniform radii [m]; the mean is exact for keep_radii
    Vec3 box_lower = Vec3::Zero();          ///< lower corner of the box [m]
    Vec3 box_upper = Vec3::Constant(2e-2);  ///< upper corner of the box [m]
    /// Periodic axes; open axes get fixed frictionless walls at the box faces during formation (the
    /// caller's system gets none).
    std::array<bool, 3> periodic = {true, true, true};
    PackingSize size_by = PackingSize::fill_box;
    double formation_friction = 0;          ///< contact friction mu while the packing forms [-], >= 0
    /// Mean compressive stress of the final packing [Pa]; 0 < p < 1e-2 x modulus (E_c of the linear
    /// law, E of Hertz-Mindlin).
    double target_pressure = 1e5;
    /// Mean stress of the consolidation stage [Pa]; 0 selects 1e-2 x modulus. No consolidation stage
    /// when it does not exceed target_pressure.
    double consolidation_pressure = 0;
    int material = 0;                       ///< density and contact law from system.materials[material]
    std::uint64_t seed = 1;                 ///< seed of std::mt19937_64 (radii and positions)
    Index max_steps = 200000;               ///< steps before SetupError [-], >= 1
    // --- formation control
    double initial_solid_fraction = 0.25;   ///< of the inserted spheres [-], in (0, 0.3]
    double local_damping = 0.7;             ///< Cundall's alpha during formation [-], in [0, 1)
    double max_growth_per_step = 1e-4;      ///< cap on the relative radius change per step [-], (0, 1e-2]
    /// Fraction of the pressure error an affine packing would correct per 10 steps [-], (0, 1].
    double servo_gain = 0.5;
    double pressure_tolerance = 0.02;       ///< relative |p - p_goal| at which a goal is reached [-], (0, 1)
    /// Quiescence: kinetic energy of the load-bearing spheres / elastic contact energy [-], > 0.
    double kinetic_energy_ratio = 1e-3;
  };

  struct DensePackingReport
  {
    Index first = 0;                   ///< id of the first appended sphere in system.particles
    Index particles = 0;               ///< spheres appended
    double solid_fraction = 0;         ///< sum of sphere volumes / box volume [-] (overlaps not removed, ~1e-6)
    double coordination = 0;           ///< 2 N_c / N, touching sphere-sphere pairs over all spheres [-]
    /// 2 N_c / N over the load-bearing spheres: rattlers (fewer than 4 contacts for frictionless
    /// formation, fewer than 2 with friction, wall contacts counted) are removed repeatedly together
    /// with their contacts [-]
    double mechanical_coordination = 0;
    Index rattlers = 0;                ///< spheres removed for mechanical_coordination
    double pressure = 0;               ///< mean compressive stress at the end [Pa]
    double consolidation_pressure = 0; ///< of the consolidation stage, 0 if there was none [Pa]
    Index steps = 0;                   ///< DEM steps of the formation
    double mean_radius = 0;            ///< final mean radius [m]
    double radius_scale = 0;           ///< mean_radius / spec.radius.mean [-] (1 for keep_radii)
    double max_overlap_ratio = 0;      ///< largest sphere-sphere overlap / min(R_i, R_j) [-]
    Vec3 box_lower = Vec3::Zero();     ///< final box, = system.domain [m]
    Vec3 box_upper = Vec3::Zero();     ///< [m]
  };

  /// The particle count that fills the box with the radius distribution at solid fraction phi:
  /// round(phi V / <4/3 pi R^3>), <R^3> = mean^3 + mean half_width^2 for uniform radii. With
  /// size_by = fill_box and phi the expected result (see the file comment), the final radii come
  /// within a few percent of the spec's. Throws SetupError for bad input.
  Index dense_packing_particle_count(const Vec3 &box_lower, const Vec3 &box_upper,
                                     const RadiusDistribution &radius, double solid_fraction);

  /// Forms the packing (see the file comment), appends it to system and returns its statistics.
  /// Throws SetupError naming the field and its allowed range for invalid specs, and with the
  /// pressure and solid fraction reached when formation does not converge within max_steps.
  DensePackingReport add_dense_packing(DemSystem &system, const DensePackingSpec &spec);
} // namespace anticrack::dem
