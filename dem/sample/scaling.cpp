#include "dem/sample/scaling.h"

#include <cmath>
#include <string>

namespace anticrack::dem
{
  void scale_sample(DemSystem &system, double s)
  {
    if (!(s > 0) || !std::isfinite(s))
      throw SetupError("scale_sample: the scale factor must be positive (got " + std::to_string(s) + ")");
    if (system.step_count != 0)
      throw SetupError("scale_sample: the system has already run " + std::to_string(system.step_count) +
                       " steps; scale a sample before initialise() and the first step");
    const double s2 = s * s, s3 = s2 * s, s5 = s3 * s2;

    ParticleStore &p = system.particles;
    for (Index i = 0; i < p.size(); ++i)
    {
      p.position[i] *= s;
      p.radius[i] *= s;
      p.mass[i] *= s3;
      p.inertia[i] *= s5;
      p.angular_velocity[i] /= s; // same surface speeds
      p.force[i] *= s2;
      p.torque[i] *= s3;
    }
    system.domain.lower *= s;
    system.domain.upper *= s;

    BondList &b = system.bonds;
    for (Index k = 0; k < b.size(); ++k)
    {
      b.shift[k] *= s;
      b.radius[k] *= s;
      b.normal_stiffness[k] *= s; // E A / L
      b.shear_stiffness[k] *= s;
      b.twist_stiffness[k] *= s3; // E J / L
      b.bending_stiffness[k] *= s3;
      b.normal_force[k] *= s2;
      b.shear_force[k] *= s2;
      b.twist_moment[k] *= s3;
      b.bending_moment[k] *= s3;
    }
    ContactList &c = system.contacts;
    for (Index k = 0; k < c.size(); ++k)
    {
      c.shift[k] *= s;
      c.shear_force[k] *= s2;
      c.overlap[k] *= s;
      c.dashpot_force[k] *= s2;
    }

    for (Clump &clump : system.clumps)
    {
      // Rebuild the rigid body from its (scaled) members, keeping its motion and load history.
      Clump scaled = clump;
      scaled.mass *= s3;
      scaled.centre *= s;
      scaled.displacement *= s;
      scaled.principal_inertia *= s5;
      scaled.angular_momentum *= s5 / s; // I omega with omega / s
      scaled.angular_velocity /= s;
      for (Vec3 &offset : scaled.member_offset)
        offset *= s;
      for (double &t : scaled.applied_force.time)
        t *= s;
      for (Vec3 &f : scaled.applied_force.value)
        f *= s2;
      clump = scaled;
    }
    for (Wall &wall : system.walls)
    {
      wall.point *= s;
      wall.area *= s2;
      wall.force *= s2;
      wall.servo_gain /= s2;
    }
    for (Vec3 &f : system.wall_shear)
      f *= s2;
    for (Vec3 &f : system.wall_dashpot)
      f *= s2;
    system.settings.time_step *= s;
    system.settings.verlet_skin *= s;
  }
} // namespace anticrack::dem
