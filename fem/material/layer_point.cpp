// The law of one layer point (see the header).
#include "fem/material/layer_point.h"

#include <algorithm>
#include <cmath>

namespace anticrack::fem
{
  using namespace dealii;

  namespace
  {
    SymmetricTensor<4, 3> isotropic_elasticity(double bulk_modulus, double shear_modulus)
    {
      const SymmetricTensor<2, 3> one = unit_symmetric_tensor<3>();
      return bulk_modulus * outer_product(one, one) +
             2 * shear_modulus * (identity_tensor<3>() - outer_product(one, one) / 3.);
    }
  } // namespace

  SymmetricTensor<2, 3> QuadraturePointState::cam_clay_stress() const
  {
    return stress + lock_up_pressure * unit_symmetric_tensor<3>() - friction_stress;
  }

  double QuadraturePointState::cam_clay_energy_density() const
  {
    return 0.5 * (cam_clay_stress() * (material.strain - material.plastic_strain));
  }

  double QuadraturePointState::lock_up_energy_density(double densification_modulus) const
  {
    return densification_modulus > 0 ? lock_up_pressure * lock_up_pressure / (2 * densification_modulus) : 0;
  }

  LayerLaw LayerLaw::elastic(double youngs_modulus, double poisson_ratio)
  {
    LayerLaw law;
    law.parameters.set_elastic_moduli(youngs_modulus, poisson_ratio);
    law.broken = law.parameters;
    return law;
  }

  LayerLaw LayerLaw::cohesive_cam_clay(const CamClayParameters &parameters, double friction_coefficient)
  {
    LayerLaw law;
    law.plastic = true;
    law.parameters = parameters;
    law.broken = parameters;
    if (!std::isnan(friction_coefficient))
    {
      law.friction = CollapsedFrictionParameters::of_layer(friction_coefficient, parameters.bulk_modulus,
                                                           parameters.shear_modulus, parameters.densification_modulus);
      law.broken.beta = 0; // the fully broken skeleton has no tension
    }
    return law;
  }

  SymmetricTensor<2, 3> carried_stress(const QuadraturePointState &state, double intact_fraction)
  {
    return intact_fraction * state.cam_clay_stress() - state.lock_up_pressure * unit_symmetric_tensor<3>() +
           state.friction_stress;
  }

  bool failed_point(const LayerLaw &law, const QuadraturePointState &previous, bool sawn)
  {
    return law.friction.active() && (previous.material.plastic_strain.norm() > 0 || sawn);
  }

  LayerPointUpdate update_layer_point(const LayerLaw &law, const QuadraturePointState &previous,
                                      const SymmetricTensor<2, 3> &strain, double intact_fraction, bool sawn,
                                      unsigned int normal_axis, bool with_tangent, QuadraturePointState &state)
  {
    const CamClayParameters &parameters = law.parameters;
    LayerPointUpdate update;
    state.strain = strain;
    state.friction_stress = 0;
    if (!law.plastic)
    {
      // σ = K tr ε I + 2 G dev ε, without forming the 4th-order tensor unless it is needed (the
      // explicit loop spends most of its time in elastic slab cells).
      state.material.strain = strain;
      state.lock_up_pressure = 0;
      state.stress = 2 * parameters.shear_modulus * deviator(strain) +
                     parameters.bulk_modulus * trace(strain) * unit_symmetric_tensor<3>();
      if (with_tangent)
        update.tangent = intact_fraction * isotropic_elasticity(parameters.bulk_modulus, parameters.shear_modulus);
      update.p_wave_modulus = intact_fraction * (parameters.bulk_modulus + 4 * parameters.shear_modulus / 3);
      state.dissipation = previous.dissipation;
      return update;
    }

    // The switch uses the committed state, so a step's Newton iterations see one law. Its tension
    // β p0 falls with p0 as the bonds break; the last of it, β p0_floor, goes once the softening is
    // complete (p0 at the floor): the fully broken skeleton has β = 0.
    const bool failed = failed_point(law, previous, sawn);
    const bool broken = failed && previous.material.p0 <= parameters.p0_floor * (1 + 1e-9);
    const CamClayParameters &skeleton = broken ? law.broken : parameters;
    const unsigned int in_plane[2] = {(normal_axis + 1) % 3, (normal_axis + 2) % 3};
    SymmetricTensor<2, 3> skeleton_strain = strain;
    if (failed)
      for (const unsigned int i : in_plane)
        skeleton_strain[i][normal_axis] = previous.material.plastic_strain[i][normal_axis];
    if (with_tangent)
    {
      const CamClayTangentUpdate result = update_stress_and_tangent(skeleton, previous.material, skeleton_strain);
      state.material = result.update.state;
      state.stress = result.update.stress;
      state.lock_up_pressure = result.update.densification_pressure;
      update.tangent = result.tangent;
      if (failed) // ∂ε_skeleton/∂ε drops the layer-plane shear
        for (unsigned int k = 0; k < 3; ++k)
          for (unsigned int l = k; l < 3; ++l)
            for (const unsigned int i : in_plane)
              update.tangent[k][l][i][normal_axis] = 0;
    }
    else
    {
      const CamClayUpdate result = update_stress(skeleton, previous.material, skeleton_strain);
      state.material = result.state;
      state.stress = result.stress;
      state.lock_up_pressure = result.densification_pressure;
    }
    const bool locked = state.lock_up_pressure > 0;
    // What the cell carries without the friction, and its tangent: the fraction f of the Cam-Clay
    // part and the whole lock-up, (L1).
    if (with_tangent)
    {
      update.tangent *= intact_fraction;
      if (locked)
        update.tangent += (1 - intact_fraction) * parameters.densification_modulus *
                          outer_product(unit_symmetric_tensor<3>(), unit_symmetric_tensor<3>());
    }
    // The friction of the failed layer's grains on the skeleton's layer-normal compression, in
    // parallel (whole in a cut cell, like the lock-up). At the switch it starts from the skeleton's
    // layer-plane shear of the step before (clipped to Coulomb's limit).
    double friction_dissipation = 0;
    if (failed)
    {
      const SymmetricTensor<2, 3> pressed = carried_stress(state, intact_fraction);
      SymmetricTensor<2, 3> normal_traction_gradient;
      if (with_tangent)
        for (unsigned int k = 0; k < 3; ++k)
          for (unsigned int l = k; l < 3; ++l)
            normal_traction_gradient[k][l] = -update.tangent[normal_axis][normal_axis][k][l];
      // The skeleton's layer-plane shear is zero once failed, so this is the friction's own τ_n,
      // except at the switch, where it is the skeleton's whole shear (the step before the switch
      // carried it whole: a cell that the saw reaches switches in that same step).
      const SymmetricTensor<2, 3> previous_traction = previous.friction_stress + previous.cam_clay_stress();
      const CollapsedFrictionUpdate slip =
        update_collapsed_friction(law.friction, normal_axis, previous_traction, strain - previous.strain,
                                  std::max(-pressed[normal_axis][normal_axis], 0.), normal_traction_gradient,
                                  with_tangent);
      state.friction_stress = slip.stress;
      state.stress += slip.stress;
      friction_dissipation = slip.dissipation;
      if (with_tangent)
        update.tangent += slip.tangent;
    }
    update.failed = failed;
    update.p_wave_modulus = intact_fraction * (parameters.bulk_modulus + 4 * parameters.shear_modulus / 3) +
                            (locked ? parameters.densification_modulus : 0.) +
                            (failed ? law.friction.shear_modulus : 0.);
    // Dissipation of this step: trapezoidal f σ_cc : Δε_p (the lock-up does no plastic work), and the
    // frictional slip's.
    const SymmetricTensor<2, 3> plastic_increment = state.material.plastic_strain - previous.material.plastic_strain;
    state.dissipation = previous.dissipation +
                        intact_fraction * 0.5 * (state.cam_clay_stress() + previous.cam_clay_stress()) * plastic_increment +
                        friction_dissipation;
    return update;
  }
} // namespace anticrack::fem
