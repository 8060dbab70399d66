#include "dem/lab/measurements.h"

#include "dem/core/parallel_sum.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <string>

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

  namespace
  {
    /// sum over every loaded pair (listed contacts with their bonds, then the unlisted bonds) of
    /// add(i, j, branch x_j + shift - x_i, force on j, s), independent of the thread count.
    template <std::size_t K, class Add>
    std::array<double, K> sum_over_pairs(const DemSystem &system, const Add &add)
    {
      const auto &x = system.particles.position;
      const auto &contacts = system.contacts;
      std::array<double, K> sum = thread_independent_sum<K>(contacts.size(), [&](Index c, std::array<double, K> &s) {
        const Index i = contacts.i[c], j = contacts.j[c];
        add(i, j, x[j] + contacts.shift[c] - x[i], contacts.load[c].force_on_j, s);
      });
      const auto &unlisted_bonds = system.unlisted_bonds();
      const std::array<double, K> unlisted = thread_independent_sum<K>(
        static_cast<Index>(unlisted_bonds.size()), [&](Index u, std::array<double, K> &s) {
          const Index b = unlisted_bonds[u];
          const Index i = system.bonds.i[b], j = system.bonds.j[b];
          add(i, j, x[j] + system.bonds.shift[b] - x[i], system.unlisted_bond_load(b).force_on_j, s);
        });
      for (std::size_t k = 0; k < K; ++k)
        sum[k] += unlisted[k];
      return sum;
    }

    void check_mask(const DemSystem &system, const PlatenSpheres &platens, const char *what)
    {
      if (!platens.empty() && platens.size() != static_cast<std::size_t>(system.particles.size()))
        throw SetupError(std::string(what) + ": the platen mask has " + std::to_string(platens.size()) +
                         " entries for " + std::to_string(system.particles.size()) + " spheres");
    }
  } // namespace

  Mat3 love_weber_stress(const DemSystem &system, double volume, bool include_kinetic, const PlatenSpheres &platens)
  {
    if (!(volume > 0))
      throw SetupError("Love-Weber stress: the volume must be positive");
    check_mask(system, platens, "Love-Weber stress");
    const auto material = [&](Index p) { return platens.empty() || platens[p] == Platen::none; };
    std::array<double, 9> sum = sum_over_pairs<9>(
      system, [&](Index i, Index j, const Vec3 &branch, const Vec3 &force_on_j, std::array<double, 9> &s) {
        if (material(i) || material(j))
          add_outer(s, force_on_j, branch, -1.0);
      });
    if (include_kinetic)
    {
      const auto kinetic = thread_independent_sum<9>(system.particles.size(), [&](Index p, std::array<double, 9> &s) {
        if (material(p))
          add_outer(s, system.particles.velocity[p], system.particles.velocity[p], -system.particles.mass[p]);
      });
      for (int k = 0; k < 9; ++k)
        sum[k] += kinetic[k];
    }
    const Mat3 stress = to_matrix(sum) / volume;
    return 0.5 * (stress + stress.transpose());
  }

  double platen_separation(const DemSystem &system, const PlatenSpheres &platens)
  {
    check_mask(system, platens, "platen separation");
    if (platens.empty())
      throw SetupError("platen separation: needs spheres of both platens");
    const auto &x = system.particles.position;
    // Per platen (0 base, 1 top): sum |f_z| z and sum |f_z| over its spheres' pairs with material.
    const std::array<double, 4> sums = sum_over_pairs<4>(
      system, [&](Index i, Index j, const Vec3 &, const Vec3 &force_on_j, std::array<double, 4> &s) {
        const Platen pi = platens[i], pj = platens[j];
        if ((pi == Platen::none) == (pj == Platen::none))
          return; // material-material or platen-platen
        const Index platen_sphere = pi == Platen::none ? j : i;
        const int k = platens[platen_sphere] == Platen::base ? 0 : 2;
        const double weight = std::abs(force_on_j.z());
        s[k] += weight * x[platen_sphere].z();
        s[k + 1] += weight;
      });
    double base_top = -std::numeric_limits<double>::infinity(), top_bottom = std::numeric_limits<double>::infinity();
    for (Index p = 0; p < system.particles.size(); ++p)
      if (platens[p] == Platen::base)
        base_top = std::max(base_top, x[p].z());
      else if (platens[p] == Platen::top)
        top_bottom = std::min(top_bottom, x[p].z());
    if (!std::isfinite(base_top) || !std::isfinite(top_bottom))
      throw SetupError("platen separation: needs spheres of both platens");
    if (!(sums[1] > 0) || !(sums[3] > 0))
      return top_bottom - base_top;
    return sums[2] / sums[3] - sums[0] / sums[1];
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

  Vec3 total_force(const ParticleStore &particles, const std::vector<Index> &spheres)
  {
    Vec3 force = Vec3::Zero();
    for (const Index p : spheres)
      force += particles.force[p];
    return force;
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
