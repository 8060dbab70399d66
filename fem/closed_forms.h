// Closed forms that the FE solver's physics tests compare against (docs/physics.md §3): plane-strain
// elastic helpers, the propagation saw test (PST) as a slab on an elastic (Winkler) foundation with
// its energy release rate, Gaume et al. (2017)'s critical cut length, Heierli (2005)'s flexural wave
// speed, and estimates of the error of the beam model against a 2D continuum. The derivations, with
// the equation numbers cited here, are in docs/fem_closed_forms.md. Plain C++ (no deal.II), SI units.
//
// PST geometry and signs (docs/fem_closed_forms.md §2):
//   x   along the slope from the column end where the saw cut starts (x = 0) into the column; the weak
//       layer is removed over 0 <= x < a (cut length a) and intact for x >= a, up to infinity (the
//       supported part is semi-infinite: semi_infinite_column_error_estimate() says when a finite
//       column of length L is long enough);
//   w   slab deflection normal to the slope, positive into the weak layer: for x >= a it is the
//       weak-layer compression (a length, positive in compression, unlike strains in docs/physics.md §0);
//   u   slab axial displacement along +x; for x >= a it is the weak-layer shear slip;
//   ψ   slope angle: ψ > 0 when the slope-parallel weight points along +x (the cut starts at the
//       upslope end of the column), ψ < 0 when the cut starts at the downslope end. The closed forms
//       of G do not depend on the sign; the neglected bending–shear coupling does (Eq. 21).
// Slab: Euler–Bernoulli beam and axial bar, plane strain (E' = E/(1 − ν²)), per unit width.
// Weak layer: independent normal springs k_n = M_wl/h and shear springs k_t = G_wl/h (Eq. 2).
#pragma once

#include <functional>

namespace anticrack::fem::closed_forms
{
  /// Standard gravity [m/s²].
  inline constexpr double standard_gravity = 9.81;

  /// Shear correction factor of a rectangular section (Timoshenko beam), used by
  /// timoshenko_shear_error_estimate().
  inline constexpr double rectangular_shear_correction = 5.0 / 6.0;

  /// cut_length_for_fracture_energy() looks for the cut length up to this many characteristic
  /// lengths 1/λ (G grows as (λa)⁴, so G there is ~1e12 G(0): far beyond any column).
  inline constexpr double maximum_cut_length_in_characteristic_lengths = 1000;

  // ---------------------------------------------------------------------------------------------
  // Isotropic linear elasticity (Eq. 1). All throw std::invalid_argument unless E > 0 and
  // −1 < ν < 1/2 (or K, G, ρ > 0), naming the argument and its range.

  /// E' = E / (1 − ν²) [Pa]: the modulus of a plate (or a beam in plane strain) in bending/stretching.
  double plane_strain_modulus(double youngs_modulus, double poisson_ratio);

  /// M = E (1 − ν) / ((1 + ν)(1 − 2ν)) [Pa]: the modulus in uniaxial strain (a laterally confined
  /// layer compressed normal to itself).
  double constrained_modulus(double youngs_modulus, double poisson_ratio);

  /// G = E / (2 (1 + ν)) [Pa].
  double shear_modulus(double youngs_modulus, double poisson_ratio);

  /// c_p = sqrt((K + 4G/3) / ρ) [m/s].
  double p_wave_speed(double bulk_modulus, double shear_modulus, double density);

  /// c_s = sqrt(G / ρ) [m/s].
  double shear_wave_speed(double shear_modulus, double density);


  // ---------------------------------------------------------------------------------------------
  // The PST as a slab on an elastic foundation (docs/fem_closed_forms.md §2–§4).

  /// Slab and weak layer of the PST (SI units). check() before use; every function below calls it.
  struct SlabOnFoundation
  {
    double slab_thickness = 0;            ///< H [m], > 0
    double slab_youngs_modulus = 0;       ///< E [Pa], > 0
    double slab_poisson_ratio = 0;        ///< ν, in (−1, 1/2)
    double slab_density = 0;              ///< ρ [kg/m³], > 0
    double weak_layer_thickness = 0;      ///< h [m], > 0
    double weak_layer_youngs_modulus = 0; ///< E_wl [Pa], > 0
    double weak_layer_poisson_ratio = 0;  ///< ν_wl, in (−1, 1/2)
    double gravity = standard_gravity;    ///< g [m/s²], > 0
    double slope_angle = 0;               ///< ψ [rad], in (−π/2, π/2); 0 = flat; sign: see top of file

    /// Throws std::invalid_argument naming the first parameter that is not finite or out of its
    /// range (given above).
    void check() const;
  };

  /// D = E' H³ / 12 [N m]: bending stiffness of the slab per unit width (Eq. 2).
  double slab_bending_stiffness(const SlabOnFoundation &s);

  /// E' H [N/m]: axial stiffness of the slab per unit width (Eq. 2).
  double slab_axial_stiffness(const SlabOnFoundation &s);

  /// k_n = M_wl / h [Pa/m]: normal stiffness of the weak layer per unit area (Eq. 2).
  double normal_foundation_stiffness(const SlabOnFoundation &s);

  /// k_t = G_wl / h [Pa/m]: shear stiffness of the weak layer per unit area (Eq. 2).
  double shear_foundation_stiffness(const SlabOnFoundation &s);

  /// q_n = ρ g H cos ψ [N/m²]: slope-normal weight of the slab per unit area (= σ_n of Gaume 2017).
  double normal_load(const SlabOnFoundation &s);

  /// q_t = ρ g H sin ψ [N/m²]: slope-parallel weight of the slab per unit area, signed (= τ_g).
  double tangential_load(const SlabOnFoundation &s);

  /// 1/λ = (4 D / k_n)^{1/4} [m]: decay length of the bending solution on the foundation (Eq. 3).
  double characteristic_length(const SlabOnFoundation &s);

  /// 1/μ = sqrt(E' H / k_t) = sqrt(E' H h / G_wl) [m]: decay length of the axial (shear-lag)
  /// solution (Eq. 3); it is Λ of Gaume et al. (2017).
  double shear_lag_length(const SlabOnFoundation &s);

  /// The slab deflection and its derivatives at one x. Bending moment M = −D w'' (sagging positive),
  /// shear force V = dM/dx = −D w'''.
  struct SlabDeflection
  {
    double w = 0;       ///< [m], positive into the weak layer
    double dw_dx = 0;   ///< [−]
    double d2w_dx2 = 0; ///< [1/m]
    double d3w_dx3 = 0; ///< [1/m²]
  };

  /// w(x) for cut length a >= 0 and any x >= 0: the cantilever quartic over 0 <= x < a (Eq. 4) and
  /// the uniform settlement plus the decaying Hetényi solution for x >= a (Eqs. 5–6). Throws
  /// std::invalid_argument if a or x is negative or not finite.
  SlabDeflection slab_deflection(const SlabOnFoundation &s, double cut_length, double x);

  /// The slab's axial displacement and strain at one x. Axial force N = E' H du/dx.
  struct SlabAxialDisplacement
  {
    double u = 0;     ///< [m], along +x
    double du_dx = 0; ///< [−]
  };

  /// u(x) of the uncoupled axial bar (mode II): the free bar over 0 <= x < a, the uniform slip plus
  /// the decaying shear-lag solution for x >= a (Eq. 11). Same argument checks as slab_deflection().
  SlabAxialDisplacement slab_axial_displacement(const SlabOnFoundation &s, double cut_length, double x);

  /// w(a) = (q_n / k_n) (1 + λa)² [m]: the total weak-layer compression at the crack tip (uniform
  /// settlement included), Eq. 7.
  double weak_layer_compression_at_tip(const SlabOnFoundation &s, double cut_length);

  /// u(a) = (q_t / k_t) (1 + μa) [m]: the weak-layer shear slip at the crack tip, signed, Eq. 11.
  double weak_layer_slip_at_tip(const SlabOnFoundation &s, double cut_length);

  /// G_I = ½ k_n w(a)² = q_n² / (2 k_n) (1 + λa)⁴ [J/m²], Eq. 10.
  double energy_release_rate_mode_I(const SlabOnFoundation &s, double cut_length);

  /// G_II = ½ k_t u(a)² = q_t² / (2 k_t) (1 + μa)² [J/m²], Eq. 12 (bending–shear coupling neglected).
  double energy_release_rate_mode_II(const SlabOnFoundation &s, double cut_length);

  /// G = G_I + G_II [J/m²] = −dΠ/da of the uncoupled model.
  double energy_release_rate(const SlabOnFoundation &s, double cut_length);

  /// The smallest a with G(a) = G_c [m] (Eq. 14; G increases strictly, so it is the only one), by
  /// TOMS 748 on a bracket [0, a_hi] doubled from 1/λ. Throws std::invalid_argument unless G_c is
  /// finite and > 0, and std::domain_error if G(0) >= G_c (the uncut column already propagates) or
  /// G_c > G at maximum_cut_length_in_characteristic_lengths / λ.
  double cut_length_for_fracture_energy(const SlabOnFoundation &s, double fracture_energy);

  // ---------------------------------------------------------------------------------------------
  // Literature closed forms (docs/fem_closed_forms.md §5).

  /// Gaume et al. (2017, The Cryosphere 11:217), a stress criterion for the onset of propagation:
  ///   a_c = Λ [−τ_g + sqrt(τ_g² + 2 σ_n (τ_p − τ_g))] / σ_n,   Λ = sqrt(E' H h / G_wl),
  /// σ_n = ρ g H cos ψ, τ_g = ρ g H sin ψ (Eq. 15): the positive root of the tip shear stress
  /// τ_g (1 + a/Λ) + σ_n a² / (2 Λ²) = τ_p. Throws std::invalid_argument unless τ_p is finite and
  /// > 0, std::domain_error if τ_p <= τ_g (the layer fails without a cut).
  double critical_cut_length_gaume2017(const SlabOnFoundation &s, double peak_shear_strength);

  /// The cut length at which the weak layer at the crack tip of the beam on an elastic foundation
  /// first reaches its strength: the tip tractions σ(a) = k_n w(a) = q_n (1 + λa)² (Eq. 7) and
  /// |τ(a)| = k_t |u(a)| = |q_t| (1 + μa) (Eq. 11) against the layer-plane shear strength
  /// `shear_strength(σ)` [Pa] (NaN where σ alone exceeds the strength, e.g. beyond the compressive
  /// tip). Unlike Gaume et al. (2017)'s shear criterion it lets the tip fail in compression, the
  /// anticrack's collapse; like it, it ignores the stress concentration of a finite-thickness layer.
  /// Scans a in steps of 1/(100 λ) and then bisects to 1e-12 relative. Throws std::domain_error if
  /// the uncut column's tip already fails, or nothing fails up to
  /// maximum_cut_length_in_characteristic_lengths / λ.
  double first_tip_yield_cut_length(const SlabOnFoundation &s, const std::function<double(double)> &shear_strength);

  /// Heierli (2005), speed of the flexural wave that a collapsing weak layer carries under the slab:
  ///   c = (g D_f / (2 h_f ρ H))^{1/4},   D_f = E H³ / 12   [m/s]   (docs/physics.md §3; Eq. 16).
  /// Throws std::invalid_argument unless every argument is finite and > 0.
  double flexural_wave_speed_heierli2005(double youngs_modulus,
                                         double slab_thickness,
                                         double slab_density,
                                         double collapse_height,
                                         double gravity = standard_gravity);

  /// Heierli (2005)'s touchdown distance of the same wave, the length from the front to where the
  /// slab rests again on the collapsed layer:
  ///   λ = γ (2 h_f D_f / (g ρ H))^{1/4},   γ = heierli2005_touchdown_factor   [m]   (Eq. 23).
  /// c λ / γ = sqrt(D_f / ρH): the steady flexural wave of Eq. 16. Same argument checks.
  double touchdown_distance_heierli2005(double youngs_modulus,
                                        double slab_thickness,
                                        double slab_density,
                                        double collapse_height,
                                        double gravity = standard_gravity);

  /// γ of Eq. 23 (Heierli 2005, as the SLF's crack-speed scripts use it).
  inline constexpr double heierli2005_touchdown_factor = 2.331;

  /// The slab of the steady-state touchdown: Euler–Bernoulli (no shear deformation) or Timoshenko
  /// (shear stiffness κ G H, κ = rectangular_shear_correction, G of the slab's E and ν).
  enum class SlabShear
  {
    euler_bernoulli,
    timoshenko
  };

  /// The static touchdown distance of a long cut (a → ∞): the slab on the elastic foundation ahead
  /// of the tip (x < 0), unsupported over 0 < x < λ, and resting on a rigid base h_c below its
  /// unloaded position beyond λ, where it lies flat (w = h_c, w' = 0) without a concentrated
  /// reaction (M = sqrt(D S) θ, the moment of the rested slab; M = 0 for Euler–Bernoulli)
  /// (Eqs. 24–26). This is the steady state of the slab-touchdown model of Rosendahl et al. (2025,
  /// mode C), with the rested slab on a rigid base instead of a stiff collapsed layer. Static: no
  /// inertia, so a running crack's touchdown is longer (Eq. 23 is the dynamic counterpart). Throws
  /// On a slope it takes the slope-normal load q_n and leaves out the slope-parallel load's coupling
  /// with bending (as Eq. 21 estimates for G). Throws std::invalid_argument unless collapse_height is
  /// finite and > 0, std::domain_error if the settlement q_n / k_n already fills it.
  double steady_state_touchdown_distance(const SlabOnFoundation &s, double collapse_height, SlabShear shear);

  // ---------------------------------------------------------------------------------------------
  // Error of the beam-on-springs model against a 2D plane-strain continuum (docs/fem_closed_forms.md
  // §6). Each returns a first-order bound of |ΔG|/G over all cut lengths a >= 0.

  /// (a) Shear deformation of the slab (Timoshenko): (λH)² E' / (24 κ G), κ = 5/6 (Eq. 18). Makes G
  /// larger; largest at λa = 1.
  double timoshenko_shear_error_estimate(const SlabOnFoundation &s);

  /// (b) Weak-layer shear caused by the slab rotation (bottom fibre slip −(H/2) w'), flat part:
  /// (3/4) ε_b with ε_b = k_t H² / (8 D λ²) = 3 G_wl / (2 E' H h λ²) (Eq. 19). Makes G smaller;
  /// largest at λa = 1.
  double slab_rotation_coupling_error_estimate(const SlabOnFoundation &s);

  /// (c) Finite weak-layer thickness (the free edge of the layer at the crack tip):
  /// 4 C_I(ν_wl) λh + 2 C_II(ν_wl) μh with the edge coefficients of a 2D elastic strip (Eq. 20,
  /// tabulated for ν_wl in [−0.3, 0.45]; throws std::domain_error outside). Makes G larger;
  /// largest at a = 0.
  double weak_layer_thickness_error_estimate(const SlabOnFoundation &s);

  /// (d) Coupling of the slope-parallel load with bending through the eccentricity H/2 of the
  /// weak-layer shear: 2 λH |tan ψ| (Eq. 21). Its sign depends on the cut direction (smaller G when
  /// the cut starts upslope, ψ > 0); largest at a = 0.
  double slope_coupling_error_estimate(const SlabOnFoundation &s);

  /// (a) + (b) + (c) + (d): choose parameters where this is small (e.g. < 0.02) for a test of the
  /// FE G(a) against energy_release_rate().
  double beam_model_error_estimate(const SlabOnFoundation &s);

  /// Relative error of G from taking the supported part as semi-infinite when it ends, free, at
  /// x = column_length: (G_I 17 e^{−2λℓ} + G_II (2d + d²)) / G, d = coth(μℓ) − 1,
  /// ℓ = column_length − a (Eq. 22; the mode-I bound holds for λℓ >= 2, the mode-II one always).
  /// Throws std::invalid_argument unless 0 <= a < column_length.
  double semi_infinite_column_error_estimate(const SlabOnFoundation &s, double cut_length, double column_length);

  // ---------------------------------------------------------------------------------------------
  // Can the weak layer carry the snowpack at all? (docs/fem_closed_forms.md §5.2, Eqs. 27–28)

  /// Mean pressure p (compression positive) and von Mises stress q [Pa] of a laterally confined
  /// elastic layer on a slope under the overburden W (the weight per unit slope-parallel area of
  /// everything above the point, W = g Σ ρ_i h_i): σ_nn = −W cos ψ, σ_xn = W sin ψ, and the
  /// in-plane stresses k σ_nn with k = ν / (1 − ν) (ε_xx = ε_zz = 0), so (Eq. 27)
  ///   p = W cos ψ (1 + 2k) / 3,   q² = (W cos ψ (1 − k))² + 3 (W sin ψ)².
  /// The far field of a long column or an infinite slope, before anything yields. Throws
  /// std::invalid_argument unless W >= 0, |ψ| < π/2 and −1 < ν < 1/2.
  struct StressInvariants
  {
    double p = 0, q = 0;
  };
  StressInvariants confined_layer_invariants(double overburden, double slope_angle, double poisson_ratio);

  /// The smallest compressive strength p0 [Pa] whose cohesive Cam-Clay surface
  /// y = (1 + 2β) q² + M² (p + β p0)(p − p0) contains the state (p, q), p > 0 (Eq. 28, the larger
  /// root of y = 0 in p0):
  ///   p0 = [−(1 − β) p + sqrt((1 − β)² p² + 4 β ((1 + 2β) q² / M² + p²))] / (2β),
  ///   p0 = p + (1 + 2β) q² / (M² p) at β = 0.
  /// y is homogeneous of degree 2 in (p, q, p0): the state λ (p, q) reaches the surface of p0 at
  /// λ = p0 / strength_to_contain(p, q). Throws std::invalid_argument unless p > 0, q >= 0,
  /// β in [0, 1] and M > 0.
  double strength_to_contain(double p, double q, double beta, double M);
} // namespace anticrack::fem::closed_forms
