#include "dem/lab/measurements.h"

#include "dem/core/parallel_sum.h"

#include <algorithm>
#include <cmath>
#include <set>

namespace anticrack::dem
{
  namespace
  {
    // The nine sums of a 3x3 tensor, for thread_independent_sum.
    void add_outer(std::array<double, 9> &sum, const Vec3 &a, const Vec3 &b, double factor)
    {
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c)
          sum[3 * r + c] += factor * a[r] * b[c];
    }
    Mat3 to_matrix(const std::array<double, 9> &sum)
    {
      Mat3 m;
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c)
          m(r, c) = sum[3 * r + c];
      return m;
    }
  } // namespace

  Mat3 love_weber_stress(const DemSystem &system, double volume, bool include_kinetic)
  {
    if (!(volume > 0))
      throw SetupError("Love-Weber stress: the volume must be positive");
    const auto &x = system.particles.position;
    const auto &contacts = system.contacts;
    // Listed pairs carry contact and bond loads together; unlisted bonds are summed separately.
    std::array<double, 9> sum = thread_independent_sum<9>(contacts.size(), [&](Index c, std::array<double, 9> &s) {
      const Vec3 branch = x[contacts.j[c]] + contacts.shift[c] - x[contacts.i[c]];
      add_outer(s, contacts.load[c].force_on_j, branch, -1.0);
    });
    const auto &unlisted_bonds = system.unlisted_bonds();
    const std::array<double, 9> unlisted = thread_independent_sum<9>(
      static_cast<Index>(unlisted_bonds.size()), [&](Index u, std::array<double, 9> &s) {
        const Index b = unlisted_bonds[u];
        const Vec3 branch = x[system.bonds.j[b]] + system.bonds.shift[b] - x[system.bonds.i[b]];
        add_outer(s, system.unlisted_bond_load(b).force_on_j, branch, -1.0);
      });
    for (int k = 0; k < 9; ++k)
      sum[k] += unlisted[k];
    if (include_kinetic)
    {
      const auto kinetic = thread_independent_sum<9>(system.particles.size(), [&](Index p, std::array<double, 9> &s) {
        add_outer(s, system.particles.velocity[p], system.particles.velocity[p], -system.particles.mass[p]);
      });
      for (int k = 0; k < 9; ++k)
        sum[k] += kinetic[k];
    }
    const Mat3 stress = to_matrix(sum) / volume;
    return 0.5 * (stress + stress.transpose());
  }

  Fabric contact_and_bond_fabric(const DemSystem &system)
  {
    Fabric fabric;
    const auto &x = system.particles.position;
    std::set<std::pair<Index, Index>> counted;
    auto count = [&](Index i, Index j, const Vec3 &shift) {
      if (!counted.emplace(i, j).second)
        return;
      const Vec3 n = (x[j] + shift - x[i]).normalized();
      fabric.tensor += n * n.transpose();
      ++fabric.pairs;
    };
    for (Index c = 0; c < system.contacts.size(); ++c)
      if (system.contacts.overlap[c] > 0)
        count(system.contacts.i[c], system.contacts.j[c], system.contacts.shift[c]);
    for (Index b = 0; b < system.bonds.size(); ++b)
      if (system.bonds.state[b] == BondState::intact)
        count(system.bonds.i[b], system.bonds.j[b], system.bonds.shift[b]);
    if (fabric.pairs > 0)
      fabric.tensor /= static_cast<double>(fabric.pairs);
    if (system.particles.size() > 0)
      fabric.coordination = 2.0 * fabric.pairs / system.particles.size();
    return fabric;
  }

  std::pair<double, double> sphere_extent(const ParticleStore &particles, int axis)
  {
    if (particles.size() == 0)
      return {0, 0};
    double lo = particles.position[0][axis] - particles.radius[0];
    double hi = particles.position[0][axis] + particles.radius[0];
    for (Index p = 1; p < particles.size(); ++p)
    {
      lo = std::min(lo, particles.position[p][axis] - particles.radius[p]);
      hi = std::max(hi, particles.position[p][axis] + particles.radius[p]);
    }
    return {lo, hi};
  }

  double sample_volume(const DemSystem &system)
  {
    if (system.particles.size() == 0)
      return 0;
    double volume = 1;
    for (int a = 0; a < 3; ++a)
    {
      if (system.domain.periodic[a])
        volume *= system.domain.length()[a];
      else
      {
        const auto [lo, hi] = sphere_extent(system.particles, a);
        volume *= hi - lo;
      }
    }
    return volume;
  }

  double broken_bond_fraction(const BondList &bonds)
  {
    return bonds.size() == 0 ? 0.0 : 1.0 - static_cast<double>(bonds.count_intact()) / bonds.size();
  }

  double mobilised_friction_angle(const double major, const double minor)
  {
    if (!(minor > 0) || !(major >= minor))
      throw SetupError("mobilised friction angle: needs major >= minor > 0 (compressive positive), got " +
                       format_for_message(major) + " and " + format_for_message(minor) + " Pa");
    return std::asin((major - minor) / (major + minor));
  }

  double brazilian_tensile_strength(const double force, const double diameter, const double thickness)
  {
    if (!(diameter > 0) || !(thickness > 0))
      throw SetupError("Brazilian tensile strength: diameter " + format_for_message(diameter) + " m and thickness " +
                       format_for_message(thickness) + " m must be positive");
    return 2 * force / (M_PI * diameter * thickness);
  }
} // namespace anticrack::dem
