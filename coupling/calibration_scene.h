// Scenes of kind `calibration` (`set Scene = calibration`): a DEM campaign (subsections DEM and
// Campaign) and the options of its calibration (subsection Calibration). `anticrack run SCENE -o
// DIR` then does what `anticrack calibrate SCENE -o DIR` does with these options: the campaign
// into DIR/campaign (resumably), the calibrated material, calibration.h5, summary.json and plots.
#pragma once

#include "coupling/calibrate.h"
#include "util/run_options.h"

#include <string>
#include <utility>
#include <vector>

namespace dealii
{
  class ParameterHandler;
}

namespace anticrack::coupling
{
  /// subsection Calibration: the options of `anticrack calibrate`, as scene entries.
  struct CalibrationParameters
  {
    static void declare_parameters(dealii::ParameterHandler &prm);
    /// Fills the options that the subsection holds.
    static void parse_parameters(dealii::ParameterHandler &prm, CalibrateOptions &options);
  };

  /// Declares the entries of a calibration scene: the DEM campaign's (with its variants, those of
  /// `file` if given, else the defaults; every variant with `every_variant`) and Calibration's.
  void declare_calibration_scene(dealii::ParameterHandler &prm, const std::string &file, bool every_variant);

  /// Reads and checks the scene (DEM, Campaign, Calibration), with `overrides` (entry path, value)
  /// set after the file's own entries (dem::read_scene); returns the calibration's options with
  /// input = `file` (output directory and the run's options are the caller's). Throws InputError.
  CalibrateOptions read_calibration_scene(const std::string &file,
                                          const std::vector<std::pair<std::string, std::string>> &overrides = {});

  /// Reads and checks the scene (DEM, Campaign, Calibration) and prints what a run would do.
  void check_calibration_scene(const std::string &file, int threads);

  /// `anticrack run` of a calibration scene; returns the exit code.
  int run_calibration_scene(const RunOptions &options);
} // namespace anticrack::coupling
