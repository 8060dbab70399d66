// The names of the history.h5 columns that are read back: by the run's failure analysis
// (dem/scene/failure_analysis.cpp), by the campaign (dem/campaign/campaign.cpp, which copies each
// test's history into campaign.h5 /tests/<id>/history) and by the calibration
// (params/campaign_data.cpp). The run declares them (dem/scene/dem_run.cpp, with units and
// descriptions); a column only the run writes keeps its name there.
#pragma once

#include <string>

namespace anticrack::dem::history_column
{
  inline constexpr const char *time = "time";
  inline constexpr const char *step = "step";
  inline constexpr const char *base_normal_stress = "base_normal_stress";
  inline constexpr const char *base_shear_stress = "base_shear_stress";
  inline constexpr const char *normal_strain = "normal_strain"; ///< -u_z / H0 of the clump
  inline constexpr const char *shear_strain = "shear_strain";   ///< u_x / H0 of the clump
  inline constexpr const char *von_mises_stress = "von_mises_stress";
  inline constexpr const char *inertial_number = "inertial_number";

  /// "clump_displacement_x", ... for axis 'x', 'y' or 'z'.
  inline std::string clump_displacement(char axis) { return std::string("clump_displacement_") + axis; }
  /// "clump_velocity_x", ...
  inline std::string clump_velocity(char axis) { return std::string("clump_velocity_") + axis; }
  /// "love_stress_xx", ... for a component "xx", "yy", "zz", "xy", "xz" or "yz" (tension positive).
  inline std::string love_stress(const std::string &component) { return "love_stress_" + component; }
} // namespace anticrack::dem::history_column
