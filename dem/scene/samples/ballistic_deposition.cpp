// DEM/Sample/Type = ballistic deposition (dem/sample/ballistic_deposition.h) into the DEM/Domain
// box, optionally with Bobillier et al.'s (2020) actuator layer on top.
#include "dem/sample/ballistic_deposition.h"
#include "dem/scene/model.h"
#include "dem/scene/sample_types.h"
#include "dem/scene/scene_entries.h"
#include "util/problems.h"

#include <algorithm>
#include <nlohmann/json.hpp>

#include <ostream>

namespace anticrack::dem
{
  namespace
  {
    using parameters::Sample;

    void declare(VariantEntries &entries)
    {
      entries.shared("Radius [m]");
      entries.shared("Initial velocity amplitude [m/s]");
      entries.shared("Particle count");
      entries.entry("Deposition rule", "sticky", Patterns::Selection("sticky|rolling"),
                    "`sticky`: a falling sphere stops at its first contact (bulk solid fraction "
                    "~0.15); `rolling`: it rolls to a three-point rest (~0.58) (ballistic "
                    "deposition only).");
      entries.shared("Radius half width [m]");
      entries.entry("Actuator layer count", "0", Patterns::Integer(0),
                    "N_a > 0: after the deposit, N_a spheres of radius Actuator layer radius [m] are "
                    "dropped on top by the rolling rule (Bobillier et al.'s (2020) cohesionless actuator layer) and "
                    "become the loading clump (DEM/Boundary particles/Clump above [m] and Actuator "
                    "thickness [mean radii] must then be empty); they are bonded to the layer where "
                    "they touch it (ballistic deposition only).");
      entries.entry("Actuator layer radius [m]", "0.01", Patterns::Double(0),
                    "Radius of the actuator layer's spheres (Bobillier et al. 2020: 10 mm). Units: m.");
    }

    void parse(dealii::ParameterHandler &prm, Sample &s)
    {
      s.rolling = prm.get("Deposition rule") == "rolling";
      s.actuator_count = prm.get_integer("Actuator layer count");
      s.actuator_radius = prm.get_double("Actuator layer radius [m]");
    }

    void check(const Sample &s, const parameters::Dem &d, Problems &problems)
    {
      const std::string why_type = for_sample_type(s);
      if (d.domain.periodic[0] != d.domain.periodic[1] || d.domain.periodic[2])
      {
        std::string axes;
        for (int a = 0; a < 3; ++a)
          if (d.domain.periodic[a])
            axes += std::string(axes.empty() ? "" : ", ") + axis_name[a];
        problems.add("DEM/Domain/Periodic axes", axes.empty() ? "(none)" : axes,
                     "must be x, y (laterally periodic specimen) or empty (sides opened after "
                     "deposition)" + why_type + "; z is never periodic: spheres are dropped onto "
                     "the base z = lower z");
      }
      check_radius_distribution(s, problems);
      const Vec3 length = d.domain.length();
      const double r_max = s.radius + s.radius_half_width;
      const double needed = std::max(8 * s.radius, 2 * (2 * r_max + verlet_skin(d.integration, s.radius)));
      for (int a = 0; a < 2; ++a)
        if (s.radius > 0 && length[a] > 0 && !(length[a] >= needed))
          problems.add("DEM/Domain/Upper corner [m]", vec(d.domain.upper),
                       "the box along " + std::string(axis_name[a]) + " (" + format_number(length[a]) +
                         " m) must be at least " + format_number(needed) +
                         " m (4 mean diameters and 2 (2 R_max + skin))" + why_type);
    }

    void build(const SceneParameters &scene, DemModel &model)
    {
      dem::DemSystem &system = model.system;
      const auto &d = scene.dem;
      dem::BallisticDepositionSpec spec;
      spec.rule = d.sample.rolling ? dem::DepositionRule::rolling : dem::DepositionRule::sticky;
      spec.box_lower = d.domain.lower;
      spec.box_upper = d.domain.upper;
      spec.particle_count = d.sample.particle_count;
      spec.radius.mean = d.sample.radius;
      spec.radius.half_width = d.sample.radius_half_width;
      spec.material = 0;
      spec.seed = d.seed;
      const Index first = system.particles.size();
      model.ballistic_deposition = dem::add_ballistic_deposit(system, spec);
      if (d.sample.actuator_count > 0)
      {
        // Bobillier et al.'s (2020) actuator: a cohesionless (rolling) deposit of larger spheres on the layer.
        dem::BallisticDepositionSpec actuator = spec;
        actuator.rule = dem::DepositionRule::rolling;
        actuator.particle_count = d.sample.actuator_count;
        actuator.radius.mean = d.sample.actuator_radius;
        actuator.radius.half_width = 0;
        actuator.seed = d.seed + 0x5eed;
        model.actuator_layer_first = system.particles.size();
        dem::add_ballistic_deposit(system, actuator);
      }
      open_axes_the_scene_does_not_wrap(d, system);
      add_random_velocities(d, system, first);
    }

    void describe(std::ostream &s, const SceneParameters &scene, const DemModel &model)
    {
      const Sample &sample = scene.dem.sample;
      const auto &r = *model.ballistic_deposition;
      s << "ballistic deposition (" << (sample.rolling ? "rolling" : "sticky") << "), N = " << sample.particle_count
        << ", R = " << sample.radius << " +- " << sample.radius_half_width << " m\n"
        << "  generator report    bulk solid fraction " << r.solid_fraction_bulk << " (z in [" << r.bulk_lower
        << ", " << r.bulk_upper << "] m), mean contacts " << r.mean_contacts << " (bulk), "
        << r.mean_contacts_all << " (all),\n                      height " << r.height << " m, "
        << r.on_base << " on the base, " << r.fallbacks << " sticky fallbacks"
        << "\n                      (`check` runs the generator: the sample is the one `run` builds)";
    }

    void summarize(nlohmann::ordered_json &sample, const SceneParameters &scene, const DemModel &model)
    {
      const auto &r = *model.ballistic_deposition;
      sample["rule"] = scene.dem.sample.rolling ? "rolling" : "sticky";
      sample["particles"] = r.particles;
      sample["fallbacks"] = r.fallbacks;
      sample["on_base"] = r.on_base;
      sample["solid_fraction_bulk"] = r.solid_fraction_bulk;
      sample["mean_contacts"] = r.mean_contacts;
      sample["mean_contacts_all"] = r.mean_contacts_all;
      sample["height_m"] = r.height;
      sample["bulk_lower_m"] = r.bulk_lower;
      sample["bulk_upper_m"] = r.bulk_upper;
    }
  } // namespace

  SampleType ballistic_deposition_sample()
  {
    return {{"ballistic deposition",
            "N spheres dropped one by one along -z onto the base z = DEM/Domain lower z inside the DEM/Domain "
            "box, laterally periodic while depositing; the domain's upper z is raised to the deposit's top if "
            "needed; with DEM/Domain/Periodic axes = x, y the specimen stays laterally periodic (Ritter et al. "
            "2020), with none its sides are opened after deposition, like a box whose side walls are removed "
            "(Bobillier et al. 2020); bonds use DEM/Bond/Gap tolerance.",
            declare}, parse, check, build, describe, summarize};
  }
} // namespace anticrack::dem
