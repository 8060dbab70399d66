#include "dem/core/particles.h"

#include <cmath>

namespace anticrack::dem
{
  Index ParticleStore::add_sphere(const Vec3 &x, double r, double density, int material, int group)
  {
    if (!(r > 0) || !(density > 0))
      throw SetupError("add_sphere: radius and density must be positive (got R = " + std::to_string(r) +
                       " m, rho = " + std::to_string(density) + " kg/m^3)");
    const double m = density * sphere_volume(r);
    position.push_back(x);
    velocity.push_back(Vec3::Zero());
    angular_velocity.push_back(Vec3::Zero());
    force.push_back(Vec3::Zero());
    torque.push_back(Vec3::Zero());
    radius.push_back(r);
    mass.push_back(m);
    inertia.push_back(0.4 * m * r * r);
    material_id.push_back(material);
    group_id.push_back(group);
    blocked.push_back(free_dofs);
    clump_id.push_back(-1);
    return size() - 1;
  }

  void ParticleStore::resize(Index n)
  {
    position.resize(n);
    velocity.resize(n);
    angular_velocity.resize(n);
    force.resize(n);
    torque.resize(n);
    radius.resize(n);
    mass.resize(n);
    inertia.resize(n);
    material_id.resize(n);
    group_id.resize(n);
    blocked.resize(n);
    clump_id.resize(n, -1);
  }

  bool ParticleStore::consistent() const
  {
    const std::size_t n = position.size();
    return velocity.size() == n && angular_velocity.size() == n && force.size() == n &&
           torque.size() == n && radius.size() == n && mass.size() == n && inertia.size() == n &&
           material_id.size() == n && group_id.size() == n && blocked.size() == n &&
           clump_id.size() == n;
  }


  void ParticleStore::keep(const std::vector<char> &keep)
  {
    if (static_cast<Index>(keep.size()) != size())
      throw SetupError("ParticleStore::keep: the mask has " + std::to_string(keep.size()) + " entries for " +
                       std::to_string(size()) + " particles");
    // Every array is compacted here; a new field must be added too.
    static_assert(sizeof(ParticleStore) == 12 * sizeof(std::vector<double>),
                  "ParticleStore gained or lost an array: update ParticleStore::keep");
    keep_entries(position, keep);
    keep_entries(velocity, keep);
    keep_entries(angular_velocity, keep);
    keep_entries(force, keep);
    keep_entries(torque, keep);
    keep_entries(radius, keep);
    keep_entries(mass, keep);
    keep_entries(inertia, keep);
    keep_entries(material_id, keep);
    keep_entries(group_id, keep);
    keep_entries(blocked, keep);
    keep_entries(clump_id, keep);
  }
} // namespace anticrack::dem
