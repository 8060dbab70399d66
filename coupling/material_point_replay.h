// The DEM tests repeated by the FE material point: the calibrated material, as the FE solver reads
// it from its material file, is driven along every DEM test's own path and fails where the load it
// carries peaks. The answer is the FE's (its elasticity, yield function and return mapping,
// fem/material/cohesive_cam_clay.h), not the calibration's formulas, so it checks that the surface
// means the same on both sides of the hand-off.
//
// The path (params/stress_path.h): the layer-plane traction σ_zz = −λ σ̂, σ_xz = λ τ̂ grows along the
// direction (σ̂, τ̂) of the DEM's failure point, with σ_yz = 0; laterally periodic specimens keep
// ε_xx = ε_yy = ε_xy = 0, open-sided ones σ_xx = σ_yy = σ_xy = 0. The strain that holds this mixed
// control is solved by Newton with the material's own tangent. The first yield λ_y, the largest λ at
// which update_stress() is still elastic, by bisection to 1e-12 relative; from it, load steps with
// Newton on the controlled strains and the consistent tangent to the peak λ_f, the failure (to 1e-10
// relative). Under the collapse law every plastic volume change softens, but the peak need not be
// the first yield: in confined compression the stress point slides along the shrinking surface
// towards the hydrostatic axis and the layer-normal stress rises, by 22 % for a surface of M = 0.93
// (docs/fem.md "The DEM specimen repeated"); in shear and tension, and for M ≈ 2, it does not.
// The calibration's path fit therefore fits the first yield to the DEM's failure divided by
// λ_f/λ_y (coupling/calibrate.cpp iterates the two).
// The elastic stiffnesses are those of the same driver at a small load: the normal one at ψ = 0
// (constrained modulus under periodic sides, Young's modulus under open ones) and the shear one
// τ/γ at ψ = 90° (γ = 2 ε_xz = u_x/h, as the DEM measures it).
#pragma once

#include "fem/material/material_file.h"
#include "params/calibration.h"

#include <nlohmann/json.hpp>

#include <map>
#include <string>
#include <vector>

namespace anticrack::coupling
{
  /// The tests of one loading angle: the DEM's mean failure point against the FE's along its ray.
  struct ReplayedAngle
  {
    double loading_angle_deg = 0;
    int tests = 0;                      ///< realizations at this angle
    double dem_sigma = 0, dem_tau = 0;  ///< mean base stresses at failure (|τ|) [Pa]
    double fe_sigma = 0, fe_tau = 0;    ///< the FE point's failure (its peak) on the same ray [Pa]
    double peak_over_first_yield = 1;   ///< the peak's load over the first yield's
    double fe_lateral_stress_ratio = 0; ///< σ_xx/σ_zz of the FE point at its first yield (0 at σ = 0)
    double fe_lateral_stress_ratio_at_peak = 0; ///< and at its peak (plastic flow moves it)
    /// ln(r_FE / r_DEM): the relative radial error, the fit's own residual measure.
    double relative_error = 0;
  };

  struct MaterialPointReplay
  {
    bool laterally_confined = false;
    std::vector<ReplayedAngle> angles;  ///< ascending loading angle
    std::vector<double> test_errors;    ///< ln(r_FE / r_DEM) per test, in the calibration's order
    /// The peak's load over the first yield's, per test id: what the calibration's path fit divides
    /// the DEM's failure points by (params::CalibrationOptions::path_peak_factors).
    std::map<std::string, double> peak_over_first_yield;
    double fit_rmse = 0;                ///< relative RMSE of the material surface's fit
    double dem_normal_stiffness = 0, fe_normal_stiffness = 0; ///< [Pa]
    double dem_shear_stiffness = 0, fe_shear_stiffness = 0;   ///< [Pa]

    /// The largest |relative_error| over the angles.
    [[nodiscard]] double largest_angle_error() const;
  };

  /// Replays the tests of microstructure calibration `c` on `material` (its material file as read
  /// back, fem::read_material_file_text). Throws fem::ReturnMappingError if the material point fails
  /// to update, std::runtime_error if no failure is found below 1e3 times the DEM's failure stress.
  MaterialPointReplay replay_tests(const params::MicrostructureCalibration &c, const fem::ContinuumMaterial &material);

  /// The replay for summary.json.
  nlohmann::ordered_json replay_json(const MaterialPointReplay &replay);
} // namespace anticrack::coupling
