// `anticrack run` of a pipeline scene (coupling/pipeline_scene.h): from a DEM weak layer to the FE
// answers in one output folder,
//   DIR/weak_layer/           the calibration scene's run: DIR/weak_layer/campaign/ (the DEM tests),
//                             material.prm (DEM units), material_snow.prm (snow units), calibration.h5,
//                             summary.json, plots (coupling/calibrate.h)
//                             (with Pipeline/Weak layer specimen = profile and pits of several
//                             classes, one such folder per class: DIR/weak_layer_150kgm3_10grains/,
//                             coupling/profile_specimen.h)
//   DIR/<snowpack scene>/     scene.prm (the snowpack scene with the weak layer's Material file set to
//                             material_snow.prm, or to pit_material_snow.prm, its copy at the pit's
//                             grain size, so that the stage can be rerun by hand) and its run
//   DIR/summary.json          the stages, each with the SHA-256 of its inputs, its status, wall
//                             time and headline results
//   DIR/report.md, report.png the calibration and the PST answers (scripts/pipeline_report.py); its
//                             short version is printed at the end.
//
// Stages and their inputs' hashes: the weak layer stage hashes its scene file and the snow units;
// a snowpack stage hashes its scene.prm and the material file it names, so a changed calibration
// changes every later hash. With --resume a stage whose hash and completed status are in
// DIR/summary.json is not run again; a changed input reruns that stage and so every stage after it
// whose inputs it changed (a campaign is itself resumed test by test).
//
// Processes. Without mpirun the campaign runs in worker processes, one per core, and the snowpack
// stages run side by side, each in a worker process of its own (an FE analysis initialises MPI,
// which a process can do once). Under mpirun every stage runs on all ranks, MPI initialised once
// for them all.
#pragma once

#include "util/run_options.h"

#include <string>

namespace dealii
{
  class ParameterHandler;
}

namespace anticrack::coupling
{
  /// Declares a pipeline scene's entries (for `anticrack params`).
  void declare_pipeline(dealii::ParameterHandler &prm, const std::string &file, bool every_variant);

  /// Reads and checks the pipeline and every scene it names, and prints its stages.
  void check_pipeline_scene(const std::string &file, int threads);

  /// Runs the pipeline; returns the exit code (0 every stage completed, 1 a stage failed, 130
  /// interrupted); throws InputError before anything is written.
  int run_pipeline_scene(const RunOptions &options);
} // namespace anticrack::coupling
