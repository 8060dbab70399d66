// The six walls of a box test (docs/physics.md §1.5): planar walls on the faces of the domain, checked
// to be the inward faces of an axis-aligned box, and the servo gain that lets a wall hold a stress.
#pragma once

#include "dem/core/system.h"

#include <array>
#include <string>

namespace anticrack::dem
{
  /// Order of the walls of a box: index 2 axis + (0 for the lower face, 1 for the upper face).
  enum BoxFace : int
  {
    x_lower = 0,
    x_upper = 1,
    y_lower = 2,
    y_upper = 3,
    z_lower = 4,
    z_upper = 5
  };

  /// Appends six fixed planar walls on the faces of system.domain, named "x-", "x+", "y-", "y+",
  /// "z-", "z+", normals pointing into the box, sphere-wall law `contact`, each with the area of its
  /// face [m^2]; returns their indices into system.walls in BoxFace order. Walls change the
  /// per-wall state of the system: call before system.initialise() (or initialise again). Throws
  /// SetupError if an axis of the domain is periodic (a wall needs an open axis).
  std::array<Index, 6> add_box_walls(DemSystem &system, const ContactParameters &contact);

  /// Servo gain [m/(s N)] of a wall so that, if the spheres stood still, one step would remove the
  /// fraction `relaxation` of the force error (PFC's servo, Itasca PFC manual "servo-control of
  /// walls": G = alpha A / (k_n N_c dt) in stress units):
  ///   speed = gain (sigma_target A - F_n),  dF_n per step = K_w speed dt  =>  gain = alpha / (K_w dt),
  /// with K_w the summed normal stiffness of the sphere-wall contacts (overlap > 0) now, at least
  /// that of one contact with the mean sphere (so that a wall that touches nothing still has a
  /// finite gain; its speed is then limited by the wall's max_speed). The sample behind the wall
  /// is softer than the wall contacts, so the true fraction per step is smaller: stable for
  /// relaxation <= 1.
  double servo_gain_for(const DemSystem &system, const Wall &wall, double relaxation);

  /// Checks that walls[face] exist and are the inward faces of an axis-aligned box (normals +-e_axis
  /// pointing inwards, each upper face above its lower face); throws SetupError naming `who` otherwise.
  void check_box_walls(const DemSystem &system, const std::array<Index, 6> &walls, const std::string &who);
} // namespace anticrack::dem
