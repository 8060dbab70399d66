// Baxter's sticky hard spheres (SHS): the Percus-Yevick relations between volume fraction phi,
// stickiness tau (smaller = stickier) and mean coordination number z (PHYSICS.md §1.4; Baxter 1968,
// J. Chem. Phys. 49:2770; Seaton & Glandt 1987, J. Chem. Phys. 86:4668). The sampler that builds
// SHS samples uses them to pick tau for a target z and to refuse unphysical requests.
//
//   lambda: smaller root of (phi/12) lambda^2 - (tau + phi/(1-phi)) lambda + (1 + phi/2)/(1-phi)^2 = 0
//   z = 2 phi lambda
//   tau_min(phi) = (14 phi^2 - 4 phi - 1) / (12 (2 phi^2 - phi - 1))
#pragma once

namespace anticrack::dem::shs
{
  /// Lower bound of the admissible stickiness at volume fraction phi (0 < phi < 1).
  double minimum_stickiness(double phi);

  /// Percus-Yevick lambda(phi, tau); throws SetupError (naming phi and tau and the admissible range)
  /// when tau < tau_min(phi) or the relation has no real root.
  double percus_yevick_lambda(double phi, double tau);

  /// Mean coordination number z = 2 phi lambda of the Percus-Yevick SHS fluid.
  double percus_yevick_coordination(double phi, double tau);

  /// The stickiness tau that gives the coordination number z at volume fraction phi (the PY relation
  /// solved for tau: tau = ((phi/12) lambda^2 + (1 + phi/2)/(1-phi)^2) / lambda - phi/(1-phi) with
  /// lambda = z/(2 phi), on the branch where lambda is the smaller root); throws SetupError when z is
  /// not reachable with tau >= tau_min(phi).
  double stickiness_for_coordination(double phi, double z);
} // namespace anticrack::dem::shs
