// The calibration's uncertainty carried to the PST answers (critical cut length, propagation speed,
// touchdown distance) by first-order sensitivities from FE runs.
//
// The uncertain parameters, in snow units, and their covariance Σ:
//   - p0, β, M: the covariance of the surface's fit (delta method, params/envelope_fit.h), p0's
//     rows and columns scaled by the stress scale S (coupling/snow_units.h);
//   - E: the standard error of its mean over the realizations, sd/√n, from the loading tests' elastic
//     part, independent of the surface and of the softening;
//   - ξ, R and the lock-up strain: the covariance of their means over the realizations, from the
//     paired per-realization values (one compaction curve gives all three; params::covariance_of_means),
//     independent of the surface and of E;
//   - μ, the failed layer's friction: the standard error of its mean over the realizations' friction
//     tests (params/friction_calibration.h), independent of the others (where the campaign has them).
// For each snowpack scene the FE runs once more per parameter i with θ_i raised by one standard
// error h_i = √Σ_ii, everything else as calibrated. The sensitivity of an answer y is
// g_i = (y_i − y_0)/h_i, its variance g^T Σ g, its interval y_0 ± z σ_y with z the normal quantile of
// the material file's confidence. The dominant parameter is the one whose standard error moves the
// answer most, |g_i| h_i. Each parameter's share of the variance, g_i (Σ g)_i / g^T Σ g, is reported
// beside it (the shares add up to 1; p0, β and M are correlated in the fit, so a share can be small or
// negative where a correlated parameter's change cancels part of its own). Linearisation: one-sided differences of one standard error, justified where y varies
// smoothly over ±1 standard error; a perturbed run whose answer is missing (the crack did not run,
// or arrested where the base run reached the end) makes the answer's interval "not linear", which
// the report says instead of a number; so does an interval that reaches 0 or below, which a
// positive answer (a length, a speed) cannot (pit 65798's own layer: one standard error of p0 took its
// speed from 23 to 4.5 m/s, and the first-order interval read −45 to 92 m/s). The mesh resolves y to about one element length: a
// sensitivity below (element length)/h_i is not resolved, and the report gives the element length.
#pragma once

#include "fem/material/material_file.h"

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>
#include <functional>
#include <vector>

namespace anticrack::coupling
{
  /// The PST answers of a snowpack stage that the pipeline reports, with intervals: the key in the
  /// FE's summary.json results, a label and the unit.
  struct PstAnswer
  {
    const char *key, *label, *unit;
  };
  const std::vector<PstAnswer> &pst_answers();

  struct UncertainParameters
  {
    std::vector<std::string> names;   ///< p0, beta, M, E, xi, R, lock_up_strain, mu
    /// Where each is in a material file (subsection Material, or Material/Collapse).
    std::vector<std::function<double &(fem::MaterialFile &)>> value_in;
    Eigen::VectorXd value;            ///< calibrated, snow units
    Eigen::MatrixXd covariance;       ///< Σ, snow units
    double confidence = 0.95;
  };

  /// From a pipeline's weak-layer folder (summary.json, material.prm, material_snow.prm). Parameters
  /// without a spread (one realization) are left out.
  UncertainParameters uncertain_parameters(const std::filesystem::path &weak_layer_directory);

  /// The parameters of `u` named in `names` (in u's order), with their covariance block.
  UncertainParameters restricted_to(const UncertainParameters &u, const std::vector<std::string> &names);

  /// `material` with parameter k raised by one standard error.
  fem::MaterialFile perturbed_material(const fem::MaterialFile &material, const UncertainParameters &u, std::size_t k);

  /// The answers' intervals of one scene: `base` and `perturbed[k]` are the results of its
  /// summary.json (base run and run k), `element_length` [m] its mesh's.
  nlohmann::ordered_json linearised_intervals(const UncertainParameters &u, const nlohmann::ordered_json &base,
                                              const std::vector<nlohmann::ordered_json> &perturbed,
                                              double element_length);

  /// An elastic stage's critical cut with two independent sources of spread: the fracture energy
  /// G_c's interval, which the stage maps exactly through its own G(a) (`mapped`: results'
  /// critical_cut_length_interval), and the linearised interval of the parameters rerun for it
  /// (`linearised`: linearised_intervals' answer for the critical cut, e.g. from E). Each side's
  /// half-width is the root of the sum of the squares of the two (independent: G_c from the
  /// compaction curves, E from the elastic part of the loading tests).
  nlohmann::ordered_json combined_critical_cut_interval(const nlohmann::ordered_json &mapped,
                                                        const nlohmann::ordered_json &linearised, double value);
} // namespace anticrack::coupling
