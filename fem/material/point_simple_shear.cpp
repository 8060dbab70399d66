// A weak-layer point in the DEM's simple shear (see the header).
#include "fem/material/point_simple_shear.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace anticrack::fem
{
  using namespace dealii;

  namespace
  {
    constexpr unsigned int normal_axis = 2;

    struct Trial
    {
      QuadraturePointState state;
      double normal_stress = 0; ///< −σ_zz [Pa]
      bool failed = false;
    };

    Trial evaluate(const LayerLaw &law, const QuadraturePointState &previous, double normal_strain, double shear_strain)
    {
      SymmetricTensor<2, 3> strain;
      strain[2][2] = -normal_strain;
      strain[0][2] = 0.5 * shear_strain;
      Trial trial;
      trial.state = previous;
      trial.failed = update_layer_point(law, previous, strain, 1, false, normal_axis, false, trial.state).failed;
      trial.normal_stress = -trial.state.stress[2][2];
      return trial;
    }

    /// The step to shear strain γ: the compaction e = −ε_zz at which −σ_zz = σ_n, searched from the
    /// previous one (the first equilibrium in the direction the imbalance asks for), then bisected
    /// to a relative tolerance of 1e-10 in the stress.
    Trial equilibrium(const LayerLaw &law, const QuadraturePointState &previous, double previous_compaction,
                      double shear_strain, double normal_stress)
    {
      const double tolerance = 1e-10 * normal_stress;
      Trial at = evaluate(law, previous, previous_compaction, shear_strain);
      double e = previous_compaction;
      if (std::abs(at.normal_stress - normal_stress) <= tolerance)
        return at;
      // Towards compaction when the point carries too little, else back; the first step is the
      // elastic one (P-wave modulus), doubled until the imbalance changes sign.
      const double direction = at.normal_stress < normal_stress ? 1 : -1;
      const double modulus = law.parameters.bulk_modulus + 4 * law.parameters.shear_modulus / 3;
      double step = std::abs(at.normal_stress - normal_stress) / modulus;
      double inner = e;
      double outer = e;
      Trial outer_trial = at;
      for (;;)
      {
        outer = e + direction * step;
        if (outer >= 1 || outer <= -1)
          throw std::runtime_error("point_simple_shear: no compaction in (-1, 1) carries the normal stress " +
                                   std::to_string(normal_stress) + " Pa at shear strain " + std::to_string(shear_strain));
        outer_trial = evaluate(law, previous, outer, shear_strain);
        if ((outer_trial.normal_stress - normal_stress) * direction >= 0)
          break;
        inner = outer;
        step *= 2;
      }
      // Bisect between inner (short of σ_n) and outer (at or beyond it).
      for (int iteration = 0; iteration < 200; ++iteration)
      {
        if (std::abs(outer_trial.normal_stress - normal_stress) <= tolerance)
          break;
        const double middle = 0.5 * (inner + outer);
        const Trial middle_trial = evaluate(law, previous, middle, shear_strain);
        if ((middle_trial.normal_stress - normal_stress) * direction >= 0)
        {
          outer = middle;
          outer_trial = middle_trial;
        }
        else
          inner = middle;
        if (std::abs(outer - inner) <= 1e-15)
          break;
      }
      return outer_trial;
    }
  } // namespace

  std::vector<PointSimpleShearSample> point_simple_shear(const LayerLaw &law, const PointSimpleShearSettings &settings)
  {
    if (!(settings.normal_stress > 0) || !std::isfinite(settings.normal_stress))
      throw std::invalid_argument("point_simple_shear: normal_stress must be finite and > 0 Pa");
    if (!(settings.final_shear_strain > 0) || !std::isfinite(settings.final_shear_strain))
      throw std::invalid_argument("point_simple_shear: final_shear_strain must be finite and > 0");
    if (settings.consolidation_steps < 1 || settings.shear_steps < 1)
      throw std::invalid_argument("point_simple_shear: consolidation_steps and shear_steps must be >= 1");

    QuadraturePointState state;
    if (law.plastic)
      state.material = CamClayState::initial(law.parameters);
    std::vector<PointSimpleShearSample> samples;
    double compaction = 0;
    const auto record = [&](const Trial &trial, double shear_strain) {
      state = trial.state;
      compaction = -state.strain[2][2];
      samples.push_back({shear_strain, compaction, state.stress[0][2], trial.normal_stress, state.material.p0, trial.failed});
    };
    for (unsigned int k = 1; k <= settings.consolidation_steps; ++k)
      record(equilibrium(law, state, compaction, 0, settings.normal_stress * k / settings.consolidation_steps), 0);
    for (unsigned int k = 1; k <= settings.shear_steps; ++k)
    {
      const double shear_strain = settings.final_shear_strain * k / settings.shear_steps;
      record(equilibrium(law, state, compaction, shear_strain, settings.normal_stress), shear_strain);
    }
    return samples;
  }
} // namespace anticrack::fem
