// The quasi-static PST: gravity equilibrium, then saw steps with Newton until equilibrium is lost or
// the crack leads the saw; series.h5 (one row per converged saw step) and the fields.
#pragma once

#include "fem/analysis/snowpack_run.h"

namespace anticrack::fem
{
  /// Runs the analysis; returns the "results" of summary.json.
  template <int dim>
  Json run_quasi_static_pst(const SnowpackScene &scene, const SnowpackRunOptions &options, MPI_Comm comm);
} // namespace anticrack::fem
