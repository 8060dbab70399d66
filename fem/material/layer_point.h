// The constitutive law of one point of a snowpack layer, as the FE model evaluates it
// (docs/physics.md §2): an elastic slab layer, or a weak layer made of the cohesive Cam-Clay
// skeleton (fem/material/cohesive_cam_clay.h), its densification lock-up and, once it has failed,
// the Coulomb friction of its broken grains (fem/material/collapsed_layer_friction.h), in a cell of
// which a fraction f is intact (the saw removes the rest).
//
// The pieces act in parallel. The cell carries
//
//   σ_carried = f σ_cc − p_d I + s_f                                                  (L1)
//
// (the lock-up and the friction are the contact of the faces of a collapsed or sawn layer, whole in
// a cut cell). When a point of a layer with friction fails, and what its skeleton sees afterwards,
// is the failed-layer law (collapsed_layer_friction.h, "the switch"): from the failure on, the
// skeleton takes the layer's failed parameters (β = 0) once its softening is complete, and it no
// longer sees the layer-plane shear, whose elastic part is frozen at its committed plastic value;
// the friction carries that shear on the skeleton's layer-normal compression.
//
// The law lives here, apart from the mesh, so that one material point can be driven along a
// laboratory path (fem/material/point_simple_shear.h) with exactly the law the PSTs use.
#pragma once

#include "fem/material/cohesive_cam_clay.h"
#include "fem/material/collapsed_layer_friction.h"

#include <deal.II/base/symmetric_tensor.h>

namespace anticrack::fem
{
  /// History of one point.
  struct QuadraturePointState
  {
    /// The total strain ε of the point.
    dealii::SymmetricTensor<2, 3> strain;
    /// Strain, plastic strain, α, p0 of the Cam-Clay part (elastic cells: strain only). Its strain
    /// is ε, except at a failed point of a layer with friction, whose skeleton does not see the
    /// layer-plane shear (fem/material/collapsed_layer_friction.h).
    CamClayState material;
    dealii::SymmetricTensor<2, 3> stress;  ///< stress of the material (without the intact fraction)
    double lock_up_pressure = 0;           ///< p_d of the densification lock-up, included in stress [Pa]
    /// s_f, the friction of the failed layer's grains (fem/material/collapsed_layer_friction.h),
    /// included in stress [Pa].
    dealii::SymmetricTensor<2, 3> friction_stress;
    double dissipation = 0;                ///< plastic and frictional work dissipated so far per volume [J/m³]

    /// The Cam-Clay part of the stress (the lock-up and the friction act in parallel with it).
    dealii::SymmetricTensor<2, 3> cam_clay_stress() const;
    /// Stored elastic energy per volume of the Cam-Clay part, ½ σ_cc : (ε − ε_p) [J/m³].
    double cam_clay_energy_density() const;
    /// Stored energy per volume of the lock-up, p_d² / (2 K_d) [J/m³].
    double lock_up_energy_density(double densification_modulus) const;
  };

  /// The law of one layer.
  struct LayerLaw
  {
    /// false: linear elastic with parameters' K and G (a slab layer); true: cohesive Cam-Clay.
    bool plastic = false;
    CamClayParameters parameters; ///< of the layer's cells (crack band applied)
    /// Of the skeleton of a failed point whose softening is complete: parameters with β = 0 when the
    /// layer has friction, else parameters.
    CamClayParameters broken;
    CollapsedFrictionParameters friction; ///< disabled: Gaume et al.'s (2018) residual surface alone

    /// A slab layer: σ = K tr ε I + 2 G dev ε.
    static LayerLaw elastic(double youngs_modulus, double poisson_ratio);
    /// A weak layer with the Cam-Clay `parameters` and the friction coefficient μ of its failed
    /// grains (NaN: none, the residual surface alone). Throws std::invalid_argument for μ out of
    /// [0, max_friction_coefficient] (CollapsedFrictionParameters::of_layer).
    static LayerLaw cohesive_cam_clay(const CamClayParameters &parameters, double friction_coefficient);
  };

  /// What a cell of intact fraction f carries at a point, (L1).
  dealii::SymmetricTensor<2, 3> carried_stress(const QuadraturePointState &state, double intact_fraction);

  /// True when a point of a layer with friction has failed and takes the friction: its skeleton has
  /// yielded (every plastic step of the collapse law softens), or the saw has cut into its cell.
  bool failed_point(const LayerLaw &law, const QuadraturePointState &previous, bool sawn);

  /// The tangent of one update and the point's stiffest P-wave modulus (for the explicit time step).
  struct LayerPointUpdate
  {
    dealii::SymmetricTensor<4, 3> tangent; ///< ∂σ_carried/∂ε (only when asked)
    double p_wave_modulus = 0;             ///< f (K + 4G/3) + K_d (locked) + G_f (failed) [Pa]
    bool failed = false;                   ///< failed_point() of the step
  };

  /// The state at total strain `strain` from the committed `previous` (header, L1), in a cell of
  /// intact fraction `intact_fraction` (> 0; a cut cell keeps a floor) that the saw has reached when
  /// `sawn`, with the layer plane's normal along `normal_axis`. state.stress is the material's
  /// stress (without f); state.dissipation adds the step's trapezoidal plastic work f σ_cc : Δε_p and
  /// the friction's. Throws ReturnMappingError (fem/material/cohesive_cam_clay.h) when the
  /// skeleton's return mapping fails.
  LayerPointUpdate update_layer_point(const LayerLaw &law, const QuadraturePointState &previous,
                                      const dealii::SymmetricTensor<2, 3> &strain, double intact_fraction,
                                      bool sawn, unsigned int normal_axis, bool with_tangent,
                                      QuadraturePointState &state);
} // namespace anticrack::fem
