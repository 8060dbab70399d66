// The energy release rate analysis: G(a) of a saw cut in an elastic snowpack, the cut length at
// which G reaches G_c, energy_release_rate.h5 and the fields of the longest cut.
#pragma once

#include "fem/analysis/snowpack_run.h"

namespace anticrack::fem
{
  /// Runs the analysis; returns the "results" of summary.json.
  template <int dim>
  Json run_energy_release_rate(const SnowpackScene &scene, const SnowpackRunOptions &options, MPI_Comm comm);
} // namespace anticrack::fem
