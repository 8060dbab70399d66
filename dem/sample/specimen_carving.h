// Specimen preparation by carving (docs/physics.md §1.5): a disc or a prism cut out of a packing, as
// the Brazilian disc and the prism of Zhao & Feng (2022) are cut out of a sample.
#pragma once

#include "dem/core/system.h"

namespace anticrack::dem
{
  /// Removes every sphere whose centre lies outside the infinite cylinder of the given axis (0, 1, 2
  /// for x, y, z) through `centre` with `radius` [m] (a centre exactly on the surface stays). Returns
  /// the number of spheres removed; the remaining ones keep their order (ids are compacted).
  /// Carving is a specimen-preparation step: it refuses (SetupError) systems that already have bonds,
  /// clumps or have stepped, because bonds, clump member lists and per-pair state hold particle ids
  /// (bond the carved specimen afterwards, which also leaves no bonds to the removed material). It
  /// clears the contact list and the per-particle run state sized by the old count; call
  /// system.initialise() afterwards.
  Index carve_cylinder(DemSystem &system, int axis, const Vec3 &centre, double radius);

  /// Removes every sphere whose centre lies outside the box [lower, upper] (faces included stay);
  /// same rules and return value as carve_cylinder.
  Index carve_box(DemSystem &system, const Vec3 &lower, const Vec3 &upper);
} // namespace anticrack::dem
