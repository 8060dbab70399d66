// The table of failure points of campaign.h5 (/failure_points, and /quasi_static_check for the
// slower reference runs): one row per test, one dataset per column. This header is the one list of
// its columns — name, unit, description and the member of FailurePointRow it holds — used by the
// writer (dem/campaign/campaign.cpp) and by the calibration's reader (params/campaign_data.cpp), so
// the two cannot drift apart. Header-only on purpose: params/ reads the table without linking the
// scene library (and with it deal.II). Layout of the whole file: dem/campaign/campaign.h, docs/lab.md.
#pragma once

#include <array>
#include <limits>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace anticrack::dem
{
  /// The group of campaign.h5 that holds the failure points of the campaign proper.
  inline constexpr const char *failure_points_group = "failure_points";
  /// The group of the displacement-controlled compaction tests (one per realization), same columns.
  inline constexpr const char *compaction_tests_group = "compaction_tests";
  /// The group of the friction tests (simple shear of the collapsed layer, one per realization).
  inline constexpr const char *friction_tests_group = "friction_tests";

  /// One row of /failure_points: a test at one loading angle of one realization of one
  /// microstructure. Stresses tension positive except sigma and p (compression positive).
  struct FailurePointRow
  {
    static constexpr double nan = std::numeric_limits<double>::quiet_NaN();
    std::string test;               ///< m<microstructure>_r<realization>_psi<angle>
    std::string status;             ///< completed, failed, interrupted or missing
    double microstructure = nan, realization = nan, loading_angle_deg = nan;
    double sigma = nan, tau = nan, p = nan, q = nan;
    std::array<double, 9> love_stress{{nan, nan, nan, nan, nan, nan, nan, nan, nan}}; ///< row-major
    double failure_time = nan, failure_step = nan;
    double flow_angle_deg = nan, secant_modulus = nan, softening_ratio = nan, peak_q = nan;
    double max_inertial_number = nan;
    double solid_fraction = nan, coordination = nan, bonds = nan;
    double specimen_height = nan, layer_thickness = nan;
    double particle_diameter = nan;
    double steady_shear_stress = nan, steady_normal_stress = nan, steady_stress_ratio = nan;
  };

  /// One column of the table; exactly one of the three members is set (a text per test, a number
  /// per test, or the 3 x 3 Love-Weber tensor per test, written as [test][i][j]).
  struct FailurePointColumn
  {
    const char *name;
    const char *unit;         ///< "" for texts
    const char *description;
    std::string FailurePointRow::*text = nullptr;
    double FailurePointRow::*number = nullptr;
    std::array<double, 9> FailurePointRow::*tensor = nullptr;
  };

  /// Every column, in the order of the file.
  inline const std::vector<FailurePointColumn> &failure_point_columns()
  {
    using R = FailurePointRow;
    auto text = [](const char *name, const char *description, std::string R::*member) {
      return FailurePointColumn{name, "", description, member, nullptr, nullptr};
    };
    auto number = [](const char *name, const char *unit, const char *description, double R::*member) {
      return FailurePointColumn{name, unit, description, nullptr, member, nullptr};
    };
    static const std::vector<FailurePointColumn> columns = {
      text("test", "test id: m<microstructure>_r<realization>_psi<angle>", &R::test),
      text("status", "completed, failed, interrupted or missing", &R::status),
      number("microstructure", "-", "index into the root attribute `microstructures` (0 = the scene's own sample)",
             &R::microstructure),
      number("realization", "-", "realization r, sample seed = DEM/Random seed + r", &R::realization),
      number("loading_angle_deg", "deg", "psi, clump force direction (sin psi, 0, -cos psi)", &R::loading_angle_deg),
      number("sigma", "Pa", "base normal stress at failure, compression positive (Ritter et al. 2020)", &R::sigma),
      number("tau", "Pa", "base shear stress at failure (along +x)", &R::tau),
      number("p", "Pa", "mean pressure of the Love-Weber stress at failure, compression positive", &R::p),
      number("q", "Pa", "von Mises stress of the Love-Weber stress at failure", &R::q),
      FailurePointColumn{"love_stress", "Pa", "full Love-Weber stress tensor at failure, tension positive, [test][i][j]",
                         nullptr, nullptr, &R::love_stress},
      number("failure_time", "s", "time of the failure point", &R::failure_time),
      number("failure_step", "-", "step of the failure point", &R::failure_step),
      number("flow_angle_deg", "deg",
             "plastic flow angle atan2(du_z, du_x) of the clump just after failure (Ritter et al. 2020)",
             &R::flow_angle_deg),
      number("secant_modulus", "Pa",
             "secant modulus to 70 % of the peak base normal stress on the layer strain u/h (Bobillier et al. 2020)",
             &R::secant_modulus),
      number("softening_ratio", "-",
             "residual (mean of the last half of the post-peak samples) / peak base normal stress (Bobillier et al. "
             "2020)", &R::softening_ratio),
      number("peak_q", "Pa", "largest von Mises stress of the whole test", &R::peak_q),
      number("max_inertial_number", "-",
             "largest inertial number between half the failure q and failure (quasi-static: < 1e-4, Ritter et al. "
             "2020)",
             &R::max_inertial_number),
      number("solid_fraction", "-", "solid volume fraction of the generated sample", &R::solid_fraction),
      number("coordination", "-", "mean coordination number of the generated sample", &R::coordination),
      number("bonds", "-", "parallel bonds of the specimen", &R::bonds),
      number("specimen_height", "m", "initial height H0 of the tested specimen (strains in the histories are u / H0)",
             &R::specimen_height),
      number("layer_thickness", "m", "deformable layer between the fixed base and the clump (centre to centre), h",
             &R::layer_thickness),
      number("particle_diameter", "m",
             "mean diameter of the specimen's spheres (the grain size the snow units scale lengths by)",
             &R::particle_diameter),
      number("steady_shear_stress", "Pa",
             "friction tests: the base's mean shear stress over the second half of the shear strain (NaN for the "
             "other tests)", &R::steady_shear_stress),
      number("steady_normal_stress", "Pa", "friction tests: the base's mean compressive normal stress over the same",
             &R::steady_normal_stress),
      number("steady_stress_ratio", "-",
             "friction tests: steady shear over normal stress, the collapsed layer's friction coefficient",
             &R::steady_stress_ratio)};
    return columns;
  }

  /// The column that holds `member` (a text, a number or the tensor of FailurePointRow).
  template <class Member>
  const FailurePointColumn &failure_point_column(Member FailurePointRow::*member)
  {
    for (const FailurePointColumn &c : failure_point_columns())
    {
      if constexpr (std::is_same_v<Member, std::string>)
      {
        if (c.text == member)
          return c;
      }
      else if constexpr (std::is_same_v<Member, double>)
      {
        if (c.number == member)
          return c;
      }
      else if (c.tensor == member)
        return c;
    }
    throw std::logic_error("failure_point_column: a member of FailurePointRow without a column");
  }
} // namespace anticrack::dem
