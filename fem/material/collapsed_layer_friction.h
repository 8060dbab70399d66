// Coulomb friction of a failed weak layer (docs/physics.md §2, "Friction of the failed layer").
//
// Once a weak layer's bonds have broken (its first plastic step: with the collapse law every
// plastic step softens, fem/material/cohesive_cam_clay.h), the slab rests on broken grains in
// contact. They carry shear only by friction on the stress that presses them together, with no
// cohesion and no tension left (Bobillier et al. 2020: once a bond breaks only frictional contact
// remains). The failed layer is therefore two pieces in parallel, on the layer plane of normal n:
//  * the crushing skeleton: the Cam-Clay stress σ_cc of the breaking layer (its tip the softening
//    p0, down to the compaction plateau the DEM measures; its tension β p0 falls with p0, and the
//    last of it, β p0_floor, goes once the softening is complete: the broken skeleton has β = 0)
//    and the lock-up −p_d I. It resists compaction and lateral strain, but not slip: the
//    layer-plane shear strain is kept out of it (its elastic part frozen at zero,
//    fem/model/snowpack_model.cpp), so σ_cc,in = 0 for i ⊥ n;
//  * the friction: a shear traction τ on the layer plane,
//
//   σ = σ_cc − p_d I + (τ ⊗ n + n ⊗ τ),   τ ⊥ n,
//   |τ| <= μ σ_n,   σ_n = ⟨−(σ_cc − p_d I)_nn⟩                                   (F1)
//
// (F1) is Coulomb's law of the crack faces with the skeleton's layer-normal compression as their
// normal traction: the slab's weight on the broken grains, whether the layer is still crushing at
// its plateau or has locked up. It is written on the layer plane, not on the deviator: a collapsing
// layer is compacted in uniaxial strain, whose deviatoric part is not slip and must not use up the
// friction. The law is that of an elastic–perfectly frictional (stick–slip) interface, per volume
// of the failed band, with the layer-plane shear strain γ_i = 2 ε_in (i ⊥ n):
//
//   trial    τ_tr = τ_n + G_f Δγ,       G_f = G max(1, K_d / K)                            (F2)
//   stick    |τ_tr| <= k = μ σ_n,n+1:  τ = τ_tr,           ∂τ_i/∂γ_j = G_f δ_ij
//   slide    |τ_tr|  > k:               τ = (k / |τ_tr|) τ_tr,
//            ∂τ_i/∂γ_j = (k / |τ_tr|) G_f (δ_ij − t_i t_j),  ∂τ_i/∂ε_kl = μ t_i ∂σ_n/∂ε_kl,  t = τ_tr / |τ_tr|
//   released σ_n,n+1 = 0 (the faces separate): τ = 0.
//
// G_f is the shear modulus of the stiffer of the layer's two states, intact (G) or locked up (the
// densified layer keeps the intact layer's Poisson ratio, so its shear modulus is K_d G / K): the
// stick never makes the failed layer softer in shear than either state, and at failure the
// skeleton's layer-plane shear passes to the friction without a drop in stiffness (the skeleton's
// shear traction at failure becomes τ_n, clipped to (F1)). It is a stick stiffness, not a measured
// modulus: a stiffer one only shortens the stick range τ/G_f of a sliding layer. The return is
// exact (radial in the layer plane, no iteration). Energy per volume: stored |τ|² / (2 G_f);
// dissipated in a step, the trapezoid ½ (τ_n + τ_n+1) · (Δγ − Δτ / G_f) (the frictional slip times
// the mean traction; a release dissipates the stored part). The trapezoid is exact against the
// trapezoidal work ½ (τ_n + τ_n+1) · Δγ of the step.
#pragma once

#include <deal.II/base/symmetric_tensor.h>

namespace anticrack::fem
{
  /// The largest friction coefficient a layer or a material file may give: μ = 2 (a friction angle
  /// of 63°) covers every granular material; beyond it the value is a typo rather than a measurement.
  inline constexpr double max_friction_coefficient = 2;

  /// Parameters of the friction of a failed layer (SI units).
  struct CollapsedFrictionParameters
  {
    /// The layer has the frictional law after failure (its μ was given); false: the Cam-Clay's
    /// residual surface alone carries the failed layer, as in Gaume et al. (2018).
    bool enabled = false;
    double friction_coefficient = 0; ///< μ of (F1), >= 0; 0: a frictionless failed layer
    double shear_modulus = 0;        ///< G_f of (F2) [Pa], > 0 when enabled

    /// μ and G_f = G max(1, K_d / K) from the layer's bulk, shear and lock-up moduli (header, F2).
    /// Throws std::invalid_argument naming the parameter unless μ is finite and in [0, 2], K, G > 0
    /// and K_d >= 0.
    static CollapsedFrictionParameters of_layer(double friction_coefficient, double bulk_modulus,
                                                double shear_modulus, double lock_up_modulus);

    /// True when the layer's failed points take the frictional law.
    [[nodiscard]] bool active() const { return enabled; }
  };

  /// One update of the frictional stress and, if asked, its tangent.
  struct CollapsedFrictionUpdate
  {
    /// τ ⊗ n + n ⊗ τ at the end of the step: only its (i, n) components, i ≠ n, are non-zero.
    dealii::SymmetricTensor<2, 3> stress;
    dealii::SymmetricTensor<4, 3> tangent; ///< ∂stress/∂ε_n+1 (zero unless asked and pressed)
    bool sliding = false;                  ///< the trial state lay beyond (F1)
    double dissipation = 0;                ///< dissipated in the step per volume, the trapezoid (header) [J/m³]
  };

  /// The friction stress at the end of a strain increment `strain_increment` from the layer-plane
  /// traction `previous` (its (i, n) components are τ_n; others ignored), with the normal traction
  /// σ_n = `normal_traction` (compression positive, at the end of the step) [Pa] and its derivative
  /// ∂σ_n/∂ε_n+1 `normal_traction_gradient` (used for the tangent only), on the layer plane of normal
  /// axis `normal_axis` (0, 1 or 2) (header, F2).
  CollapsedFrictionUpdate update_collapsed_friction(const CollapsedFrictionParameters &parameters,
                                                    unsigned int normal_axis,
                                                    const dealii::SymmetricTensor<2, 3> &previous,
                                                    const dealii::SymmetricTensor<2, 3> &strain_increment,
                                                    double normal_traction,
                                                    const dealii::SymmetricTensor<2, 3> &normal_traction_gradient,
                                                    bool with_tangent);

  /// Stored energy per volume of the stick state, |τ|² / (2 G_f) = stress : stress / (4 G_f) [J/m³]
  /// (0 without friction).
  double friction_energy_density(const CollapsedFrictionParameters &parameters,
                                 const dealii::SymmetricTensor<2, 3> &friction_stress);
} // namespace anticrack::fem
