// Ballistic-deposition sample generators (docs/physics.md §1.4).
//
// Spheres fall one at a time along -z at a uniformly random (x, y) in a box that is periodic along
// x and y, onto the base plane z = box_lower.z and the spheres deposited before them.
//
//  * sticky (cohesive ballistic deposition, Lubachevsky, Privman & Roy 1992): a sphere stops at its
//    first contact, z = max(base + R, max_j (z_j + sqrt((R + R_j)^2 - d_j^2))) over the deposited
//    spheres j whose horizontal minimum-image distance d_j is below R + R_j. Bulk solid fraction
//    ~0.15, two contacts per sphere.
//  * rolling (cohesionless, Visscher & Bolsterli 1972): after its first contact the sphere rolls
//    over that sphere along the steepest descent until it touches a second one, then rolls on the
//    circle of centre positions touching both, downwards, until it touches a third; it rests when
//    gravity is balanced by compressive normal forces of the three supports (equivalently, the
//    horizontal projection of its centre lies in the triangle of the support points), or when it
//    touches the base. A support whose normal force would become tensile is dropped and the sphere
//    rolls on. Solid fraction ~0.58.
//
// The rolling paths are followed exactly (no time stepping): on one support the centre moves on a
// great-circle arc of the sphere of radius R + R_a, on two supports on the circle where the spheres
// of radii R + R_a and R + R_b around the supports meet; contacts with further spheres, with the
// base and the loss of a support are roots of closed-form equations (a sin t + b cos t = k, or
// linear in cos t). Every contact is therefore touching to round-off (~1e-15 relative), so that
// DemSystem::bond_touching_pairs with a small gap tolerance (e.g. 1e-9) bonds exactly the
// deposited contacts. A sphere that does not come to rest within `max_roll_events` events is placed
// by the sticky rule at its first contact and counted in DepositionReport::fallbacks.
//
// The generator appends spheres to system.particles (density of system.materials[material]); it
// does not make bonds. Expectation on the domain: the caller sets system.domain to the box with
// periodic x and y. If system.domain is not periodic along both x and y, it is set here to the box
// (periodic x, y; z open from box_lower.z). If it is periodic, its lateral extent must equal the
// box's. The domain's upper z is raised to the deposit's top if the deposit grows above it.
// Particles already in the system act as obstacles (their images under the lateral periodicity);
// the report is about the newly deposited spheres only.
#pragma once

#include "dem/core/system.h"

#include <cstdint>

namespace anticrack::dem
{
  enum class DepositionRule
  {
    sticky, ///< stop at first contact
    rolling ///< roll to a three-point rest
  };

  /// Radii uniform in [mean - half_width, mean + half_width].
  struct RadiusDistribution
  {
    double mean = 1e-3;     ///< [m]
    double half_width = 0;  ///< [m], 0 <= half_width < mean
  };

  struct BallisticDepositionSpec
  {
    DepositionRule rule = DepositionRule::sticky;
    Vec3 box_lower = Vec3::Zero();              ///< base plane at box_lower.z
    Vec3 box_upper = Vec3::Constant(2e-2);      ///< lateral extent; upper z is not a limit
    Index particle_count = 1000;                ///< spheres to drop
    RadiusDistribution radius;
    int material = 0;
    std::uint64_t seed = 1;
    bool base_layer = true;   ///< the plane z = box_lower.z stops spheres (else they fall through)
    Index max_roll_events = 1000; ///< rolling: events per sphere before the sticky fallback
    double bulk_margin = 4;   ///< mean diameters excluded at the bottom and top of the bulk slab (at most a quarter of the thickness each)
    double contact_tolerance = 1e-9; ///< gap <= tolerance * min(R_i, R_j) counts as a contact
  };

  struct DepositionReport
  {
    Index first = 0;                 ///< id of the first deposited sphere
    Index particles = 0;             ///< spheres deposited
    Index fallbacks = 0;             ///< rolling spheres placed by the sticky rule
    Index on_base = 0;               ///< spheres touching the base plane
    double solid_fraction_bulk = 0;  ///< in the slab [bulk_lower, bulk_upper]; 0 if it is empty
    double mean_contacts = 0;        ///< sphere-sphere contacts per sphere, centres in the bulk slab
    double mean_contacts_all = 0;    ///< 2 * contact pairs / particles, whole deposit
    double height = 0;               ///< max(z + R) - base
    /// z of the bulk slab: base + margin .. mean surface height - margin, margin = bulk_margin
    /// mean diameters, at most a quarter of the mean thickness (a thin layer keeps its middle half);
    /// the mean surface height averages the highest z + R over lateral bins one mean diameter wide.
    double bulk_lower = 0, bulk_upper = 0;
  };

  /// Deposits spec.particle_count spheres; see the file comment. Throws SetupError naming the
  /// offending parameter for bad input.
  DepositionReport add_ballistic_deposit(DemSystem &system, const BallisticDepositionSpec &spec);
} // namespace anticrack::dem
