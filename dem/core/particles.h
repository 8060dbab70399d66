// Sphere storage in structure-of-arrays form: one contiguous array per attribute, indexed by the
// particle's position in the store (its id). Clump members are ordinary particles with a clump id.
#pragma once

#include "dem/common/types.h"

#include <cmath>
#include <vector>

namespace anticrack::dem
{
  /// Degrees of freedom a particle may have blocked. A blocked DOF keeps the velocity it has
  /// (zero for "fixed"), whatever force acts on it; the force it feels is the boundary reaction.
  enum BlockedDofs : std::uint8_t
  {
    free_dofs = 0,
    block_translation = 1,
    block_rotation = 2,
    block_all = block_translation | block_rotation
  };

  /// Volume of a sphere of radius r, 4/3 pi r^3.
  inline double sphere_volume(double r) { return 4.0 / 3.0 * M_PI * r * r * r; }

  /// Keeps the entries i with keep[i] != 0 (in order) and drops the others: the compaction of every
  /// per-particle array when particles are removed.
  template <class T>
  void keep_entries(std::vector<T> &values, const std::vector<char> &keep)
  {
    std::size_t kept = 0;
    for (std::size_t i = 0; i < values.size(); ++i)
      if (keep[i])
        values[kept++] = std::move(values[i]);
    values.resize(kept);
  }

  struct ParticleStore
  {
    // --- kinematic state (velocities live at half steps in the leapfrog scheme)
    std::vector<Vec3> position;
    std::vector<Vec3> velocity;
    std::vector<Vec3> angular_velocity;
    // --- per-step results
    std::vector<Vec3> force;
    std::vector<Vec3> torque;
    // --- properties
    std::vector<double> radius;
    std::vector<double> mass;
    std::vector<double> inertia; ///< moment of inertia of a solid sphere, 2/5 m R^2
    std::vector<int> material_id;
    std::vector<int> group_id;
    std::vector<std::uint8_t> blocked;
    std::vector<int> clump_id; ///< -1 when the particle is not part of a clump

    [[nodiscard]] Index size() const { return static_cast<Index>(position.size()); }

    /// Append a solid sphere of the given density; returns its id.
    Index add_sphere(const Vec3 &x, double r, double density, int material = 0, int group = 0);

    /// Resize every array consistently (used by readers).
    void resize(Index n);

    /// Keeps the particles with keep[p] != 0 (in their order) and drops the others from every
    /// array; keep.size() must equal size(). Ids of the kept particles change.
    void keep(const std::vector<char> &keep);

    /// True when every array has the same length.
    [[nodiscard]] bool consistent() const;
  };
} // namespace anticrack::dem
