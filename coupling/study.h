// `anticrack run` of a study scene (coupling/study_scene.h): every variant of the base scene, and
// what each setting buys for its run time.
//
//   DIR/variants/vNNN/scene.prm   the base scene's copy with the variant's entries set at its end
//                                 (files it names are made absolute: relocatable_scene_text)
//   DIR/variants/vNNN/run/        the variant's run, as `anticrack run scene.prm -o run` writes it
//   DIR/variants/vNNN/variant.json its status, exit code, wall time and the SHA-256 of its scene
//   DIR/study.csv                 one row per variant: the varied values, status, wall time, each
//                                 result and its error
//   DIR/study.json                the same, and per entry's line (coupling/study_scene.h
//                                 line_of_entry) the errors, observed orders and the cheapest
//                                 setting within 5 % and 1 % (coupling/study_analysis.h)
//   DIR/summary.json              the run's record (scene hashes, status, timing, versions) with the
//                                 lines' orders and cheapest settings
//   DIR/work_precision.png, DIR/results.png   scripts/plot_study.py
//
// Every variant's scene is read and checked by its kind's own reader before anything is written
// (a bad value in Study/Entry k/Values is refused naming the variant). Processes: without mpirun
// each variant runs in a process of its own, `Variants side by side` at a time (its wall time is
// measured from its start to its end); under mpirun, variants of kind `dem` are spread over the
// ranks (each rank whole runs, as a campaign's tests), those of other kinds run one after another
// on all ranks (the kind spreads its own work). A failed variant is recorded and the others run;
// the study then exits 1. Ctrl-C stops the running variants (each writes its checkpoint where its
// kind does) and starts no more; --resume skips every variant whose scene is unchanged and whose
// run completed, and resumes the others.
#pragma once

#include "util/run_options.h"

#include <functional>
#include <string>

namespace dealii
{
  class ParameterHandler;
}

namespace anticrack::coupling
{
  /// How the study runs and checks a scene of another kind: the command line's dispatch by kind
  /// (app/scenes.cpp), handed in so that the table of kinds stays in one place.
  struct SceneRunner
  {
    std::function<int(const RunOptions &)> run;
    /// Reads and checks a scene as `anticrack check` does; throws InputError.
    std::function<void(const std::string &scene_file, int threads)> check;
  };

  void declare_study(dealii::ParameterHandler &prm, const std::string &file, bool every_variant);

  /// Reads the study and every variant's scene and prints the variants.
  void check_study_scene(const std::string &file, int threads, const SceneRunner &runner);

  /// Runs the study; returns the exit code (0 every variant completed, 1 one failed, 130
  /// interrupted); throws InputError before anything is written.
  int run_study_scene(const RunOptions &options, const SceneRunner &runner);
} // namespace anticrack::coupling
