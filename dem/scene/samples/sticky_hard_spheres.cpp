// DEM/Sample/Type = sticky hard spheres (dem/sample/sticky_hard_spheres.h): Baxter's adhesive
// hard-sphere fluid sampled by Monte Carlo in a periodic box that replaces DEM/Domain.
#include "dem/sample/sticky_hard_spheres.h"
#include "dem/scene/model.h"
#include "dem/scene/sample_types.h"
#include "dem/scene/scene_entries.h"
#include "util/problems.h"

#include <cmath>
#include <nlohmann/json.hpp>

#include <ostream>
#include <string>

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
      entries.entry("Volume fraction", "0.3", Patterns::Double(0, 0.55),
                    "phi: solid volume fraction of the sticky-hard-sphere sample, in (0, 0.55] "
                    "(sticky hard spheres only). Dimensionless.");
      entries.entry("Stickiness", "0.2", Patterns::Double(0),
                    "tau: Baxter stickiness parameter (smaller = stickier), at least "
                    "tau_min(phi) = (14 phi^2 - 4 phi - 1) / (12 (2 phi^2 - phi - 1)); 0 = take "
                    "tau from the target coordination number (sticky hard spheres only). "
                    "Dimensionless.");
      entries.entry("Target coordination number", "0", Patterns::Double(0),
                    "z: mean number of bonded neighbours wanted; > 0 selects tau from the "
                    "Percus-Yevick relation z = 2 phi lambda(phi, tau) and requires Stickiness = 0; "
                    "0 = use Stickiness (sticky hard spheres only). Dimensionless.");
      entries.entry("Well width", "0.03", Patterns::Double(0, 0.1),
                    "delta / sigma: width of the square well that represents Baxter's adhesion, "
                    "relative to the diameter sigma = 2 R, in (0, 0.1]; pairs in the well "
                    "(gap <= delta sigma) become bonds (sticky hard spheres only). "
                    "Dimensionless.");
      entries.entry("Box edge [m]", "0", Patterns::Double(0),
                    "L: the sticky-hard-sphere box's edge along z, the specimen's height (the cube's edge "
                    "when Box aspect ratios = 1, 1, 1); > 0 sets the radius "
                    "R = (phi L_x L_y L_z / (4/3 pi N))^(1/3) and overrides Radius [m] (Ritter et al. (2020) keep "
                    "a 1 cm cube for every phi); 0 = from Radius [m] (sticky hard spheres only). "
                    "Units: m.");
      entries.vector("Box aspect ratios", "1, 1, 1",
                     "a_x, a_y, a_z: the box's edges relative to each other, L_x : L_y : L_z, all positive; "
                     "1, 1, 1 is a cube, 2, 2, 1 a layer twice as wide as it is thick (sticky hard "
                     "spheres only). Dimensionless.");
      entries.entry("Sweeps", "20000", Patterns::Integer(1),
                    "Monte Carlo sweeps of N trial moves each; the sample must level off within them "
                    "(Equilibration tolerance): at phi = 0.3, z = 2.9 it takes 15 000-20 000 "
                    "(docs/work_precision.md) (sticky hard spheres only).");
      entries.entry("Sweep extension limit", "1", Patterns::Double(1, dem::shs::max_sweep_extension_limit),
                    "a sample that has not levelled off after Sweeps (Equilibration tolerance) runs on, "
                    "Sweeps more at a time, until it has or until it has run this many times Sweeps "
                    "in all; it is refused only then. 1 = exactly Sweeps. A looser sample levels off later "
                    "(fewer encounters per sweep); a sample that levels off within Sweeps is the same "
                    "whatever the limit (sticky hard spheres only). Dimensionless, in [1, 10].");
      entries.entry("Equilibration tolerance", "0.015", Patterns::Double(0, 1),
                    "the largest rise of the sample's coordination (partners in the well per sphere) "
                    "allowed from the third to the last quarter of the sweeps, relative, beyond 1.5 times "
                    "its scatter at equilibrium (1.7 % for 1024 spheres, as 1/sqrt(N)); a sample that rises more has not levelled off and is "
                    "refused (it would be less bonded, so weaker, than the fluid it stands for: about 4 % "
                    "of strength per 1 % of z). 0 = not checked, for studies of the sampler itself "
                    "(sticky hard spheres only). Dimensionless.");
      entries.entry("Cluster move fraction", "0", Patterns::Double(0, 1),
                    "fraction of Monte Carlo trial moves that translate a whole cluster of "
                    "spheres in each other's well (pairs in the well linked with the contact "
                    "probability 1 - exp(-eps/kT), Swendsen-Wang; detailed balance kept because "
                    "the move is refused only on hard-core overlap, for clusters of more than 16 "
                    "spheres and for clusters that wrap around the box); helps dense, sticky "
                    "states with finite clusters equilibrate, not a network that already spans the "
                    "box (sticky hard spheres only). Must be below 1. Dimensionless.");
    }

    void parse(dealii::ParameterHandler &prm, Sample &s)
    {
      s.volume_fraction = prm.get_double("Volume fraction");
      s.stickiness = prm.get_double("Stickiness");
      s.target_coordination = prm.get_double("Target coordination number");
      s.well_width = prm.get_double("Well width");
      s.sweeps = prm.get_integer("Sweeps");
      s.sweep_extension_limit = prm.get_double("Sweep extension limit");
      s.cluster_move_fraction = prm.get_double("Cluster move fraction");
      s.equilibration_tolerance = prm.get_double("Equilibration tolerance");
      s.box_edge = prm.get_double("Box edge [m]");
      s.box_aspect_ratios = get_triple<Vec3>(prm, "Box aspect ratios");
    }

    void check(const Sample &s, const parameters::Dem &, Problems &problems)
    {
      const std::string why_type = for_sample_type(s);
      if (s.particle_count < 8)
        problems.add("DEM/Sample/Particle count", s.particle_count, "must be at least 8" + why_type);
      if (!(s.volume_fraction > 0))
        problems.add("DEM/Sample/Volume fraction", s.volume_fraction, "must be in (0, 0.55]" + why_type);
      check_radius(s, problems);
      if (!(s.box_aspect_ratios.minCoeff() > 0) || !s.box_aspect_ratios.allFinite())
        problems.add("DEM/Sample/Box aspect ratios", vec(s.box_aspect_ratios), "must be three finite positive numbers" + why_type);
      if (!(s.well_width > 0))
        problems.add("DEM/Sample/Well width", s.well_width, "must be in (0, 0.1]" + why_type);
      if (s.equilibration_tolerance > 0 && s.sweeps < dem::shs::minimum_sweeps_to_judge_equilibrium)
        problems.add("DEM/Sample/Sweeps", s.sweeps,
                     "must be at least " + std::to_string(dem::shs::minimum_sweeps_to_judge_equilibrium) +
                       " to tell whether the sample has levelled off (DEM/Sample/Equilibration tolerance > 0 "
                       "compares the last two quarters of a coordination recorded every 100 sweeps)");
      if (!(s.cluster_move_fraction < 1))
        problems.add("DEM/Sample/Cluster move fraction", s.cluster_move_fraction,
                     "must be in [0, 1): single-sphere moves are needed to make and break clusters");
      const bool use_z = s.target_coordination > 0;
      if (use_z && s.stickiness > 0)
        problems.add("DEM/Sample/Stickiness", s.stickiness,
                     "must be 0 when DEM/Sample/Target coordination number = " +
                       format_number(s.target_coordination) + " > 0 selects tau; set one of the two to 0");
      else if (!use_z && !(s.stickiness > 0))
        problems.add("DEM/Sample/Stickiness", s.stickiness,
                     "must be positive (at least tau_min(phi)) unless DEM/Sample/Target "
                     "coordination number > 0 selects it");
      else if (s.volume_fraction > 0 && s.volume_fraction < 1)
      {
        const double tau_min = dem::shs::minimum_stickiness(s.volume_fraction);
        if (!use_z && s.stickiness < tau_min)
          problems.add("DEM/Sample/Stickiness", s.stickiness,
                       "is below the admissible minimum tau_min(phi) = " + format_number(tau_min) +
                         " at DEM/Sample/Volume fraction phi = " + format_number(s.volume_fraction) +
                         " (allowed: tau >= tau_min(phi), docs/physics.md §1.4); raise tau or lower phi");
        if (use_z)
          try
          {
            dem::shs::stickiness_for_coordination(s.volume_fraction, s.target_coordination);
          }
          catch (const dem::SetupError &e)
          {
            problems.add("DEM/Sample/Target coordination number", s.target_coordination, e.what());
          }
      }
    }

    void build(const SceneParameters &scene, DemModel &model)
    {
      const auto &d = scene.dem;
      // The sampler replaces the domain by its periodic box.
      dem::shs::SamplerSpec spec;
      spec.particle_count = d.sample.particle_count;
      spec.volume_fraction = d.sample.volume_fraction;
      spec.stickiness = d.sample.stickiness;
      spec.target_coordination = d.sample.target_coordination;
      spec.aspect_ratios = d.sample.box_aspect_ratios;
      spec.radius = d.sample.sticky_sphere_radius();
      spec.well_width = d.sample.well_width;
      spec.sweeps = d.sample.sweeps;
      spec.sweep_extension_limit = d.sample.sweep_extension_limit;
      spec.cluster_move_fraction = d.sample.cluster_move_fraction;
      spec.equilibration_tolerance = d.sample.equilibration_tolerance;
      spec.material = 0;
      spec.seed = d.seed;
      model.sticky_hard_spheres = dem::shs::sample_sticky_hard_spheres(model.system, spec);
      open_axes_the_scene_does_not_wrap(d, model.system);
      add_random_velocities(d, model.system, 0);
    }

    void describe(std::ostream &s, const SceneParameters &scene, const DemModel &model)
    {
      const Sample &sample = scene.dem.sample;
      const auto &r = *model.sticky_hard_spheres;
      s << "sticky hard spheres, N = " << sample.particle_count << ", R = " << model.system.particles.radius.front()
        << (sample.box_edge > 0 ? " (from Box edge [m])" : "")
        << " m, well width delta/sigma = " << sample.well_width << ", " << r.sweeps << " sweeps"
        << (r.sweeps > sample.sweeps ? " (Sweeps extended until levelled off)" : "") << "\n"
        << "                      (DEM/Domain is replaced by the sampler's periodic box, edges "
        << format_vector(r.box_lengths) << " m)\n"
        << "  generator report    phi = " << r.volume_fraction << ", tau = " << r.stickiness
        << (sample.target_coordination > 0 ? " (from the target z)" : "") << ", z = " << r.coordination
        << " (Percus-Yevick " << r.percus_yevick_coordination << "), contacts " << r.contacts
        << ",\n                      largest cluster " << r.largest_cluster_fraction << " of the spheres, "
        << (r.percolating ? "percolating" : "not percolating") << ", acceptance " << r.acceptance
        << ",\n                      coordination rise over the last half " << 100 * r.coordination_rise << " % (scatter at equilibrium "
        << 100 * r.coordination_rise_error << " %; refused above " << 100 * sample.equilibration_tolerance
        << " % + 1.5 x scatter)"
        << "\n                      (`check` runs the generator: the sample is the one `run` builds)";
    }

    void summarize(nlohmann::ordered_json &sample, const SceneParameters &scene, const DemModel &model)
    {
      const auto &r = *model.sticky_hard_spheres;
      sample["volume_fraction"] = r.volume_fraction;
      sample["stickiness"] = r.stickiness;
      sample["coordination"] = r.coordination;
      sample["percus_yevick_coordination"] = r.percus_yevick_coordination;
      sample["contacts"] = r.contacts;
      sample["acceptance"] = r.acceptance;
      sample["cluster_move_fraction"] = scene.dem.sample.cluster_move_fraction;
      sample["cluster_acceptance"] = r.cluster_acceptance;
      sample["largest_cluster_fraction"] = r.largest_cluster_fraction;
      sample["percolating"] = r.percolating;
      sample["box_lengths_m"] = {r.box_lengths[0], r.box_lengths[1], r.box_lengths[2]};
      sample["coordination_history"] = r.coordination_history;
      sample["coordination_rise"] = r.coordination_rise;
      sample["coordination_rise_error"] = r.coordination_rise_error;
      sample["equilibration_tolerance"] = scene.dem.sample.equilibration_tolerance;
      sample["sweeps"] = r.sweeps;
    }
  } // namespace

  SampleType sticky_hard_spheres_sample()
  {
    return {{"sticky hard spheres",
            "N spheres of radius R sampled by Monte Carlo as Baxter's adhesive hard-sphere fluid at volume "
            "fraction phi and stickiness tau (docs/physics.md §1.4) in a periodic box of edges in the ratio "
            "Box aspect ratios and volume N 4/3 pi R^3 / phi (or of height Box edge [m], which then sets R) with "
            "its lower corner at the origin: DEM/Domain's corners are ignored and replaced by this box, sampled "
            "periodic in x, y "
            "and z; axes missing from DEM/Domain/Periodic axes are opened after sampling (no bond crosses them: "
            "Ritter et al.'s (2020) specimen is periodic in x and y only), and every pair inside the well "
            "(gap <= 2 delta R) is bonded, whatever DEM/Bond/Gap tolerance says.",
            declare}, parse, check, build, describe, summarize};
  }
} // namespace anticrack::dem
