// DEM/Loading/Test = triaxial (dem/lab/triaxial_test.h; Elyashiv et al. 2020): six servo walls
// on the domain's faces, isotropic consolidation, then axial strain.
#include "dem/lab/box_walls.h"
#include "dem/lab/triaxial_test.h"
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
      entries.entry("Confining pressure [Pa]", "1e5", Patterns::Double(0),
                    "sigma_c of the triaxial test (Elyashiv et al. 2020: 100, 250, 500 kPa). Units: Pa.");
      entries.entry("Axial strain rate [1/s]", "1", Patterns::Double(0),
                    "Axial strain rate of the triaxial test's loading stage. Units: 1/s.");
      entries.shared("Final axial strain");
      entries.entry("Max servo speed [m/s]", "0", Patterns::Double(0),
                    "Cap on the triaxial servo walls' speed; 0 = 10 x strain rate x the largest box "
                    "length. Units: m/s.");
    }

    void parse(dealii::ParameterHandler &prm, Loading &l)
    {
      l.confining_pressure = prm.get_double("Confining pressure [Pa]");
      l.axial_strain_rate = prm.get_double("Axial strain rate [1/s]");
      l.max_servo_speed = prm.get_double("Max servo speed [m/s]");
    }

    void check(const Loading &l, const parameters::Dem &d, Problems &problems)
    {
      for (int a = 0; a < 3; ++a)
        if (d.domain.periodic[a])
          problems.add("DEM/Domain/Periodic axes", axis_name[a],
                       "the triaxial test walls every face of the domain: no axis may be periodic");
      for (int f = 0; f < 6; ++f)
        if (d.walls.face[f].active)
          problems.add(parameters::Walls::path(f) + "/Active", "true",
                       "the triaxial test adds its own six servo walls; leave DEM/Walls inactive");
      require_positive(problems,
                       {{"Confining pressure [Pa]", l.confining_pressure},
                        {"Axial strain rate [1/s]", l.axial_strain_rate},
                        {"Final axial strain", l.final_axial_strain}},
                       "must be positive for the triaxial test");
    }

    void add_to_model(const SceneParameters &scene, DemModel &model)
    {
      model.box_walls = dem::add_box_walls(model.system, scene.dem.material.contact);
      for (int f = 0; f < 6; ++f)
        model.wall_face.push_back(f);
    }

    std::unique_ptr<LabProtocol> make_protocol(const SceneParameters &scene, DemModel &model)
    {
      const auto &d = scene.dem;
      dem::TriaxialSettings s;
      s.confining_pressure = d.loading.confining_pressure;
      s.axial_strain_rate = d.loading.axial_strain_rate;
      s.final_axial_strain = d.loading.final_axial_strain;
      const Vec3 box = model.system.domain.length();
      s.max_servo_speed =
        d.loading.max_servo_speed > 0 ? d.loading.max_servo_speed : 10 * s.axial_strain_rate * box.maxCoeff();
      auto triaxial = std::make_unique<dem::TriaxialTest>(model.system, model.box_walls, s);
      triaxial->start(model.system);
      return triaxial;
    }
  } // namespace

  LabTest triaxial_test()
  {
    return {{"triaxial",
             "Elyashiv et al.'s (2020) test in a box of six servo walls (added on the domain's faces; DEM/Walls "
             "must be inactive and no axis periodic): isotropic consolidation to Confining pressure [Pa], then the "
             "z walls close at Axial strain rate [1/s] to Final axial strain while the lateral walls hold the "
             "confinement.",
             declare},
            parse,
            check,
            add_to_model,
            make_protocol,
            wall_tests_have_no_loading_angles,
            ActuatorControl::force};
  }
} // namespace anticrack::dem
