#include "dem/lab/box_walls.h"

#include "dem/contact/contact_law.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace anticrack::dem
{
  namespace
  {
    const char *const face_name[6] = {"x-", "x+", "y-", "y+", "z-", "z+"};

    Vec3 axis_vector(const int axis)
    {
      Vec3 e = Vec3::Zero();
      e[axis] = 1;
      return e;
    }
  } // namespace

  std::array<Index, 6> add_box_walls(DemSystem &system, const ContactParameters &contact)
  {
    const Domain &d = system.domain;
    for (int a = 0; a < 3; ++a)
    {
      if (d.periodic[a])
        throw SetupError("add_box_walls: domain axis " + std::string(1, "xyz"[a]) +
                         " is periodic; box walls need all three axes open (periodic = false)");
      if (!(d.upper[a] > d.lower[a]))
        throw SetupError("add_box_walls: domain upper corner must exceed the lower corner along " +
                         std::string(1, "xyz"[a]));
    }
    const Vec3 length = d.length();
    std::array<Index, 6> indices{};
    for (int face = 0; face < 6; ++face)
    {
      const int axis = face / 2;
      const bool upper = face % 2 == 1;
      Wall wall;
      wall.name = face_name[face];
      wall.normal = (upper ? -1.0 : 1.0) * axis_vector(axis);
      wall.point = upper ? d.upper : d.lower;
      wall.contact = contact;
      wall.control = WallControl::fixed;
      wall.area = length[(axis + 1) % 3] * length[(axis + 2) % 3];
      indices[face] = static_cast<Index>(system.walls.size());
      system.walls.push_back(wall);
    }
    return indices;
  }

  void check_box_walls(const DemSystem &system, const std::array<Index, 6> &walls, const std::string &who)
  {
    for (int face = 0; face < 6; ++face)
    {
      const Index w = walls[face];
      if (w < 0 || w >= static_cast<Index>(system.walls.size()))
        throw SetupError(who + ": wall index " + std::to_string(w) + " of face " + face_name[face] +
                         " must lie in [0, " + std::to_string(system.walls.size()) +
                         ") (system.walls; create them with add_box_walls)");
      const int axis = face / 2;
      const Vec3 inward = (face % 2 == 1 ? -1.0 : 1.0) * axis_vector(axis);
      if ((system.walls[w].normal - inward).norm() > 1e-9)
        throw SetupError(who + ": wall " + std::to_string(w) + " ('" + system.walls[w].name + "') of face " +
                         face_name[face] + " must have the inward normal " +
                         (face % 2 == 1 ? "-e_" : "+e_") + std::string(1, "xyz"[axis]));
    }
    for (int axis = 0; axis < 3; ++axis)
    {
      const double lower = system.walls[walls[2 * axis]].point[axis];
      const double upper = system.walls[walls[2 * axis + 1]].point[axis];
      if (!(upper > lower))
        throw SetupError(who + ": the " + face_name[2 * axis + 1] + " wall must lie above the " +
                         face_name[2 * axis] + " wall along " + std::string(1, "xyz"[axis]));
    }
  }

  double servo_gain_for(const DemSystem &system, const Wall &wall, const double relaxation)
  {
    if (!(relaxation > 0 && relaxation <= 1))
      throw SetupError("servo gain: relaxation " + format_for_message(relaxation) + " must lie in (0, 1]");
    if (!(system.dt > 0))
      throw SetupError("servo gain: the system has no time step yet; call DemSystem::initialise() first");
    const ParticleStore &ps = system.particles;
    double stiffness = 0, mean_radius = 0;
    for (Index p = 0; p < ps.size(); ++p)
    {
      mean_radius += ps.radius[p];
      const double overlap = ps.radius[p] - (ps.position[p] - wall.point).dot(wall.normal);
      if (overlap <= 0)
        continue;
      double kn, ks;
      contact_tangent_stiffness(wall.contact, ps.radius[p], 0, overlap, kn, ks);
      stiffness += kn;
    }
    if (ps.size() > 0)
      mean_radius /= static_cast<double>(ps.size());
    // Floor: one contact of the mean sphere (Hertz-Mindlin at 1 % overlap, as the critical time step
    // estimate of DemSystem assumes for a wall contact about to form).
    double kn_one = 0, ks_one;
    if (mean_radius > 0)
      contact_tangent_stiffness(wall.contact, mean_radius, 0, 0.01 * mean_radius, kn_one, ks_one);
    stiffness = std::max(stiffness, kn_one);
    if (!(stiffness > 0))
      throw SetupError("servo gain: wall '" + wall.name + "' has no contact stiffness (no particles?)");
    return relaxation / (stiffness * system.dt);
  }
} // namespace anticrack::dem
