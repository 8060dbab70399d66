// DEM/Loading/Test = clump force (Ritter et al. 2020) and tilted gravity (Bobillier et al. 2020):
// both ramp the load on the clump (dem/lab/load_control.h ClumpForceRamp), the second as the
// growing weight of the actuator under tilted gravity.
#include "dem/lab/load_control.h"
#include "dem/lab/measurements.h"
#include "dem/scene/lab_tests.h"
#include "dem/scene/model.h"
#include "dem/scene/scene_entries.h"
#include "util/problems.h"

namespace anticrack::dem
{
  namespace
  {
    using parameters::Loading;

    void declare(VariantEntries &entries)
    {
      for (const char *name : {"Adaptive rate", "Slow rate fraction", "Control interval [steps]", "Rate recovery factor",
                               "Lag tolerance", "Stop strain"})
        entries.shared(name);
    }

    void parse(dealii::ParameterHandler &, Loading &) {} // only shared entries

    /// The ramp, or nullptr when the force (the weight) grows without control or stop.
    std::unique_ptr<LabProtocol> make_ramp(const SceneParameters &scene, DemModel &model, const bool tilted)
    {
      const auto &d = scene.dem;
      if (model.clump < 0)
        return nullptr;
      // Strains are relative to the specimen's initial height (the z extent of its spheres).
      const auto [low, high] = dem::sphere_extent(model.system.particles, 2);
      if (!(tilted || d.loading.adaptive || d.loading.stop_strain > 0))
        return nullptr;
      auto ramp = std::make_unique<dem::ClumpForceRamp>(
        model.clump, model.fixed_particles, d.boundary.clump_force_direction, d.loading.ramp, d.loading.adaptive,
        d.loading.stop_strain * (high - low), tilted ? d.integration.settings.gravity.norm() : 0.0);
      ramp->start(model.system);
      return ramp;
    }

    // ------------------------------------------------------------------------- clump force
    void check_clump_force(const Loading &, const parameters::Dem &, Problems &)
    {
      // What it needs is the clump's (check_clump_sources_and_users in dem/scene/parameters.cpp).
    }

    std::unique_ptr<LabProtocol> make_clump_force(const SceneParameters &scene, DemModel &model)
    {
      return make_ramp(scene, model, false);
    }

    // ---------------------------------------------------------------------- tilted gravity
    void check_tilted_gravity(const Loading &l, const parameters::Dem &d, Problems &problems)
    {
      check_fixed_base_and_clump(l, d, problems);
      if (!(d.integration.settings.gravity.norm() > 0))
        problems.add("DEM/Integration/Gravity [m/s^2]", vec(d.integration.settings.gravity),
                     "must be nonzero for DEM/Loading/Test = tilted gravity (its magnitude is g; the direction "
                     "is DEM/Boundary particles/Clump force direction)");
    }

    std::unique_ptr<LabProtocol> make_tilted_gravity(const SceneParameters &scene, DemModel &model)
    {
      return make_ramp(scene, model, true);
    }
  } // namespace

  LabTest clump_force_test()
  {
    return {{"clump force", "the force F(t) = Fdot t d at its centre of mass (Ritter et al.'s (2020) mixed-mode test).",
             declare},
            parse, check_clump_force, nullptr, make_clump_force, nullptr, ActuatorControl::force};
  }

  LabTest tilted_gravity_test()
  {
    return {{"tilted gravity",
             "Bobillier et al.'s (2020) actuator, whose density grows linearly under gravity of magnitude "
             "|DEM/Integration/Gravity| along d = Clump force direction (tilted by psi), acting on every sphere; "
             "Clump force rate [N/s] is the growth rate of the actuator's weight.",
             declare},
            parse, check_tilted_gravity, nullptr, make_tilted_gravity, nullptr, ActuatorControl::force};
  }
} // namespace anticrack::dem
