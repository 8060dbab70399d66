#include "dem/scene/sample_types.h"

#include "dem/core/system.h"
#include "dem/scene/parameters.h"
#include "dem/scene/scene_entries.h"
#include "util/problems.h"

#include <random>

namespace anticrack::dem
{
  // Each in its own file of dem/scene/samples/.
  SampleType simple_cubic_lattice_sample();
  SampleType snapshot_sample();
  SampleType sticky_hard_spheres_sample();
  SampleType ballistic_deposition_sample();
  SampleType dense_random_packing_sample();

  const std::vector<SampleType> &sample_types()
  {
    static const std::vector<SampleType> types{
      simple_cubic_lattice_sample(), // the default
      snapshot_sample(),
      sticky_hard_spheres_sample(),
      ballistic_deposition_sample(),
      dense_random_packing_sample(),
    };
    return types;
  }

  const std::vector<SharedEntry> &shared_sample_entries()
  {
    static const std::vector<SharedEntry> entries{
      {"Radius [m]", "1e-3", std::make_shared<Patterns::Double>(0),
       "R: sphere radius, at most half the spacing (lattice); the radius of every "
       "sphere (sticky hard spheres); the mean radius (ballistic deposition). "
       "Units: m."},
      {"Initial velocity amplitude [m/s]", "0", std::make_shared<Patterns::Double>(0),
       "a: every velocity component starts uniformly random in [-a, a] (seeded "
       "by DEM/Random seed; fixed and clumped spheres start at rest). Units: m/s."},
      {"Particle count", "512", std::make_shared<Patterns::Integer>(1),
       "N: number of spheres (sticky hard spheres: at least 8; ballistic "
       "deposition)."},
      {"Radius half width [m]", "0", std::make_shared<Patterns::Double>(0),
       "w: radii uniform in [R - w, R + w] with R = Radius [m]; 0 <= w < R "
       "(ballistic deposition, dense random packing). Units: m."},
    };
    return entries;
  }

  void parse_shared_sample_entries(dealii::ParameterHandler &prm, parameters::Sample &s)
  {
    // Entries of other sample types are not declared for this scene: they keep their defaults.
    const auto uses = [&](const std::string &entry) { return s.type->has_entry(entry); };
    if (uses("Radius [m]"))
      s.radius = prm.get_double("Radius [m]");
    if (uses("Initial velocity amplitude [m/s]"))
      s.velocity_amplitude = prm.get_double("Initial velocity amplitude [m/s]");
    if (uses("Particle count"))
      s.particle_count = prm.get_integer("Particle count");
    if (uses("Radius half width [m]"))
      s.radius_half_width = prm.get_double("Radius half width [m]");
  }

  std::string sample_type_documentation()
  {
    return name_paragraphs(sample_types()) +
           " The generators are seeded by DEM/Random seed and run again by `anticrack check`, which prints "
           "their statistics.";
  }

  std::string for_sample_type(const parameters::Sample &sample)
  {
    return " for DEM/Sample/Type = " + std::string(sample.type->name);
  }

  double verlet_skin(const parameters::Integration &integration, const double mean_radius)
  {
    return integration.settings.verlet_skin > 0 ? integration.settings.verlet_skin : 0.1 * mean_radius;
  }

  bool check_radius(const parameters::Sample &s, Problems &problems)
  {
    if (s.radius > 0)
      return true;
    problems.add("DEM/Sample/Radius [m]", s.radius, "must be positive");
    return false;
  }

  void check_radius_distribution(const parameters::Sample &s, Problems &problems)
  {
    if (check_radius(s, problems) && !(s.radius_half_width < s.radius))
      problems.add("DEM/Sample/Radius half width [m]", s.radius_half_width,
                   "must be below DEM/Sample/Radius [m] = " + format_number(s.radius) +
                     " (allowed: 0 <= w < R)");
  }

  void add_random_velocities(const parameters::Dem &d, DemSystem &system, const Index first)
  {
    if (!(d.sample.velocity_amplitude > 0))
      return;
    std::mt19937_64 rng(d.seed ^ 0x9e3779b97f4a7c15ULL);
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    for (Index p = first; p < system.particles.size(); ++p)
      for (int a = 0; a < 3; ++a)
        system.particles.velocity[p][a] = d.sample.velocity_amplitude * uniform(rng);
  }

  void open_axes_the_scene_does_not_wrap(const parameters::Dem &d, DemSystem &system)
  {
    for (int a = 0; a < 3; ++a)
      system.domain.periodic[a] = system.domain.periodic[a] && d.domain.periodic[a];
  }
} // namespace anticrack::dem
