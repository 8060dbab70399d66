// DEM/Loading/Test = simple shear (dem/lab/simple_shear.h; Mede et al. 2018): the clump is a
// platen pressed at constant normal stress, then driven along +x.
#include "dem/lab/measurements.h"
#include "dem/lab/simple_shear.h"
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
      entries.shared("Control interval [steps]");
      entries.entry("Normal stress [Pa]", "1e4", Patterns::Double(0),
                    "sigma_n: compressive normal stress on the platen (simple shear). Units: Pa.");
      entries.entry("Shear velocity [m/s]", "1e-3", Patterns::Double(0),
                    "v: platen velocity along +x while shearing (simple shear). Units: m/s.");
      entries.entry("Consolidation time [s]", "1e-3", Patterns::Double(0),
                    "Duration of the normal-force ramp before shearing (simple shear). Units: s.");
      entries.entry("Final shear strain", "0.1", Patterns::Double(0),
                    "gamma = u_x / H at which the simple shear test ends. Dimensionless.");
    }

    void parse(dealii::ParameterHandler &prm, Loading &l)
    {
      l.normal_stress = prm.get_double("Normal stress [Pa]");
      l.shear_velocity = prm.get_double("Shear velocity [m/s]");
      l.consolidation_time = prm.get_double("Consolidation time [s]");
      l.final_shear_strain = prm.get_double("Final shear strain");
    }

    void check(const Loading &l, const parameters::Dem &d, Problems &problems)
    {
      check_fixed_base_and_clump(l, d, problems);
      require_positive(problems,
                       {{"Normal stress [Pa]", l.normal_stress},
                        {"Shear velocity [m/s]", l.shear_velocity},
                        {"Consolidation time [s]", l.consolidation_time},
                        {"Final shear strain", l.final_shear_strain}},
                       "must be positive for simple shear");
      if (!d.domain.periodic[0])
        problems.add("DEM/Domain/Periodic axes", "(x not periodic)",
                     "simple shear drives the platen along x: the specimen must be periodic along x");
      if (l.adaptive)
        problems.add("DEM/Loading/Adaptive rate", "true",
                     "adapts a force ramp; simple shear is displacement-controlled (set false)");
    }

    std::unique_ptr<LabProtocol> make_protocol(const SceneParameters &scene, DemModel &model)
    {
      const auto &d = scene.dem;
      if (model.clump < 0)
        return nullptr;
      // Strains are relative to the specimen's initial height (the z extent of its spheres).
      const auto [low, high] = dem::sphere_extent(model.system.particles, 2);
      dem::SimpleShearSettings s;
      s.normal_stress = d.loading.normal_stress;
      s.area = model.base_area;
      s.height = high - low;
      s.shear_velocity = d.loading.shear_velocity;
      s.consolidation_time = d.loading.consolidation_time;
      s.acceleration_time = 0.1 * d.loading.consolidation_time;
      s.final_shear_strain = d.loading.final_shear_strain;
      s.interval = d.loading.ramp.interval;
      auto shear = std::make_unique<dem::SimpleShear>(model.clump, model.fixed_particles, s);
      shear->start(model.system);
      return shear;
    }
  } // namespace

  LabTest simple_shear_test()
  {
    return {{"simple shear",
             "Mede et al.'s (2018) test at constant normal stress: the clump (a platen) is pressed with Normal "
             "stress [Pa], then driven along +x at Shear velocity [m/s], free along z, to Final shear strain.",
             declare},
            parse,
            check,
            nullptr,
            make_protocol,
            "campaigns run load-controlled tests at loading angles; simple shear has none",
            ActuatorControl::shear_displacement};
  }
} // namespace anticrack::dem
