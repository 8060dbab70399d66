// Micro-to-macro measurements on a DEM state (docs/physics.md §1.5): the Love-Weber stress tensor, the
// fabric tensor and coordination numbers. They read the loads of the last step, so call them after
// DemSystem::step().
#pragma once

#include "dem/lab/stress_invariants.h"
#include "dem/core/system.h"

#include <utility>
#include <vector>

namespace anticrack::dem
{
  /// What a sphere is to a specimen between two rigid platens along z: material, or a sphere of the
  /// fixed base or of the loading platen (the clump).
  enum class Platen : unsigned char
  {
    none,
    base,
    top
  };
  /// One role per sphere; empty: every sphere is material.
  using PlatenSpheres = std::vector<Platen>;

  /// Love-Weber stress over the volume V (tension positive, docs/physics.md §0 and §1.5):
  ///   sigma = -(1/V) sum_pairs F_j (x) l  -  (1/V) sum_p m v (x) v
  /// with F_j the force a pair exerts on its particle j (contact and bond together) and l the branch
  /// vector x_j + shift - x_i, so that pushing spheres give compression. With `platens`, the pairs
  /// of two platen spheres and the platens' kinetic part do not count: the stress of the material
  /// between the platens, whose volume V is then the platen area times platen_separation() (the
  /// branches of the material-platen pairs end at the platens' centres). In static equilibrium
  /// without body forces this is exactly the platen traction (sigma_zz = -F_base / A), for rough
  /// platens too. Sphere-wall contacts are boundary tractions and do not enter; the
  /// kinetic part uses the half-step velocities. Bond couples make the contact part slightly
  /// asymmetric; the symmetric part is returned.
  Mat3 love_weber_stress(const DemSystem &system, double volume, bool include_kinetic = true,
                         const PlatenSpheres &platens = {});

  /// Distance along z between the platens' lines of action [m]: for each platen, the height of its
  /// spheres' centres weighted by the |z-force| each gets from the material, top minus base. For
  /// flat platens the distance between their centre planes; for rough ones (an actuator of large
  /// spheres resting in the valleys of a deposit) the height at which the load actually enters, so
  /// that the Love-Weber stress over (area x this) has the platen traction as its zz-component.
  /// Without load on either platen, the distance between the highest base and the lowest top
  /// centre. Throws SetupError without spheres of both platens.
  double platen_separation(const DemSystem &system, const PlatenSpheres &platens);

  struct Fabric
  {
    Mat3 tensor = Mat3::Zero();   ///< C = (1/N_c) sum n (x) n over the counted pairs (trace 1)
    Index pairs = 0;              ///< N_c
    double coordination = 0;      ///< 2 N_c / N over the particles considered
  };

  /// Fabric of the touching contacts (overlap > 0 at the last step) and of the intact bonds, counted
  /// once per pair (a bonded pair that touches counts once), over all particles.
  Fabric contact_and_bond_fabric(const DemSystem &system);

  /// Lowest and highest sphere surface along an axis (0, 0 for no spheres).
  std::pair<double, double> sphere_extent(const ParticleStore &particles, int axis);

  /// Volume the sample occupies: along periodic axes the box length, along open axes the extent of
  /// the spheres (lowest surface to highest surface). The volume for the Love-Weber stress.
  double sample_volume(const DemSystem &system);

  /// The sum of the forces on `spheres` (e.g. a fixed base: minus its z-component is the compressive
  /// reaction the specimen exerts on it).
  Vec3 total_force(const ParticleStore &particles, const std::vector<Index> &spheres);

  /// Fraction of bonds that are broken (0 when there are none).
  double broken_bond_fraction(const BondList &bonds);

  /// Mobilised friction angle [rad] of a cohesionless sample at principal stresses major >= minor > 0
  /// (compressive positive): sin(phi) = (sigma_1 - sigma_3) / (sigma_1 + sigma_3) (Mohr-Coulomb).
  double mobilised_friction_angle(double major, double minor);

  /// Splitting tensile strength of a Brazilian disc [Pa]: sigma_t = 2 F / (pi D t) (ISRM 1978;
  /// Zhao & Feng 2022, section 5), F the failure load [N], D the diameter [m], t the thickness [m].
  double brazilian_tensile_strength(double force, double diameter, double thickness);
} // namespace anticrack::dem
