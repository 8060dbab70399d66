// The dynamic PST: gravity equilibrium, then the saw, the crack and its arrest in time by explicit
// central differences; series.h5, the fields, and checkpoints from which a run resumes bit for bit.
#pragma once

#include "fem/analysis/snowpack_run.h"

namespace anticrack::fem
{
  /// Runs (or, with options.resume, continues) the analysis; returns the "results" of summary.json.
  template <int dim>
  Json run_dynamic_pst(const SnowpackScene &scene, const SnowpackRunOptions &options, MPI_Comm comm);
} // namespace anticrack::fem
