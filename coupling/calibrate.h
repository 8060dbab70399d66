// `anticrack calibrate`: a campaign file (or a scene whose campaign is run first, resumably) in,
// the calibrated continuum out (params/): calibration.h5, material file(s), summary.json and the
// plots of scripts/plot_calibration.py.
#pragma once

#include "coupling/snow_units.h"

#include <cstdint>
#include <optional>
#include <string>

namespace anticrack::coupling
{
  struct CalibrateOptions
  {
    std::string input;            ///< campaign.h5, or a scene (.prm) with a Campaign subsection
    std::string output_directory;
    double confidence = 0.95;
    double poisson_ratio = -2;    ///< in (-1, 0.5): given ν (E from the axial modulus alone); else measured
    int bootstrap_samples = 1000;
    std::uint64_t seed = 1;
    bool plots = true;
    bool overwrite = false;       ///< replace an earlier calibration in the directory
    int threads = -1;             ///< for a scene's campaign
    std::string command_line;
    /// Also write every material in snow units (material_snow.prm, material_m<k>_snow.prm).
    std::optional<SnowUnits> snow;
  };

  /// The material file name of microstructure m of `count`: material.prm for one microstructure,
  /// material_m<k>.prm otherwise; `snow`: the file in snow units (material_snow.prm, ...).
  std::string material_file_name(std::size_t m, std::size_t count, bool snow = false);

  /// Returns the exit code; throws InputError (bad options, degenerate data) before writing.
  int run_calibration(const CalibrateOptions &options);

  /// params::calibrate with the path plane fitted through the FE material point's peaks: refits
  /// with CalibrationOptions::path_peak_factors from the replay of the last fit until they settle.
  /// Throws params::CalibrationError if they do not in 40 (relaxed) refits.
  params::Calibration calibrate_to_the_fe_points_peaks(const params::CampaignData &campaign,
                                                       params::CalibrationOptions options);
} // namespace anticrack::coupling
