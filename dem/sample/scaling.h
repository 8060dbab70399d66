// Homothetic scaling of a sample: every length by a factor s, with moduli, strengths and densities
// unchanged. Stresses, strains and failure envelopes of the scaled sample are then those of the
// original (forces scale by s^2, masses by s^3, times by s: the critical step sqrt(m/k) grows by s),
// which lets a calibration done at one grain size serve another (Bobillier et al. (2020) scale their grains this way).
#pragma once

#include "dem/core/system.h"

namespace anticrack::dem
{
  /// Scales a sample that has not started running (step_count == 0): positions, radii, masses
  /// (s^3), inertias (s^5), the domain, bonds (radius s, normal and shear stiffness k A s, twist and
  /// bending stiffness s^3; stored loads as forces s^2 and moments s^3), contacts' stored state,
  /// clumps (recomputed from their members; applied forces s^2 at times s), walls (points, areas s^2,
  /// servo gains s^-2) and the fixed time step (s). Throws SetupError for s <= 0 or a running system.
  void scale_sample(DemSystem &system, double factor);
} // namespace anticrack::dem
