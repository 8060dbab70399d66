// A DEM test's stress path as the FE material point sees it: how a failure point measured as base
// stresses (σ, τ) becomes a point of the FE's invariant plane (p, q) with the same meaning.
//
// The DEM test applies a traction to the layer plane, the base stresses σ (normal, compression
// positive) and τ (shear along x), along its loading direction ψ. The FE material point driven along
// the same path carries the same layer-plane traction, σ_zz = −σ and σ_xz = τ (tension-positive
// tensor, z normal to the layer), under the test's lateral boundary condition:
//   laterally periodic specimen (Ritter et al. 2020): no lateral strain, ε_xx = ε_yy = ε_xy = 0, so
//     the elasticity sets σ_xx = σ_yy = −k σ with the lateral stress ratio k = ν/(1 − ν);
//   open sides (Bobillier et al. 2020): free lateral faces, σ_xx = σ_yy = 0, k = 0.
// Its invariants are then (docs/physics.md §0: p = −tr σ/3, q = sqrt(3/2 s:s))
//   p = (1 + 2k) σ / 3,   q = sqrt((1 − k)² σ² + 3 τ²).                                   (P1)
// The cohesive Cam-Clay point is elastic until its first yield, at the (p, q) of (P1) evaluated at the
// (σ, τ) where its surface crosses the ray of fixed τ/σ. Its failure, the peak of the load it carries,
// lies at or beyond: under the collapse law every plastic volume change softens, yet in confined
// compression the stress point can slide along the shrinking surface to a larger load (22 % for
// M = 0.93; coupling/material_point_replay.h). The calibration therefore maps each DEM failure
// divided by that peak-over-first-yield factor (CalibrationOptions::path_peak_factors, iterated by
// coupling/calibrate.h), so that the fitted first yield times the factor is the DEM's failure. (P1) is homogeneous of
// degree one in (σ, τ): a ray of the (σ, τ) plane is a ray of the (p, q) plane, and the relative radial
// residual ln(r/R) of a failure point is the same in both. A surface fitted to the mapped points by
// the relative radial residuals of params/envelope_fit.h is therefore exactly the surface whose FE
// material point, driven along every test's path, fails (peaks) closest to the DEM's (σ, τ) in that
// measure.
//
// Why the path and not the Love–Weber lateral stresses: the FE point is what must fail where the DEM
// failed, and its lateral stresses are those of its elasticity, k σ, not the DEM's. The Love–Weber
// lateral stresses at failure are recorded beside the path's (lateral_stress_ratio_at_failure) to
// show how close the two are; for the layer-plane traction the base stresses are taken
// (docs/physics.md §1.5: the specimen's Love–Weber shear of a ballistic layer is short of the base
// shear by its bond couples).
//
// What an isotropic invariant surface cannot do. Under open sides a compression test (ψ = 0) maps to
// q = 3p, a shear test (ψ = 90°) to p = 0, q = √3 τ, a tension test (ψ = 180°) to q = −3p. A convex
// surface through the two uniaxial points contains the chord between them, so its shear point must
// lie at or above the chord's q at p = 0. A layer whose shear strength is below that (the ballistic
// deposit: uniaxial tension 0.87 kPa, compression 1.5 kPa, shear 0.27 kPa) has no isotropic convex
// surface that fails where it fails: chord_shear_deficit() measures by how much.
#pragma once

#include "params/yield_envelopes.h"

namespace anticrack::params
{
  /// The lateral boundary condition of a DEM test and the FE elasticity that holds it.
  struct TestPath
  {
    bool laterally_confined = false; ///< periodic sides: no lateral strain
    double poisson_ratio = 0;        ///< ν of the FE elasticity (used when confined)

    /// k = σ_xx/σ_zz = σ_yy/σ_zz of the FE point: ν/(1 − ν) confined, 0 open.
    [[nodiscard]] double lateral_stress_ratio() const;

    /// (p, q) of the FE point carrying the layer-plane traction (σ, τ), Eq. (P1) [Pa].
    [[nodiscard]] StressPoint invariants(double sigma, double tau) const;
  };

  /// The least ratio of peak shear strength to half the compressive–tensile range that the image of
  /// a cohesive Cam-Clay surface of the invariants has in the (σ, τ) plane on `path`: (1 − k)/√3.
  ///
  /// By (P1) the surface (1 + 2β) q² + M² (p + β p0)(p − p0) = 0 maps to the (σ, τ) ellipse
  ///   (1 + 2β)[(1 − k)² σ² + 3 τ²] + M² (cσ + β p0)(cσ − p0) = 0,   c = (1 + 2k)/3,
  /// symmetric about the σ axis. For an ellipse A σ² + B σ + C + D τ² = 0 the τ semi-axis over the
  /// σ semi-axis is sqrt(A/D); here A/D = (1 − k)²/3 + M² c²/(3 (1 + 2β)) > (1 − k)²/3, because a
  /// uniaxial load on the path already carries q = (1 − k) σ. The (σ, τ) cohesive Cam-Clay
  /// ellipse (1 + 2β') τ² + M'² (σ + β' σ0)(σ − σ0) = 0 has the ratio M'/sqrt(1 + 2β'). Above
  /// (1 − k)/√3 there is exactly one (p0, β, M) whose image it is (solving the three coefficients),
  /// so the two fits are the same least-squares problem; at or below it none is, and the fit on the
  /// paths runs off to a degenerate surface.
  [[nodiscard]] double least_cam_clay_shear_ratio(const TestPath &path);

  /// Convexity test of three failure points of the (σ, τ) plane on `path`: compression (σ_c > 0 at
  /// τ = 0), shear (τ_s at σ = 0) and tension (σ_t < 0 at τ = 0). Returns q_chord(p = 0) − √3 τ_s of
  /// the mapped points over q_chord (> 0: no convex invariant surface reaches the shear point from
  /// the two uniaxial points; the value is the fraction by which the shear strength falls short).
  double chord_shear_deficit(const TestPath &path, double compression, double shear, double tension);
} // namespace anticrack::params
