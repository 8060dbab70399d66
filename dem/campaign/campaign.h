// Virtual-laboratory campaigns (Ritter et al. 2020): the scene's mixed-mode test at every loading angle x
// realization x microstructure of its Campaign subsection, each test a complete run of its own.
//
// Layout of the output directory:
//   tests/<id>/summary.json, history.h5   every test, as `anticrack run` writes them (resumable)
//   campaign.h5                           every test's history under /tests/<id>/history, the table
//                                         of failure points /failure_points (one row per test, in
//                                         test order; columns in dem/campaign/campaign_file.h) and
//                                         the quasi-static check /quasi_static_check
//   summary.json                          the campaign: what ran, failure points, the quasi-static
//                                         check against slower reference runs, wall time
// Test ids read m<microstructure>_r<realization>_psi<angle>, e.g. m0_r2_psi067.5; a quasi-static
// reference run of that test is m0_r2_psi067.5_slow4.
//
// Without mpirun, one worker process per core pulls the tests from one queue, the longest first
// (util/worker_processes.h SharedCounter). Under mpirun every rank runs whole tests (threads inside
// each test); the tests are dealt out in
// contiguous blocks so that a rank builds few samples (the sample of a microstructure and
// realization is generated once per rank and copied for every angle). A test does not depend on
// the rank or thread count that runs it (the engine is bit-reproducible), so a campaign on any
// number of ranks writes the same failure points as a serial one. Rank 0 assembles campaign.h5 and
// summary.json once every rank has finished.
#pragma once

#include "dem/scene/dem_run.h"

#include <iosfwd>

namespace anticrack::dem
{
  struct SceneParameters;

  /// Runs the campaign of `scene` (Campaign/Loading angles not empty) into options.output_directory;
  /// returns the exit code (numerical failure if any test failed). Throws InputError for problems
  /// found before anything is written.
  int run_campaign(const SceneParameters &scene, const RunOptions &options);

  /// What `anticrack check` adds for a campaign: the tests it would run. Validates the
  /// microstructure variants (throws InputError).
  void describe_campaign(std::ostream &out, const SceneParameters &scene);
} // namespace anticrack::dem
