#include "dem/core/neighbor_list.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace anticrack::dem
{
  namespace
  {
    struct Candidate
    {
      Index j;
      Vec3 shift;
    };

    /// Appends j to i's candidates when the gap is below the skin.
    inline void consider(const ParticleStore &particles, const Domain &domain, double skin, Index i,
                         Index j, std::vector<Candidate> &out)
    {
      if (particles.clump_id[i] >= 0 && particles.clump_id[i] == particles.clump_id[j])
        return;
      const Vec3 shift = domain.minimum_image_shift(particles.position[i], particles.position[j]);
      const double reach = particles.radius[i] + particles.radius[j] + skin;
      if ((particles.position[j] + shift - particles.position[i]).squaredNorm() < reach * reach)
        out.push_back({j, shift});
    }
  } // namespace

  void NeighborList::build(ParticleStore &particles, const Domain &domain, double skin,
                           ContactList &contacts)
  {
    const Index n = particles.size();
    // Clump members are placed by their clump, which wraps its own centre.
    for (Index p = 0; p < n; ++p)
      if (particles.clump_id[p] < 0)
        particles.position[p] = domain.wrap(particles.position[p]);

    double r_max = 0;
    for (const double r : particles.radius)
      r_max = std::max(r_max, r);
    const double cell_size = 2 * r_max + skin;

    // Cell grid: the box along periodic axes, the particles' bounding box otherwise.
    Vec3 lo = domain.lower, hi = domain.upper;
    for (int a = 0; a < 3; ++a)
      if (!domain.periodic[a] && n > 0)
      {
        lo[a] = hi[a] = particles.position[0][a];
        for (Index p = 0; p < n; ++p)
        {
          lo[a] = std::min(lo[a], particles.position[p][a]);
          hi[a] = std::max(hi[a], particles.position[p][a]);
        }
      }
    std::array<Index, 3> cells{};
    bool all_pairs = false;
    for (int a = 0; a < 3; ++a)
    {
      cells[a] = std::max<Index>(1, static_cast<Index>(std::floor((hi[a] - lo[a]) / cell_size)));
      if (domain.periodic[a])
      {
        if (domain.length()[a] < 2 * cell_size)
          throw SetupError("periodic box too small along axis " + std::to_string(a) + ": length " +
                           std::to_string(domain.length()[a]) + " m, needs at least 2 (2 R_max + skin) = " +
                           std::to_string(2 * cell_size) + " m");
        all_pairs = all_pairs || cells[a] < 3;
      }
    }
    // A sparse system spread over a large region would get far more cells than particles: coarsen
    // the grid along the non-periodic axes (where the extent comes from the particles) so that the
    // cell count stays O(N); coarser cells only add candidates to test.
    const double cell_budget = 2.0 * static_cast<double>(n) + 1000.0;
    double periodic_cells = 1, open_cells = 1;
    for (int a = 0; a < 3; ++a)
      (domain.periodic[a] ? periodic_cells : open_cells) *= static_cast<double>(cells[a]);
    if (periodic_cells * open_cells > cell_budget && open_cells > 1)
    {
      const int open_axes = 3 - static_cast<int>(domain.periodic[0] + domain.periodic[1] + domain.periodic[2]);
      const double coarsen =
        std::pow(periodic_cells * open_cells / cell_budget, 1.0 / open_axes);
      for (int a = 0; a < 3; ++a)
        if (!domain.periodic[a])
          cells[a] = std::max<Index>(1, static_cast<Index>(cells[a] / coarsen));
    }

    std::vector<std::vector<Candidate>> candidates(n);
    if (all_pairs || n < 64)
    {
      for (Index i = 0; i < n; ++i)
        for (Index j = i + 1; j < n; ++j)
          consider(particles, domain, skin, i, j, candidates[i]);
    }
    else
    {
      const Vec3 width((hi[0] - lo[0]) / cells[0], (hi[1] - lo[1]) / cells[1], (hi[2] - lo[2]) / cells[2]);
      auto cell_coordinate = [&](const Vec3 &x, int a) {
        const double w = width[a] > 0 ? width[a] : 1.0;
        const double coordinate_a = domain.periodic[a] ? domain.wrap(x)[a] : x[a];
        const Index c = static_cast<Index>(std::floor((coordinate_a - lo[a]) / w));
        return std::clamp<Index>(c, 0, cells[a] - 1);
      };
      const Index cell_count = cells[0] * cells[1] * cells[2];
      std::vector<Index> cell_of(n), start(cell_count + 1, 0), members(n);
      std::vector<std::array<Index, 3>> coordinate(n);
      for (Index p = 0; p < n; ++p)
      {
        for (int a = 0; a < 3; ++a)
          coordinate[p][a] = cell_coordinate(particles.position[p], a);
        cell_of[p] = coordinate[p][0] + cells[0] * (coordinate[p][1] + cells[1] * coordinate[p][2]);
        ++start[cell_of[p] + 1];
      }
      for (Index c = 0; c < cell_count; ++c)
        start[c + 1] += start[c];
      std::vector<Index> fill(start.begin(), start.end() - 1);
      for (Index p = 0; p < n; ++p)
        members[fill[cell_of[p]]++] = p;

#pragma omp parallel for schedule(dynamic, 256)
      for (Index i = 0; i < n; ++i)
      {
        for (Index dz = -1; dz <= 1; ++dz)
          for (Index dy = -1; dy <= 1; ++dy)
            for (Index dx = -1; dx <= 1; ++dx)
            {
              const std::array<Index, 3> d = {dx, dy, dz};
              std::array<Index, 3> c{};
              bool inside = true;
              for (int a = 0; a < 3; ++a)
              {
                c[a] = coordinate[i][a] + d[a];
                if (domain.periodic[a])
                  c[a] = (c[a] + cells[a]) % cells[a];
                else if (c[a] < 0 || c[a] >= cells[a])
                  inside = false;
              }
              if (!inside)
                continue;
              const Index cell = c[0] + cells[0] * (c[1] + cells[1] * c[2]);
              for (Index k = start[cell]; k < start[cell + 1]; ++k)
                if (members[k] > i)
                  consider(particles, domain, skin, i, members[k], candidates[i]);
            }
        std::sort(candidates[i].begin(), candidates[i].end(),
                  [](const Candidate &a, const Candidate &b) { return a.j < b.j; });
      }
    }

    // Merge into the new list, carrying the tangential state of pairs that persist. Both the old
    // and the new list are sorted by (i, j).
    ContactList fresh;
    Index total = 0;
    for (const auto &c : candidates)
      total += static_cast<Index>(c.size());
    fresh.i.reserve(total);
    Index old = 0;
    for (Index i = 0; i < n; ++i)
      for (const Candidate &c : candidates[i])
      {
        fresh.push_back(i, c.j, c.shift);
        const Index k = fresh.size() - 1;
        while (old < contacts.size() &&
               (contacts.i[old] < i || (contacts.i[old] == i && contacts.j[old] < c.j)))
          ++old;
        if (old < contacts.size() && contacts.i[old] == i && contacts.j[old] == c.j)
        {
          fresh.shear_force[k] = contacts.shear_force[old];
          fresh.normal[k] = contacts.normal[old];
          fresh.active[k] = contacts.active[old];
          fresh.dashpot_force[k] = contacts.dashpot_force[old];
        }
        const double distance = (particles.position[c.j] + c.shift - particles.position[i]).norm();
        fresh.overlap[k] = particles.radius[i] + particles.radius[c.j] - distance;
      }
    contacts = std::move(fresh);

    reference_position_ = particles.position;
    ++builds_;
  }

  bool NeighborList::needs_rebuild(const ParticleStore &particles, double skin) const
  {
    const Index n = particles.size();
    if (static_cast<Index>(reference_position_.size()) != n)
      return true;
    const double limit = 0.25 * skin * skin;
    int moved = 0;
#pragma omp parallel for schedule(static) reduction(max : moved)
    for (Index p = 0; p < n; ++p)
      if ((particles.position[p] - reference_position_[p]).squaredNorm() > limit)
        moved = 1;
    return moved != 0;
  }
} // namespace anticrack::dem
