// DEM/Loading/Test = platen compression (dem/lab/platen_compression_test.h; Zhao & Feng 2022):
// the walls z- and z+ approach each other, uniaxial compression or the Brazilian disc test.
#include "dem/lab/platen_compression_test.h"
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
      entries.shared("Final axial strain");
      entries.entry("Platen speed [m/s]", "0.01", Patterns::Double(0),
                    "Speed of each platen towards the other (platen compression). Units: m/s.");
      entries.entry("Post-peak fraction", "0.5", Patterns::Double(0, 1),
                    "The platen test ends once the force has fallen below this fraction of its peak. "
                    "Dimensionless.");
    }

    void parse(dealii::ParameterHandler &prm, Loading &l)
    {
      l.platen_speed = prm.get_double("Platen speed [m/s]");
      l.post_peak_fraction = prm.get_double("Post-peak fraction");
    }

    void check(const Loading &l, const parameters::Dem &d, Problems &problems)
    {
      if (!d.walls.face[4].active || !d.walls.face[5].active)
        problems.add("DEM/Walls/z- and z+/Active", "false",
                     "platen compression drives the walls z- and z+: activate both");
      if (!(l.platen_speed > 0))
        problems.add("DEM/Loading/Platen speed [m/s]", l.platen_speed, "must be positive");
      if (!(l.post_peak_fraction > 0))
        problems.add("DEM/Loading/Post-peak fraction", l.post_peak_fraction, "must be in (0, 1)");
    }

    std::unique_ptr<LabProtocol> make_protocol(const SceneParameters &scene, DemModel &model)
    {
      const auto &d = scene.dem;
      dem::PlatenSettings s;
      s.platen_speed = d.loading.platen_speed;
      s.post_peak_fraction = d.loading.post_peak_fraction;
      s.max_strain = d.loading.final_axial_strain;
      // The platens are the walls on the z- and z+ faces (face indices 4 and 5).
      Index lower = -1, upper = -1;
      for (std::size_t w = 0; w < model.wall_face.size(); ++w)
      {
        if (model.wall_face[w] == 4)
          lower = static_cast<Index>(w);
        if (model.wall_face[w] == 5)
          upper = static_cast<Index>(w);
      }
      auto platens = std::make_unique<dem::PlatenCompression>(model.system, lower, upper, s);
      platens->start(model.system);
      return platens;
    }
  } // namespace

  LabTest platen_compression_test()
  {
    return {{"platen compression",
             "Zhao & Feng's (2022) uniaxial compression or Brazilian disc test: DEM/Walls/z- and z+ (must be "
             "active) move towards each other at Platen speed [m/s] each, until the force has fallen below "
             "Post-peak fraction of its peak (or Final axial strain).",
             declare},
            parse,
            check,
            nullptr,
            make_protocol,
            wall_tests_have_no_loading_angles,
            ActuatorControl::force};
  }
} // namespace anticrack::dem
