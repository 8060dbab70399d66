// Verlet list built with linked cells (docs/physics.md §1.3 and any MD text, e.g. Allen & Tildesley §5.3).
// Candidate pairs are those with a gap below `skin`; the list stays valid until some particle has
// moved by more than skin/2 since the build. Polydisperse radii: the cell size is 2 R_max + skin.
// Periodic axes wrap the cell grid; when an axis has fewer than three cells the search falls back
// to an all-pairs minimum-image loop (tiny systems, tests).
#pragma once

#include "dem/core/domain.h"
#include "dem/common/interactions.h"
#include "dem/core/particles.h"

#include <vector>

namespace anticrack::dem
{
  class NeighborList
  {
  public:
    /// Wraps positions into the periodic box, then rebuilds `contacts` keeping the tangential state
    /// of pairs that were already in the list. Pairs of the same clump are left out.
    void build(ParticleStore &particles, const Domain &domain, double skin, ContactList &contacts);

    /// True when some particle has moved more than skin/2 since the last build.
    [[nodiscard]] bool needs_rebuild(const ParticleStore &particles, double skin) const;

    [[nodiscard]] Index builds() const { return builds_; }

    /// Positions at the last build (the rebuild criterion's reference), for checkpoints.
    [[nodiscard]] const std::vector<Vec3> &reference_positions() const { return reference_position_; }
    void restore_reference_positions(std::vector<Vec3> positions) { reference_position_ = std::move(positions); }

  private:
    std::vector<Vec3> reference_position_;
    Index builds_ = 0;
  };
} // namespace anticrack::dem
