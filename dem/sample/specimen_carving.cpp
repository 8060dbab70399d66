#include "dem/sample/specimen_carving.h"

#include <cmath>
#include <string>
#include <vector>

namespace anticrack::dem
{
  namespace
  {
    /// Per-wall blocks [w * n + p] of sphere-wall state, compacted to the kept particles (resized to
    /// the new count if the block layout does not match the old one).
    void keep_wall_slots(std::vector<Vec3> &slots, const std::vector<char> &keep, std::size_t walls, Index kept)
    {
      const std::size_t n = keep.size();
      if (slots.size() != walls * n)
      {
        slots.assign(walls * static_cast<std::size_t>(kept), Vec3::Zero());
        return;
      }
      std::vector<Vec3> compact;
      compact.reserve(walls * static_cast<std::size_t>(kept));
      for (std::size_t w = 0; w < walls; ++w)
        for (std::size_t p = 0; p < n; ++p)
          if (keep[p])
            compact.push_back(slots[w * n + p]);
      slots = std::move(compact);
    }

    /// Removes the particles with keep[p] == 0 (see carve_cylinder for the rules); returns the count.
    Index remove_particles(DemSystem &system, const std::vector<char> &keep, const std::string &who)
    {
      if (system.bonds.size() > 0 || !system.clumps.empty() || system.step_count > 0)
        throw SetupError(who + ": carve the specimen before bonding, clumping and stepping (the system has " +
                         std::to_string(system.bonds.size()) + " bonds, " + std::to_string(system.clumps.size()) +
                         " clumps and has run " + std::to_string(system.step_count) + " steps)");
      ParticleStore &ps = system.particles;
      const Index before = ps.size();
      ps.keep(keep);
      if (!ps.consistent())
        throw SetupError(who + ": particle arrays became inconsistent");
      const Index kept = ps.size();
      // Run state sized by the particle count (present after initialise()).
      if (static_cast<Index>(system.previous_velocity.size()) == before)
        keep_entries(system.previous_velocity, keep);
      if (static_cast<Index>(system.previous_angular_velocity.size()) == before)
        keep_entries(system.previous_angular_velocity, keep);
      keep_wall_slots(system.wall_shear, keep, system.walls.size(), kept);
      keep_wall_slots(system.wall_dashpot, keep, system.walls.size(), kept);
      // Candidate pairs hold old ids; initialise() builds the list again.
      system.contacts.clear();
      return before - kept;
    }
  } // namespace

  Index carve_cylinder(DemSystem &system, const int axis, const Vec3 &centre, const double radius)
  {
    if (axis < 0 || axis > 2)
      throw SetupError("carve_cylinder: axis " + std::to_string(axis) + " must be 0, 1 or 2 (x, y, z)");
    if (!(radius > 0) || !std::isfinite(radius))
      throw SetupError("carve_cylinder: radius " + format_for_message(radius) + " m must be positive and finite");
    const auto &x = system.particles.position;
    std::vector<char> keep(x.size());
    for (std::size_t p = 0; p < x.size(); ++p)
    {
      Vec3 off = x[p] - centre;
      off[axis] = 0;
      keep[p] = off.squaredNorm() <= radius * radius;
    }
    return remove_particles(system, keep, "carve_cylinder");
  }

  Index carve_box(DemSystem &system, const Vec3 &lower, const Vec3 &upper)
  {
    for (int a = 0; a < 3; ++a)
      if (!(upper[a] > lower[a]))
        throw SetupError("carve_box: upper corner must exceed the lower corner along " + std::string(1, "xyz"[a]) +
                         " (lower " + format_for_message(lower[a]) + " m, upper " + format_for_message(upper[a]) +
                         " m)");
    const auto &x = system.particles.position;
    std::vector<char> keep(x.size());
    for (std::size_t p = 0; p < x.size(); ++p)
      keep[p] = (x[p].array() >= lower.array()).all() && (x[p].array() <= upper.array()).all();
    return remove_particles(system, keep, "carve_box");
  }
} // namespace anticrack::dem
