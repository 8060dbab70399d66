// Cohesive Cam-Clay plasticity at a material point (small strain, 3D): the constitutive core of the
// FE solver (docs/physics.md §2; Gaume et al. 2018, Nat. Commun. 9:3047; Ritter et al. 2020, Eq. 1).
//
// Conventions (docs/physics.md §0): stress and strain tensors are tension-positive; the mean pressure
// p = −tr σ / 3 is compression-positive; s = σ + p I, q = sqrt(3/2 s:s). Plane strain is a 3D strain
// with ε_zz = ε_xz = ε_yz = 0 (plane_strain()); σ_zz follows from the 3D update.
//
// Model:
//   elasticity     σ = K tr(ε − ε_p) I + 2 G dev(ε − ε_p)
//   yield surface  y(p, q, p0) = (1 + 2β) q² + M² (p + β p0)(p − p0)
//                              = (1 + 2β) q² + M² (p − p_c)² − M² a²,
//                  p_c = (1 − β) p0 / 2,  a = (1 + β) p0 / 2
//                  (tips at p = p0 and p = −β p0; q_max = M p0 (1 + β) / (2 sqrt(1 + 2β)) at p_c)
//   flow           Δε_p = Δγ ∂y/∂σ = Δγ (−(2/3) M² (p − p_c) I + 3 (1 + 2β) s)   (associative)
//   hardening      p0 = max(K sinh(min(ξ max(−α, 0), max_sinh_argument)), p0_floor),
//                  α_{n+1} = α_n + tr Δε_p    (signed_volumetric: compaction hardens, dilation softens)
//                  α_{n+1} = α_n + |tr Δε_p|  (collapse: every plastic volume change softens)
//                  α_0 = −asinh(p0_initial / K) / ξ; ξ = 0 means no hardening (p0 ≡ p0_initial).
//                  Under hydrostatic compaction the collapse law snaps back when ξ cosh(ξ α) > 1
//                  (so for ξ > 1 when p0 ≪ K): softening outruns the elastic unloading and the
//                  backward-Euler step lands on the floor at once (a jump, not a path).
//   densification  σ = σ_cc − p_d I,   p_d = K_d ⟨−tr ε − ε_d⟩,   ⟨x⟩ = max(x, 0),
//                  σ_cc the Cam-Clay stress above, ε the TOTAL strain; off when ε_d = 0.
//
// Residual response after collapse (docs/physics.md §2: a collapsed weak layer must not invert
// elements). Two pieces act together:
//  * the floor p0_floor is the residual strength: once the layer has collapsed (collapse law) p0
//    sits there, and the Cam-Clay part keeps flowing plastically at the small stress of the floor
//    surface (p <= p0_floor in compaction); residual_p0_floor() sets it from the material file's
//    "Residual strength ratio";
//  * the lock-up: when the compaction −tr ε exceeds ε_d the collapsed pores are closed and the
//    grains are in contact; a compaction spring K_d in parallel with the Cam-Clay stress then
//    carries the load. Under hydrostatic compaction past the collapse
//        p = p_cc + K_d ⟨−tr ε − ε_d⟩,   p_cc = p0_floor,
//    so a load p needs −tr ε = ε_d + (p − p0_floor)/K_d: with K_d of the order of the slab's
//    modulus (MPa) and p = 1–10 kPa, ε_d + 1e-3 … 1e-2. For snow weak layers the collapse height is
//    3–5 mm of 10–30 mm, ε_d ≈ 0.15–0.3.
//    The spring is linear, so it keeps −tr ε < 1 (the small-strain image of det F > 0) for every
//    mean stress p < p0_floor + K_d (1 − ε_d), not for an unbounded load; with K_d = 1 MPa and
//    ε_d = 0.2 that is 0.8 MPa, ~100 times the weight of a 3 m slab (ρ g D ≈ 7 kPa). It bounds the
//    volumetric compaction only: distortion at the residual strength is not bounded by it.
//    K_d also enters the explicit time step (p_wave_modulus()): K_d ≫ K + 4G/3 of the layer shrinks
//    the stable step of the locked elements by sqrt((K + 4G/3 + K_d)/(K + 4G/3)).
// The lock-up is a nonlinear elastic (history-free, conservative: energy K_d ⟨·⟩²/2) spring. It does
// NOT enter the yield function: the return mapping sees only σ_cc, and p_d only adds to the stress
// and K_d I⊗I to the tangent (where −tr ε > ε_d). Reasons: it models a second load path (closed
// pores, grain contacts) in parallel with the broken bond skeleton rather than a change of the
// skeleton's strength; it keeps the Cam-Clay history (ε_p, α, p0) identical with and without it,
// so the return mapping, its brackets and its tangent are untouched (bit-for-bit when off). The
// shear strength of the Cam-Clay part of a densified layer stays at the residual surface
// q_max(p0_floor) whatever the confinement; the pressure-dependent friction of the compacted grains
// is a model of its own, in parallel (fem/material/collapsed_layer_friction.h).
//
// Return mapping (backward Euler, closest point in the energy norm). With the trial state (p_tr, q_tr)
// and c = 2 K M² Δγ, d = 1 + 6 G (1 + 2β) Δγ, docs/physics.md §2 gives
//   q = q_tr / d,   p = (p_tr + c p_c) / (1 + c)   ⇔   p − p_c = (p_tr − p_c) / (1 + c),
// so for fixed p0, y(Δγ) = (1 + 2β) q_tr²/d² + M² (p_tr − p_c)²/(1 + c)² − M² a² decreases strictly
// from y_tr > 0 to −M² a² < 0. The deviatoric direction of the trial stress is kept (radial return
// in the deviatoric plane). With hardening the two unknowns are Δγ and δ = α_{n+1} − α_n:
//   R1 = y(Δγ, p0(α_n + δ)) = 0,   R2 = δ − h(tr Δε_p) = 0,   tr Δε_p = (p − p_tr) / K.
// See update_stress() for how they are solved and sub-stepped.
#pragma once

#include <deal.II/base/symmetric_tensor.h>

#include <stdexcept>

namespace anticrack::fem
{
  /// How the volumetric plastic strain accumulator α evolves (docs/physics.md §2).
  enum class HardeningLaw
  {
    signed_volumetric, ///< α += tr Δε_p: compaction hardens, dilation softens
    collapse           ///< α += |tr Δε_p|: every plastic volume change softens (weak layers)
  };

  /// The return mapping did not converge even with the largest number of sub-steps, the strain was
  /// not finite, or the local Jacobian of the tangent was singular. The message gives the trial state.
  class ReturnMappingError : public std::runtime_error
  {
  public:
    using std::runtime_error::runtime_error;
  };

  /// The sinh argument ξ max(−α, 0) of the hardening law is capped here so that p0 = K sinh(·) never
  /// overflows (p0 ≤ K sinh(50) ≈ 2.6e21 K, far beyond any physical state; y ~ M² p0² stays finite).
  inline constexpr double max_sinh_argument = 50;

  /// Parameters of the cohesive Cam-Clay material point (SI units). check() before use.
  struct CamClayParameters
  {
    double bulk_modulus = 0;     ///< K [Pa], > 0
    double shear_modulus = 0;    ///< G [Pa], > 0
    double M = 0;                ///< slope of the critical state line, > 0
    double beta = 0;             ///< β: tensile tip at −β p0, in [0, 1]
    double p0_initial = 0;       ///< compressive tip of the initial surface [Pa], >= p0_floor
    double hardening_factor = 0; ///< ξ of p0 = K sinh(ξ max(−α, 0)), >= 0; 0: no hardening
    double p0_floor = 0;         ///< lower bound of p0 [Pa], > 0
    HardeningLaw law = HardeningLaw::signed_volumetric;
    /// ε_d: the compaction −tr ε (of the TOTAL strain) at which the collapsed pores are closed and
    /// the lock-up spring engages (header); in [0, 1); 0: no lock-up. Weak layers: ≈ 0.15–0.3.
    double densification_strain = 0;
    /// K_d [Pa]: modulus of the lock-up, p_d = K_d ⟨−tr ε − ε_d⟩; > 0 when densification_strain
    /// > 0 and 0 when it is 0 (a modulus without a strain is refused rather than ignored).
    /// Of the order of the densified layer's or the slab's modulus (MPa).
    double densification_modulus = 0;
    /// Iterations allowed to each scalar solve of the return mapping (the projection for fixed p0
    /// and the hardening solve); when exceeded the strain increment is sub-stepped.
    unsigned int max_iterations = 60;
    /// Largest number of sub-steps (1, 2, 4, ... up to this) before ReturnMappingError.
    unsigned int max_substeps = 64;

    /// Sets K = E / (3 (1 − 2ν)) and G = E / (2 (1 + ν)); throws std::invalid_argument unless
    /// E > 0 and −1 < ν < 1/2.
    void set_elastic_moduli(double youngs_modulus, double poisson_ratio);

    /// Throws std::invalid_argument naming the first parameter out of its range (given above; also
    /// p0_initial <= K sinh(max_sinh_argument) when ξ > 0, and every value finite).
    void check() const;
  };

  /// Smallest residual strength ratio residual_p0_floor() uses: p0_floor >= this × p0_initial.
  inline constexpr double min_residual_strength_ratio = 1e-3;

  /// p0_floor from the material file's "Residual strength ratio" R (residual / peak strength,
  /// params/): max(R, min_residual_strength_ratio) · p0_initial [Pa].
  /// The floor must stay positive even for R = 0: at p0 = 0 the surface shrinks to the point
  /// p = q = 0 (no elastic range; the projection divides by M a ∝ p0, and check() requires
  /// p0_floor > 0), and the return mapping is well conditioned and tested down to p0_floor =
  /// 1e-3 p0 (p_tr/p0_floor ~ 1e3 in the projection). A thousandth of the peak is "no strength" for
  /// the structure: the residual ratios the DEM measures are of order 0.1.
  /// Throws std::invalid_argument unless p0_initial > 0 and 0 <= R <= 1 (both finite).
  double residual_p0_floor(double p0_initial, double residual_strength_ratio);

  /// History of a material point. p0 is stored with α so that the state describes its own surface.
  struct CamClayState
  {
    dealii::SymmetricTensor<2, 3> strain;         ///< total strain at which the state was reached
    dealii::SymmetricTensor<2, 3> plastic_strain; ///< ε_p
    double alpha = 0;                             ///< α, the volumetric plastic strain accumulator
    double p0 = 0;                                ///< p0(α) [Pa]

    /// Zero strain, zero plastic strain, α = α_0 (0 if ξ = 0) and p0 = p0(α_0), which is p0_initial
    /// to rounding. Calls parameters.check().
    static CamClayState initial(const CamClayParameters &parameters);
  };

  /// Result of one strain-driven update.
  struct CamClayUpdate
  {
    dealii::SymmetricTensor<2, 3> stress;
    CamClayState state;              ///< the new state (its strain is the total strain given)
    bool plastic = false;            ///< some sub-step yielded
    double plastic_multiplier = 0;   ///< Δγ summed over the sub-steps [1/Pa]
    /// Newton/bisection iterations of the accepted integration (projections and hardening solves,
    /// summed over the sub-steps); 0 for an elastic step.
    unsigned int iterations = 0;
    unsigned int substeps = 1;       ///< number of sub-steps of the accepted integration
    /// p_d = K_d ⟨−tr ε − ε_d⟩ [Pa] of the lock-up, already in `stress` (σ = σ_cc − p_d I): the
    /// Cam-Clay part is stress + p_d I. 0 when the lock-up is off or not engaged.
    double densification_pressure = 0;
  };

  /// The update and its algorithmic tangent.
  struct CamClayTangentUpdate
  {
    CamClayUpdate update;
    /// dσ_{n+1}/dε_{n+1} of exactly the same update (sub-steps included; plus K_d I⊗I where the
    /// lock-up is engaged, −tr ε > ε_d; at −tr ε = ε_d the unlocked side). SymmetricTensor<4,3> stores
    /// all 6×6 components, so it holds the tangent without major symmetry (with hardening
    /// C_ijkl ≠ C_klij); only the minor symmetries, which any stress–strain tangent has, are used.
    dealii::SymmetricTensor<4, 3> tangent;
  };

  /// σ at total strain `total_strain` from the converged state `previous` (backward Euler).
  ///
  /// Algorithm: elastic trial from ε − ε_p,n; if y_tr <= 0 the step is elastic. Otherwise the
  /// hardening equation R(δ) = δ − h(tr Δε_p(δ)) = 0 is solved for δ = α_{n+1} − α_n by Newton
  /// safeguarded by bisection on a bracket known a priori (signed law: between 0 and
  /// (p_c,n − p_tr)/K; collapse law: [0, max(|p_c,n − p_tr|, |p_c,floor − p_tr|)/K]); every
  /// evaluation of R projects the trial state on the surface of p0(α_n + δ) by solving
  /// M a / r(Δγ) − 1 = 0, r² = (1 + 2β) q² + M² (p − p_c)², again by bracketed Newton (the bracket
  /// follows from d, 1 + c lying between 1 + k_min Δγ and 1 + k_max Δγ). ξ = 0, or the collapse law
  /// at the floor, fix p0 and need no hardening iterations. If a solve exceeds max_iterations or
  /// gives a non-finite value, the increment ε − ε_n is split into 2, 4, ... max_substeps equal
  /// sub-steps; then ReturnMappingError. Never returns NaN. The lock-up pressure of the final
  /// total strain is added to the stress after the return (header; it is history-free).
  /// Precondition: parameters.check() passed (CamClayState::initial() calls it).
  CamClayUpdate update_stress(const CamClayParameters &parameters,
                              const CamClayState &previous,
                              const dealii::SymmetricTensor<2, 3> &total_strain);

  /// update_stress() and its consistent tangent: analytic, from the implicit derivatives of the 2×2
  /// local system (R1, R2) with respect to (p_tr, q_tr, α_n), chained through the sub-steps.
  /// Throws ReturnMappingError also when the local Jacobian is singular (the update is not
  /// differentiable there, e.g. at a collapse bifurcation).
  CamClayTangentUpdate update_stress_and_tangent(const CamClayParameters &parameters,
                                                 const CamClayState &previous,
                                                 const dealii::SymmetricTensor<2, 3> &total_strain);

  /// p_d = K_d ⟨−tr ε − ε_d⟩ [Pa] of the lock-up at total strain `total_strain` (0 when off). The
  /// stress of update_stress() at that strain includes −p_d I.
  double densification_pressure(const CamClayParameters &parameters,
                                const dealii::SymmetricTensor<2, 3> &total_strain);

  /// K + 4G/3, plus K_d where the lock-up is engaged (−tr ε > ε_d) [Pa]: for the explicit solver's
  /// time step Δt <= h / sqrt(modulus/ρ). An upper bound of the elastic wave modulus at the point:
  /// K + 4G/3 is the largest eigenvalue of the acoustic tensor of the elastic tangent, the lock-up
  /// adds K_d I⊗I (longitudinal waves only), plastic loading is softer (unless the softening snaps
  /// back, where no stable step exists) and unloading is elastic. It jumps by K_d at ε_d:
  /// re-evaluate it as the strain changes, and keep a safety factor for points that reach ε_d
  /// within a step.
  double p_wave_modulus(const CamClayParameters &parameters, const dealii::SymmetricTensor<2, 3> &total_strain);

  /// p = −tr σ / 3 (compression positive).
  double mean_pressure(const dealii::SymmetricTensor<2, 3> &stress);

  /// q = sqrt(3/2 s:s), s = dev σ.
  double von_mises(const dealii::SymmetricTensor<2, 3> &stress);

  /// y(p, q, p0) = (1 + 2β) q² + M² (p + β p0)(p − p0) [Pa²]: <= 0 inside or on the surface.
  double yield_function(double p, double q, double p0, const CamClayParameters &parameters);

  /// τ_p: the layer-plane shear traction at which the surface of tip p0 is reached under the
  /// layer-plane normal traction σ (compression positive) [Pa], for a point whose lateral stresses
  /// are k σ (k = ν/(1 − ν) laterally confined, as the weak layer under a slab; 0 free). With
  /// p = (1 + 2k) σ / 3 and q² = (1 − k)² σ² + 3 τ² (the layer-plane traction's invariants,
  /// docs/physics.md §2 Eq. P1), y = 0 gives (Eq. P2)
  ///   τ_p² = [−M² (p + β p0)(p − p0) / (1 + 2β) − (1 − k)² σ²] / 3.
  /// NaN where σ alone already lies outside the surface (τ_p² < 0).
  double layer_plane_shear_strength(double sigma, double lateral_stress_ratio, double p0,
                                    const CamClayParameters &parameters);

  /// σ_c: the layer-plane normal traction (compression positive) at which the surface of tip p0 is
  /// reached with no shear, for lateral stresses k σ [Pa]: the positive root of τ_p(σ) = 0 in Eq. P2,
  ///   [M² a² + (1 + 2β)(1 − k)²] σ² + M² a p0 (β − 1) σ − M² β p0² = 0,   a = (1 + 2k)/3
  /// (k = 1: hydrostatic, σ_c = p0). The strength of a confined weak layer under a slab in pure
  /// compression, the peak stress of its collapse.
  double layer_plane_compressive_strength(double lateral_stress_ratio, double p0, const CamClayParameters &parameters);

  /// σ_f: the layer-normal stress (compression positive) of steady plastic flow in uniaxial
  /// compaction (laterally confined, normal n) on the surface of a fixed tip p0 [Pa]: the state
  /// where the associative flow direction is the imposed strain's (the elastic strain no longer
  /// changes), p − p_c = λ/(2M²), q = λ/(3(1 + 2β)), y = 0, σ_f = p + 2q/3. What a collapsed layer
  /// at its residual p0_floor carries while it keeps compacting: a slab whose normal traction
  /// exceeds it crushes the layer further (docs/physics.md §2, "Collapse under the slab").
  double confined_flow_normal_stress(double p0, const CamClayParameters &parameters);

  /// p0(α) of the hardening law, floor and cap included [Pa].
  double hardening_p0(double alpha, const CamClayParameters &parameters);

  /// The 3D strain of a plane-strain state (ε_zz = ε_xz = ε_yz = 0).
  dealii::SymmetricTensor<2, 3> plane_strain(const dealii::SymmetricTensor<2, 2> &in_plane_strain);
} // namespace anticrack::fem
