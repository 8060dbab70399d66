// Coulomb friction of a collapsed weak layer (docs/physics.md §2, "Friction of the collapsed layer").
//
// Once a weak layer has collapsed and its pores are closed (the lock-up of
// fem/material/cohesive_cam_clay.h, p_d = K_d ⟨−tr ε − ε_d⟩ > 0), the slab rests on broken grains in
// contact. Its bond skeleton keeps only the residual Cam-Clay strength, but the grain contacts carry
// shear by friction on the pressure that closes them. This model adds that resistance as a shear
// traction τ on the layer plane (normal n), in parallel with the Cam-Clay stress and the lock-up:
//
//   σ = σ_cc − p_d I + (τ ⊗ n + n ⊗ τ),   τ ⊥ n,
//   |τ| <= μ p_d                                                              (F1)
//
// (F1) is Coulomb's law of the crack faces with the lock-up pressure as their normal traction. It
// is written on the layer plane, not on the deviator: a collapsing layer is compacted in uniaxial
// strain, whose deviatoric part is not slip and must not use up the friction. The law is that of
// an elastic–perfectly frictional (stick–slip) interface, per volume of the collapsed band, with
// the layer-plane shear strain γ_i = 2 ε_in (i ⊥ n):
//
//   trial    τ_tr = τ_n + G_f Δγ,       G_f = K_d G / K                                  (F2)
//   stick    |τ_tr| <= k = μ p_d,n+1:  τ = τ_tr,           ∂τ_i/∂γ_j = G_f δ_ij
//   slide    |τ_tr|  > k:               τ = (k / |τ_tr|) τ_tr,
//            ∂τ_i/∂γ_j = (k / |τ_tr|) G_f (δ_ij − t_i t_j),  ∂τ_i/∂ε_kk = −μ K_d t_i,  t = τ_tr / |τ_tr|
//   released p_d,n+1 = 0 (the faces separate, or the layer has not locked): τ = 0.
//
// G_f is the shear stiffness of the stick state: the densified layer keeps the Poisson ratio of the
// intact layer, so its shear modulus relates to the lock-up modulus K_d as G does to K (F2). The
// return is exact (radial in the layer plane, no iteration). Energy per volume: stored
// |τ|² / (2 G_f); dissipated in a step, the trapezoid ½ (τ_n + τ_n+1) · (Δγ − Δτ / G_f) (the
// frictional slip times the mean traction; a release dissipates the stored part). The trapezoid is
// exact against the trapezoidal work ½ (τ_n + τ_n+1) · Δγ of the step.
#pragma once

#include <deal.II/base/symmetric_tensor.h>

namespace anticrack::fem
{
  /// Parameters of the friction of a collapsed layer (SI units).
  struct CollapsedFrictionParameters
  {
    double friction_coefficient = 0; ///< μ of (F1), >= 0; 0: no friction (τ ≡ 0)
    double shear_modulus = 0;        ///< G_f of (F2) [Pa], > 0 when μ > 0
    double lock_up_modulus = 0;      ///< K_d of the lock-up [Pa] (dk/dε = −√3 μ K_d I)

    /// μ, G_f = K_d G / K and K_d from the layer's moduli (header, F2). Throws std::invalid_argument
    /// naming the parameter unless μ is finite and in [0, 2], and K, G > 0, K_d >= 0.
    static CollapsedFrictionParameters of_layer(double friction_coefficient, double bulk_modulus,
                                                double shear_modulus, double lock_up_modulus);

    /// True when the friction acts at all (μ > 0 and a lock-up to act on).
    [[nodiscard]] bool active() const { return friction_coefficient > 0 && lock_up_modulus > 0; }
  };

  /// One update of the frictional stress and, if asked, its tangent.
  struct CollapsedFrictionUpdate
  {
    /// τ ⊗ n + n ⊗ τ at the end of the step: only its (i, n) components, i ≠ n, are non-zero.
    dealii::SymmetricTensor<2, 3> stress;
    dealii::SymmetricTensor<4, 3> tangent; ///< ∂stress/∂ε_n+1 (zero unless asked and locked)
    bool sliding = false;                  ///< the trial state lay beyond (F1)
    double dissipation = 0;                ///< dissipated in the step per volume, the trapezoid (header) [J/m³]
  };

  /// The friction stress at the end of a strain increment `strain_increment` from `previous` (the
  /// last step's stress) with the lock-up pressure `lock_up_pressure` (p_d at the end of the step)
  /// [Pa], on the layer plane of normal axis `normal_axis` (0, 1 or 2) (header, F2).
  CollapsedFrictionUpdate update_collapsed_friction(const CollapsedFrictionParameters &parameters,
                                                    unsigned int normal_axis,
                                                    const dealii::SymmetricTensor<2, 3> &previous,
                                                    const dealii::SymmetricTensor<2, 3> &strain_increment,
                                                    double lock_up_pressure, bool with_tangent);

  /// Stored energy per volume of the stick state, |τ|² / (2 G_f) = stress : stress / (4 G_f) [J/m³]
  /// (0 without friction).
  double friction_energy_density(const CollapsedFrictionParameters &parameters,
                                 const dealii::SymmetricTensor<2, 3> &friction_stress);
} // namespace anticrack::fem
