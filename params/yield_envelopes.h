// Failure envelopes in a two-dimensional stress plane, the shapes the calibration fits to DEM failure
// points: the cohesive Cam-Clay ellipse (docs/physics.md §2, Ritter et al. 2020, Eq. 1), Mohr-Coulomb with an
// elliptical cap (Mede et al. 2018: weak-layer envelopes "resemble Mohr-Coulomb with a cap") and the quadratic
// polynomial of Bobillier et al. 2020 (Eqs. 9 and 10).
//
// The plane. A point has a normal coordinate, COMPRESSION POSITIVE, and a shear coordinate >= 0. It is
// either the base-stress plane (sigma, tau) of the mixed-mode tests of Ritter et al. (2020) or the invariant plane
// (p, q) of the continuum model; the envelopes do not know which, the caller says so in the names of
// its data sets. The two planes hold different stress measures (docs/physics.md §2): a fit in one plane is not
// a fit in the other.
//
// Why radii. The DEM loads along rays from the origin: the direction of the load (the loading angle psi
// of Ritter et al. 2020) is what the test controls, the size of the load at failure is what it measures. Every
// envelope here encloses the origin and is star-shaped about it, so it is the curve r = R(a) in polar
// coordinates of the plane, a in [0, pi] the angle from the compressive normal axis,
//     normal = r cos a,   shear = r sin a.
// A failure point i has a_i = atan2(shear_i, normal_i) and r_i = |point_i|; the fits minimise the
// radial residuals r_i - R(a_i) (the error sits in the measured variable, not in the controlled one).
//
// Parametrisations. Each model has physical parameters (what a user reads, with units) and an
// unconstrained internal parametrisation the optimiser works in (logarithms of positive parameters,
// logits of bounded ones), so that every internal vector is an admissible envelope.
#pragma once

#include <Eigen/Core>

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace anticrack::params
{
  /// A failure point in a stress plane: normal stress compression positive, shear >= 0 [Pa].
  struct StressPoint
  {
    double normal = 0; ///< sigma or p, compression positive [Pa]
    double shear = 0;  ///< tau or q, >= 0 [Pa]
  };

  /// Polar angle a = atan2(shear, normal) of a point, in [0, pi] for shear >= 0 [rad].
  double polar_angle(const StressPoint &point);

  /// Distance of a point from the origin of the plane [Pa].
  double polar_radius(const StressPoint &point);

  /// Result of an admissibility check: the reason names the violated condition and the values.
  struct Admissibility
  {
    bool admissible = true;
    std::string reason; ///< empty when admissible
  };

  /// A failure envelope r = R(a) in a stress plane, enclosing the origin; see the file comment for the
  /// plane, the angle and the parametrisations. Implementations are stateless: parameters are passed to
  /// every call, so one object serves every fit.
  class YieldEnvelope
  {
  public:
    virtual ~YieldEnvelope() = default;

    /// Snake-case identifier of the model ("cohesive_cam_clay", ...), used in output files.
    virtual std::string name() const = 0;

    /// Names of the physical parameters, in the order of the parameter vectors.
    virtual std::vector<std::string> parameter_names() const = 0;

    /// Units of the physical parameters ("Pa", "-", "deg", "1/Pa"), same order.
    virtual std::vector<std::string> parameter_units() const = 0;

    /// Number of parameters (physical and internal vectors have this size).
    std::size_t n_parameters() const { return parameter_names().size(); }

    /// Distance R(a) from the origin to the envelope along the ray of polar angle a in [0, pi] [Pa].
    virtual double radius(double angle, const Eigen::VectorXd &physical) const = 0;

    /// Shear of the envelope at a normal stress, if the envelope reaches that normal stress (between its
    /// tensile and compressive tips); for plotting.
    virtual std::optional<double> shear_at(double normal, const Eigen::VectorXd &physical) const = 0;

    /// Internal (unconstrained) coordinates of admissible physical parameters.
    virtual Eigen::VectorXd to_internal(const Eigen::VectorXd &physical) const = 0;

    /// Physical parameters of internal coordinates; admissible for every finite internal vector (up to
    /// overflow of the exponentials).
    virtual Eigen::VectorXd to_physical(const Eigen::VectorXd &internal) const = 0;

    /// Jacobian d physical_i / d internal_j of to_physical at `internal`. Entries for a physical
    /// parameter that does not depend on an internal coordinate are exactly zero: a row with a single
    /// non-zero entry, on the diagonal, marks a parameter that is a monotone function of its own
    /// internal coordinate alone (confidence intervals map endpoint to endpoint, see envelope_fit.h).
    virtual Eigen::MatrixXd physical_jacobian(const Eigen::VectorXd &internal) const = 0;

    /// Whether the physical parameters describe an envelope of this family that encloses the origin,
    /// with the violated condition in the reason otherwise.
    virtual Admissibility admissible(const Eigen::VectorXd &physical) const = 0;

    /// Several admissible starting points (physical) derived from the data, for a multi-start fit: the
    /// fit must not depend on one lucky guess. The data must have passed check_envelope_data()
    /// (envelope_fit.h): finite, at least one tensile point (normal < 0).
    virtual std::vector<Eigen::VectorXd> initial_guesses(const std::vector<StressPoint> &points) const = 0;
  };

  /// The envelope families.
  enum class EnvelopeKind
  {
    cohesive_cam_clay,   ///< docs/physics.md §2, Eq. 1 of Ritter et al. (2020)
    mohr_coulomb_cap,    ///< Mede et al.'s (2018) description of weak-layer envelopes
    quadratic_polynomial ///< Eq. 9 of Bobillier et al. (2020)
  };

  /// Every envelope family, in the order of the enumeration.
  std::vector<EnvelopeKind> all_envelope_kinds();

  /// A new model object of the given family.
  std::unique_ptr<YieldEnvelope> make_envelope(EnvelopeKind kind);

  // ---------------------------------------------------------------------------------------------------
  // Cohesive Cam-Clay, the pieces the rest of the code uses directly.

  /// The cohesive Cam-Clay surface (docs/physics.md §2; Ritter et al. 2020, Eq. 1 with sigma_0 = p0) as
  /// the calibration hands it on. The fits keep positional vectors in the order of
  /// YieldEnvelope::parameter_names() for the optimiser; past the fit the surface travels by name.
  struct CamClaySurface
  {
    double p0 = 0;    ///< compressive tip (sigma_0 in the (sigma, tau) plane) [Pa], > 0
    double beta = 0;  ///< tensile tip at -beta p0, >= 0 (cohesion)
    double M = 0;     ///< slope of the cohesionless critical state line, > 0
  };

  /// A confidence interval of the surface, parameter by parameter: the lower ends and the upper ends.
  struct CamClaySurfaceInterval
  {
    CamClaySurface lower, upper;
  };

  /// The surface of a physical parameter vector (p0, beta, M) of the cohesive Cam-Clay envelope;
  /// throws std::invalid_argument unless the vector has 3 entries.
  CamClaySurface cam_clay_surface(const Eigen::VectorXd &physical);

  /// Cohesive Cam-Clay yield function (docs/physics.md §2; Ritter et al. 2020, Eq. 1 with sigma0 = p0):
  ///   y(n, s) = (1 + 2 beta) s^2 + M^2 (n + beta p0)(n - p0),
  /// negative inside, zero on the ellipse with tips n = p0 (compression) and n = -beta p0 (tension).
  /// Units Pa^2.
  double cam_clay_yield(double normal, double shear, double p0, double beta, double M);

  /// Distance from the origin to the Cam-Clay ellipse along the ray (cos a, sin a), a in [0, pi]: the
  /// one positive root of R^2 [(1 + 2 beta) sin^2 a + M^2 cos^2 a] + R M^2 p0 (beta - 1) cos a
  /// - M^2 beta p0^2 = 0 (for beta = 0 the root is 0 on the tensile side) [Pa].
  double cam_clay_radius(double angle, double p0, double beta, double M);

  /// Largest shear of the Cam-Clay ellipse, q_max = M p0 (1 + beta) / (2 sqrt(1 + 2 beta)), reached at
  /// the centre n = (1 - beta) p0 / 2 (docs/physics.md §2) [Pa].
  double cam_clay_peak_shear(double p0, double beta, double M);

  // ---------------------------------------------------------------------------------------------------
  // Quadratic polynomial, the strength scaling of Bobillier et al. (2020).

  /// Coefficients (b0, b1, b2) of the polynomial envelope shear = b0 + b1 n + b2 n^2 scaled
  /// homothetically by k = strength_ratio = sigma_c / sigma_c,ref: both stress axes are multiplied by
  /// k (n' = k n, s' = k s), so s' = k b0 + b1 n' + (b2 / k) n'^2 and both tips move by the factor k.
  ///
  /// Eq. 10 of Bobillier et al. (2020) as printed, tau = (b2 sigma^2 + b1 sigma + b0) sigma_wl / sigma_wl,ref, multiplies
  /// only the shear by the ratio: it leaves the tensile and compressive tips where they were, although
  /// sigma_wl,ref is itself the compressive strength that the ratio is meant to change. A change of bond
  /// strength in a bonded-particle model scales every stress of the failure envelope by the same
  /// factor (the bond forces at failure, hence all macroscopic stresses, are proportional to the bond
  /// strength while the geometry is unchanged), which is the homothety implemented here.
  ///
  /// (Bobillier et al. (2020) print b0 = -766 Pa, b1 = -0.25, b2 = 1.97e-4 1/Pa, a convex curve through negative
  /// shear; with the shear taken positive, as here, its envelope is b0 = 766 Pa, b1 = 0.25,
  /// b2 = -1.97e-4 1/Pa, with tips at n = -1437 Pa and n = 2706 Pa, next to its sigma_wl,ref = 2650 Pa.)
  ///
  /// Throws std::invalid_argument unless the vector has 3 entries and the ratio is finite and > 0.
  Eigen::VectorXd scale_polynomial(const Eigen::VectorXd &polynomial_parameters, double strength_ratio);
} // namespace anticrack::params
