// Plastic flow of the DEM samples against the cohesive Cam-Clay surface in the mixed-mode plane
// (Ritter et al. 2020, Results "Yield surface and plastic flow" and Methods "Plastic flow in the normalized
// stress space", Eqs. 4-7 and 12-19).
//
// Conventions of the mixed-mode plane:
//  * sigma is the normal stress at the base, compression positive; tau the shear stress, tau >= 0
//    for our loading.
//  * The clump force is F (sin psi, 0, -cos psi): the loading angle psi = 0 is pure compression,
//    pi/2 pure shear, pi pure tension, and the loading ray in (sigma, tau) is r (cos psi, sin psi),
//    r > 0; mu = tan psi (Ritter et al. 2020, Eq. 12 without star).
//  * The flow angle theta = atan2(du_z, du_x) is the direction of the clump displacement after
//    failure (u_z up, so theta > 0 is expansion and theta < 0 compaction); Ritter et al. (2020) write
//    theta = arctan(u_z/u_x).
//
// The surface is Eq. 1 of Ritter et al. (2020), tau^2 (1 + 2 beta) + M^2 (sigma - sigma_0)(sigma + beta sigma_0) = 0,
// an ellipse with tips at sigma_0 (compression) and -beta sigma_0 (tension) and its apex at
// sigma = (1 - beta) sigma_0/2. In the normalised coordinates of Eqs. 5-6 it is the unit circle
// sigma*^2 + tau*^2 = 1 (Eq. 4), and the loading ray of angle psi meets it at the normalised loading
// angle psi* = atan2(tau*, sigma*).
//
// Associative flow: the plastic strain increment (-du_z, du_x)/h, conjugate to (sigma, tau), is
// normal to the surface, so tan theta = d tau/d sigma along the envelope; in normalised space the
// normal of the unit circle at psi* gives theta* = psi* - pi/2 (Eq. 16), and the raw and normalised
// flow angles are related by tan theta* = (sqrt(1 + 2 beta)/M) tan theta (Eqs. 17-18).
//
// Angles are in radians throughout; only quantities whose names end in _deg are in degrees.
#pragma once

#include "params/regression.h"
#include "params/yield_envelopes.h"

#include <vector>

namespace anticrack::params
{
  // The surface in the mixed-mode plane: CamClaySurface of yield_envelopes.h, p0 = sigma_0.

  /// A point in the normalised stress plane of Ritter et al. (2020), Eqs. 5-6.
  struct NormalisedStress
  {
    double sigma = 0;  ///< sigma*
    double tau = 0;    ///< tau*
  };

  /// Eqs. 5-6 of Ritter et al. (2020): sigma* = (2 sigma - (1 - beta) p0)/((1 + beta) p0),
  /// tau* = 2 tau sqrt(1 + 2 beta)/(M (1 + beta) p0); points of the surface satisfy
  /// sigma*^2 + tau*^2 = 1 (Eq. 4). Throws CalibrationError for invalid parameters.
  NormalisedStress normalise(double sigma, double tau, const CamClaySurface &parameters);

  /// The point (normal = sigma, shear = tau; StressPoint of yield_envelopes.h) where the loading ray
  /// r (cos psi, sin psi), r > 0, meets the surface, for psi in [0, pi]. For beta > 0 the origin is
  /// inside the surface and the point is unique; for beta = 0 the origin is the tensile tip, and every
  /// ray with psi >= pi/2 meets the surface only there.
  /// Throws CalibrationError for psi outside [0, pi] or invalid parameters.
  StressPoint surface_point_on_loading_ray(double psi, const CamClaySurface &parameters);

  /// The normalised loading angle psi* = atan2(tau*, sigma*) in [0, pi] of the point where the
  /// loading ray of angle psi in [0, pi] meets the surface (the intersection is computed, so that
  /// psi* > pi/2 beyond the transition angle keeps its quadrant, which Eq. 14's
  /// sigma* = 1/sqrt(1 + mu*^2) loses). psi = 0 gives 0, psi = pi gives pi, the ray through the apex
  /// gives pi/2. Throws CalibrationError for psi outside [0, pi] or invalid parameters.
  double normalised_loading_angle(double psi, const CamClaySurface &parameters);

  /// mu* = tan psi* from mu = tan psi by Ritter et al. (2020), Eq. 19,
  /// mu* = (mu/M) sqrt(1 + 2 beta) (1 + (1 - beta)/(1 + beta) sqrt(1 + mu*^2)), in closed form, on
  /// the branch sigma* > 0 (Eq. 14), i.e. loading angles below the transition angle of Eq. 7.
  /// With k = (mu/M) sqrt(1 + 2 beta) and d = (1 - beta)/(1 + beta) the squared equation is the
  /// quadratic (1 - k^2 d^2) mu*^2 - 2 k mu* + k^2 (1 - d^2) = 0, whose roots are
  /// k (1 +- d S)/(1 - k^2 d^2), S = sqrt(1 + k^2 (1 - d^2)); the root returned is the one that
  /// satisfies the unsquared equation with sigma* > 0 and tau* >= 0. Throws CalibrationError if the
  /// ray with slope mu meets the surface at sigma* <= 0 (at or beyond the transition angle), or for
  /// invalid parameters.
  double normalised_loading_slope_eq19(double mu, const CamClaySurface &parameters);

  /// Eq. 18 of Ritter et al. (2020), theta* = arctan((sqrt(1 + 2 beta)/M) tan theta), evaluated as
  /// atan2(sqrt(1 + 2 beta) sin theta, M cos theta) so that the quadrant is kept (theta near
  /// -pi/2, compaction under pure compression, stays near -pi/2). Throws CalibrationError for invalid
  /// parameters.
  double normalised_flow_angle(double theta, const CamClaySurface &parameters);

  /// Inverse of normalised_flow_angle: theta = atan2(M sin theta*, sqrt(1 + 2 beta) cos theta*).
  double flow_angle_from_normalised(double theta_star, const CamClaySurface &parameters);

  /// Associative flow in normalised space, Eq. 16 of Ritter et al. (2020): theta* = psi* - pi/2.
  double associative_normalised_flow_angle(double psi_star);

  /// The raw flow angle theta that associative flow predicts for the loading angle psi in [0, pi]:
  /// psi -> psi* (intersection with the surface), Eq. 16, then the inverse of Eq. 18. Equals
  /// atan2 of the surface slope d tau/d sigma at the failure point, in (-pi/2, pi/2) for tau > 0.
  double associative_flow_angle(double psi, const CamClaySurface &parameters);

  /// Eq. 7 of Ritter et al. (2020): the loading angle psi+- of the ray through the apex of the surface, where
  /// associative flow changes from compaction to expansion,
  /// tan psi+- = M (1 + beta)/((1 - beta) sqrt(1 + 2 beta)), in (0, pi): arctan M for beta = 0,
  /// pi/2 for beta = 1, obtuse for beta > 1. Throws CalibrationError for invalid parameters.
  double transition_loading_angle(const CamClaySurface &parameters);

  /// How associative measured flow is, in the normalised plane of Ritter et al. (2020), Fig. 5B.
  struct AssociativityMeasure
  {
    /// d_i = theta*_i - (psi*_i - pi/2), wrapped to (-pi, pi] (directions, not numbers) [rad].
    std::vector<double> deviation;
    double rms_deviation = 0;          ///< sqrt(mean d^2) [rad]
    double rms_deviation_deg = 0;
    double max_abs_deviation = 0;      ///< max |d| [rad]
    double max_abs_deviation_deg = 0;
    double mean_deviation = 0;         ///< mean d [rad]: a systematic offset from normality
    double mean_deviation_deg = 0;
    Interval mean_deviation_ci;        ///< t-interval of mean d [rad]
    /// Least squares theta* = a psi* + b; associative flow is a = 1, b = -pi/2.
    LinearFit line;
    /// 1 lies inside the interval of a (up to round-off, so that exact data count as consistent).
    bool slope_consistent_with_associative = false;
    /// -pi/2 lies inside the interval of b (up to round-off).
    bool intercept_consistent_with_associative = false;
    /// 1 - sum d^2 / sum (theta* - mean theta*)^2: the share of the variation of theta* that the
    /// associative rule explains (1 for exact normality, can be negative). NaN if theta* is
    /// constant.
    double r_squared_associative = 0;
    double confidence = 0.95;
    int n = 0;
  };

  /// Compares normalised flow angles theta*_i with the associative prediction psi*_i - pi/2
  /// (Ritter et al. 2020, Eq. 16). Throws CalibrationError for fewer than 3 points, sizes that differ, non-finite
  /// values, all psi* equal, or a confidence outside (0, 1).
  AssociativityMeasure measure_associativity(const std::vector<double> &psi_star,
                                             const std::vector<double> &theta_star,
                                             double confidence = 0.95);

  /// The loading angle where measured flow changes from compaction (theta < 0) to expansion
  /// (theta > 0), to compare with Eq. 7 (Ritter et al. (2020) report ~67.5 deg). Flow angles are averaged per
  /// distinct loading angle (angles within 1e-9 rad are the same), sorted by psi, and the first change
  /// from negative to positive mean is interpolated linearly; a run of means that are exactly 0
  /// between them gives the middle of the run. Throws CalibrationError if the sizes differ, a value is
  /// not finite, fewer than 2 distinct angles are given, or the mean flow never changes from
  /// compaction to expansion (all compaction, all expansion, or only expansion to compaction).
  double observed_transition_angle(const std::vector<double> &psi, const std::vector<double> &theta);
} // namespace anticrack::params
