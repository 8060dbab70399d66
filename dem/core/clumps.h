// Rigid clumps: sets of spheres that move as one rigid body. The clump carries the summed force
// and torque of its members (about its centre of mass) plus an optional applied force history;
// members do not interact with each other. Translation and rotation are integrated with the same
// leapfrog as free spheres; rotation uses the angular momentum and the world-frame inertia
// tensor I = R I_body R^T, so that clumps of any shape rotate correctly.
#pragma once

#include "dem/core/force_history.h"
#include "dem/core/particles.h"

#include <vector>

namespace anticrack::dem
{
  struct Clump
  {
    std::vector<Index> members;
    double mass = 0;
    Vec3 centre = Vec3::Zero();          ///< centre of mass (wrapped into a periodic box at rebuilds)
    Vec3 displacement = Vec3::Zero();    ///< of the centre since the clump was made, never wrapped
    Vec3 velocity = Vec3::Zero();        ///< at half step
    Vec3 angular_momentum = Vec3::Zero();///< at half step
    Vec3 angular_velocity = Vec3::Zero();
    Quat orientation = Quat::Identity();
    Vec3 principal_inertia = Vec3::Ones();///< body frame
    Quat principal_frame = Quat::Identity(); ///< rotation body principal frame -> world at t=0
    std::vector<Vec3> member_offset;     ///< member centres in the principal body frame
    bool rotation_locked = false;
    std::uint8_t blocked = free_dofs;    ///< block_translation keeps the clump velocity
    /// Bit a set: the velocity component a is prescribed (kept), the others follow the forces
    /// (a platen driven along x and free along z, e.g. simple shear at constant normal force).
    std::uint8_t held_axes = 0;
    ForceHistory applied_force;          ///< external force on the centre of mass [N]
    Vec3 force = Vec3::Zero();           ///< last total force (members + applied + gravity)
    Vec3 torque = Vec3::Zero();          ///< last total torque about the centre

    /// World-frame inverse inertia tensor for the current orientation.
    [[nodiscard]] Mat3 inverse_inertia_world() const;
  };

  /// Builds a clump from existing particles: computes mass, centre, inertia tensor (members as solid
  /// spheres, overlaps counted twice, as in PFC/YADE clumps of spheres) and marks the members.
  Clump make_clump(ParticleStore &particles, const std::vector<Index> &members, int clump_id);
} // namespace anticrack::dem
