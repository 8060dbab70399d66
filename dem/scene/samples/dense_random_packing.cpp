// DEM/Sample/Type = dense random packing (dem/sample/dense_packing.h) filling the DEM/Domain box,
// optionally carved to the Brazilian test's disc (dem/sample/specimen_carving.h).
#include "dem/contact/contact_law.h"
#include "dem/sample/dense_packing.h"
#include "dem/sample/specimen_carving.h"
#include "dem/scene/model.h"
#include "dem/scene/sample_types.h"
#include "dem/scene/scene_entries.h"
#include "util/problems.h"

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
      entries.shared("Radius half width [m]");
      entries.entry("Formation friction", "0", Patterns::Double(0),
                    "mu while the dense random packing forms (0: dense, ~1: loose); the run uses "
                    "DEM/Material/Friction coefficient (dense random packing only). Dimensionless.");
      entries.entry("Packing pressure [Pa]", "1e5", Patterns::Double(0),
                    "Mean stress at which the dense random packing is complete, in (0, 1e-2 x "
                    "contact modulus) (dense random packing only). Units: Pa.");
      entries.entry("Disc diameter [m]", "0", Patterns::Double(0),
                    "D > 0: keep only the spheres within the disc of diameter D, axis along y, "
                    "centred in the domain's x-z section (Brazilian test; dense random packing "
                    "only). 0 = no carving. Units: m.");
    }

    void parse(dealii::ParameterHandler &prm, Sample &s)
    {
      s.formation_friction = prm.get_double("Formation friction");
      s.packing_pressure = prm.get_double("Packing pressure [Pa]");
      s.disc_diameter = prm.get_double("Disc diameter [m]");
    }

    void check(const Sample &s, const parameters::Dem &d, Problems &problems)
    {
      const std::string why_type = for_sample_type(s);
      check_radius_distribution(s, problems);
      const double modulus = dem::contact_law_modulus(d.material.contact);
      if (!(s.packing_pressure > 0 && s.packing_pressure < 1e-2 * modulus))
        problems.add("DEM/Sample/Packing pressure [Pa]", s.packing_pressure,
                     "must be in (0, 1e-2 x the contact modulus = " + format_number(1e-2 * modulus) + ")" +
                       why_type);
      const Vec3 length = d.domain.length();
      if (s.disc_diameter > 0 &&
          (s.disc_diameter > length[0] * (1 + 1e-12) || s.disc_diameter > length[2] * (1 + 1e-12)))
        problems.add("DEM/Sample/Disc diameter [m]", s.disc_diameter,
                     "must fit in the domain's x-z section (" + format_number(length[0]) + " x " +
                       format_number(length[2]) + " m)");
    }

    void build(const SceneParameters &scene, DemModel &model)
    {
      dem::DemSystem &system = model.system;
      const auto &d = scene.dem;
      dem::DensePackingSpec spec;
      spec.particle_count = d.sample.particle_count;
      spec.radius.mean = d.sample.radius;
      spec.radius.half_width = d.sample.radius_half_width;
      spec.box_lower = d.domain.lower;
      spec.box_upper = d.domain.upper;
      spec.periodic = d.domain.periodic;
      spec.formation_friction = d.sample.formation_friction;
      spec.target_pressure = d.sample.packing_pressure;
      spec.material = 0;
      spec.seed = d.seed;
      model.dense_packing = dem::add_dense_packing(system, spec);
      if (d.sample.disc_diameter > 0)
      {
        // The Brazilian disc: axis along y, centred in the x-z section.
        const Vec3 centre = 0.5 * (system.domain.lower + system.domain.upper);
        dem::carve_cylinder(system, 1, centre, 0.5 * d.sample.disc_diameter);
      }
      add_random_velocities(d, system, 0);
    }

    void describe(std::ostream &s, const SceneParameters &scene, const DemModel &model)
    {
      const Sample &sample = scene.dem.sample;
      const auto &r = *model.dense_packing;
      s << "dense random packing, N = " << sample.particle_count << ", R = " << sample.radius << " +- "
        << sample.radius_half_width << " m, formation friction " << sample.formation_friction << "\n"
        << "  generator report    solid fraction " << r.solid_fraction << ", coordination " << r.coordination
        << " (mechanical " << r.mechanical_coordination << ", " << r.rattlers << " rattlers), p = " << r.pressure
        << " Pa after " << r.steps << " steps, mean radius " << r.mean_radius << " m";
      if (sample.disc_diameter > 0)
        s << "\n                      disc of diameter " << sample.disc_diameter << " m carved (axis y): "
          << model.system.particles.size() << " spheres kept";
      s << "\n                      (`check` runs the generator: the sample is the one `run` builds)";
    }

    void summarize(nlohmann::ordered_json &sample, const SceneParameters &scene, const DemModel &model)
    {
      const auto &r = *model.dense_packing;
      sample["formation_friction"] = scene.dem.sample.formation_friction;
      sample["volume_fraction"] = r.solid_fraction;
      sample["coordination"] = r.coordination;
      sample["mechanical_coordination"] = r.mechanical_coordination;
      sample["rattlers"] = r.rattlers;
      sample["pressure_Pa"] = r.pressure;
      sample["formation_steps"] = r.steps;
      sample["mean_radius_m"] = r.mean_radius;
      sample["max_overlap_ratio"] = r.max_overlap_ratio;
      sample["particles_after_carving"] = model.system.particles.size();
      sample["disc_diameter_m"] = scene.dem.sample.disc_diameter;
    }
  } // namespace

  SampleType dense_random_packing_sample()
  {
    return {{"dense random packing",
            "N spheres (radius R +- w) grown in the DEM/Domain box with friction Formation friction until the "
            "mean stress is Packing pressure [Pa] (Elyashiv et al. 2020: the formation friction sets the density; "
            "frictionless ~0.64, rough ~0.56); open axes are walled while it forms; touching pairs are bonded "
            "(Gap tolerance); Disc diameter [m] > 0 then carves a disc with its axis along y for the Brazilian "
            "test.",
            declare}, parse, check, build, describe, summarize};
  }
} // namespace anticrack::dem
