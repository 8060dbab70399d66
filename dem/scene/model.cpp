#include "dem/scene/model.h"

#include "dem/contact/contact_law.h"
#include "dem/core/force_history.h"
#include "dem/io/state_hdf5.h"
#include "dem/lab/box_walls.h"
#include "dem/lab/load_control.h"
#include "dem/lab/measurements.h"
#include "dem/lab/platen_compression_test.h"
#include "dem/lab/simple_shear.h"
#include "dem/lab/triaxial_test.h"
#include "dem/sample/bedding.h"
#include "dem/sample/lattice.h"
#include "dem/sample/specimen_carving.h"
#include "util/input_error.h"

#include <chrono>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <map>
#include <numeric>
#include <ostream>
#include <random>
#include <sstream>

namespace anticrack::dem
{
  std::string to_string(const dem::WallControl control) { return parameters::wall_control_names().name(control); }

  int apply_thread_count(const int threads)
  {
    // Without an explicit count the OpenMP default applies: OMP_NUM_THREADS, else every core.
    if (threads > 0)
      dem::DemSystem::set_threads(threads);
    return dem::DemSystem::threads();
  }

  namespace
  {
    using parameters::Walls;

    /// Initial velocity amplitude for the generated samples (the generators leave them at rest).
    void add_random_velocities(const parameters::Dem &d, dem::DemSystem &system, const Index first)
    {
      if (!(d.sample.velocity_amplitude > 0))
        return;
      std::mt19937_64 rng(d.seed ^ 0x9e3779b97f4a7c15ULL);
      std::uniform_real_distribution<double> uniform(-1.0, 1.0);
      for (Index p = first; p < system.particles.size(); ++p)
        for (int a = 0; a < 3; ++a)
          system.particles.velocity[p][a] = d.sample.velocity_amplitude * uniform(rng);
    }

    /// The generators sample in a periodic box; the specimen is periodic only along the axes the
    /// scene lists. Opening an axis before the bonding pass means that no bond crosses its faces
    /// (the spheres keep their wrapped positions inside the box).
    void open_axes_the_scene_does_not_wrap(const parameters::Dem &d, dem::DemSystem &system)
    {
      for (int a = 0; a < 3; ++a)
        system.domain.periodic[a] = system.domain.periodic[a] && d.domain.periodic[a];
    }

    void add_sample(const SceneParameters &scene, DemModel &model)
    {
      dem::DemSystem &system = model.system;
      const auto &d = scene.dem;
      if (d.sample.type == parameters::Sample::Type::sticky_hard_spheres)
      {
        // The sampler replaces the domain by its periodic cube.
        dem::shs::SamplerSpec spec;
        spec.particle_count = d.sample.particle_count;
        spec.volume_fraction = d.sample.volume_fraction;
        spec.stickiness = d.sample.stickiness;
        spec.target_coordination = d.sample.target_coordination;
        spec.radius = d.sample.box_edge > 0 ?
                        std::cbrt(d.sample.volume_fraction * std::pow(d.sample.box_edge, 3) /
                                  (d.sample.particle_count * dem::sphere_volume(1.0))) :
                        d.sample.radius;
        spec.well_width = d.sample.well_width;
        spec.sweeps = d.sample.sweeps;
        spec.cluster_move_fraction = d.sample.cluster_move_fraction;
        spec.material = 0;
        spec.seed = d.seed;
        model.sticky_hard_spheres = dem::shs::sample_sticky_hard_spheres(system, spec);
        open_axes_the_scene_does_not_wrap(d, system);
        add_random_velocities(d, system, 0);
        return;
      }
      if (d.sample.type == parameters::Sample::Type::ballistic_deposition)
      {
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
        return;
      }
      if (d.sample.type == parameters::Sample::Type::dense_random_packing)
      {
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
        return;
      }
      if (d.sample.type == parameters::Sample::Type::simple_cubic_lattice)
      {
        dem::LatticeSpec spec;
        spec.cells = d.sample.lattice_size;
        spec.radius = d.sample.radius;
        spec.spacing = d.sample.spacing;
        spec.origin = d.sample.origin;
        spec.material = 0;
        spec.velocity_amplitude = d.sample.velocity_amplitude;
        spec.seed = d.seed;
        dem::add_simple_cubic_lattice(system, spec);
        return;
      }

      // An external sample (dem/io/state_hdf5.h read_sample): spheres, optional clumps and bonds.
      dem::io::ExternalSample sample;
      try
      {
        sample = dem::io::read_sample(d.sample.snapshot_file);
      }
      catch (const std::exception &e)
      {
        throw InputError("DEM/Sample/Snapshot file = " + d.sample.snapshot_file + ": " + e.what());
      }
      const std::vector<Vec3> &position = sample.position;
      std::mt19937_64 rng(d.seed);
      std::uniform_real_distribution<double> uniform(-1.0, 1.0);
      const Index first = system.particles.size();
      for (std::size_t k = 0; k < position.size(); ++k)
      {
        for (int a = 0; a < 3; ++a)
          if (!d.domain.periodic[a] &&
              !(position[k][a] >= d.domain.lower[a] && position[k][a] <= d.domain.upper[a]))
            throw InputError("DEM/Sample/Snapshot file = " + d.sample.snapshot_file + ": sphere " +
                             std::to_string(k) + " at (" + format_vector(position[k]) +
                             ") m lies outside DEM/Domain");
        const Index p = system.particles.add_sphere(system.domain.wrap(position[k]), sample.radius[k],
                                                    d.material.density, 0);
        if (d.sample.velocity_amplitude > 0)
          for (int a = 0; a < 3; ++a)
            system.particles.velocity[p][a] = d.sample.velocity_amplitude * uniform(rng);
      }
      // Rigid grains: spheres sharing a clump id.
      std::map<int, std::vector<Index>> grains;
      for (std::size_t k = 0; k < sample.clump_id.size(); ++k)
        if (sample.clump_id[k] >= 0)
          grains[sample.clump_id[k]].push_back(first + static_cast<Index>(k));
      for (const auto &[id, members] : grains)
        system.add_clump(members);
      // Bonds given by the file replace the bonding of touching pairs.
      model.imported_bonds = !sample.bond_i.empty();
      for (std::size_t b = 0; b < sample.bond_i.size(); ++b)
        system.add_bond(first + sample.bond_i[b], first + sample.bond_j[b],
                        sample.bond_radius.empty() ? 0.0 : sample.bond_radius[b]);
    }

    /// Fixed base and loaded clump (docs/physics.md §1.5). Both start at rest.
    void add_boundary_particles(const SceneParameters &scene, DemModel &model)
    {
      const auto &bp = scene.dem.boundary;
      auto &particles = model.system.particles;
      const Index n = particles.size();
      double z_min = std::numeric_limits<double>::infinity(), z_max = -z_min;
      for (Index p = 0; p < n; ++p)
        z_min = std::min(z_min, particles.position[p][2]), z_max = std::max(z_max, particles.position[p][2]);
      const std::string range = "the sphere centres span z = [" + format_number(z_min) + ", " +
                                format_number(z_max) + "] m";

      // Thresholds in mean radii become heights: the base from the domain's floor, the actuator from
      // the sample's top (the lower of the domain's ceiling and the highest sphere top).
      const dem::Domain &domain = model.system.domain;
      const double mean_radius =
        n > 0 ? std::accumulate(particles.radius.begin(), particles.radius.end(), 0.0) / n : 0.0;
      double top = -std::numeric_limits<double>::infinity();
      for (Index p = 0; p < n; ++p)
        top = std::max(top, particles.position[p][2] + particles.radius[p]);
      top = std::min(top, domain.upper[2]);
      const std::optional<double> fix_below =
        bp.base_thickness ? std::optional(domain.lower[2] + *bp.base_thickness * mean_radius) : bp.fix_below;
      const std::optional<double> clump_above =
        bp.actuator_thickness ? std::optional(top - *bp.actuator_thickness * mean_radius) : bp.clump_above;
      const std::string which_base =
        bp.base_thickness ? "Base thickness [mean radii] = " + format_number(*bp.base_thickness) + " (z < " +
                              format_number(*fix_below) + " m)" :
                            "Fix below [m] = " + (fix_below ? format_number(*fix_below) : std::string());
      const std::string which_clump =
        bp.actuator_thickness ?
          "Actuator thickness [mean radii] = " + format_number(*bp.actuator_thickness) + " (z > " +
            format_number(clump_above.value_or(0)) + " m)" :
          "Clump above [m] = " + (clump_above ? format_number(*clump_above) : std::string());

      std::vector<Index> clump_members;
      for (Index p = 0; p < n; ++p)
      {
        const double z = particles.position[p][2];
        if (fix_below && z < *fix_below)
        {
          model.fixed_particles.push_back(p);
          particles.blocked[p] = dem::block_all;
          particles.velocity[p].setZero();
          particles.angular_velocity[p].setZero();
        }
        else if ((clump_above && z > *clump_above) ||
                 (model.actuator_layer_first >= 0 && p >= model.actuator_layer_first))
        {
          clump_members.push_back(p);
          particles.velocity[p].setZero();
          particles.angular_velocity[p].setZero();
        }
      }
      if (fix_below && model.fixed_particles.empty())
        throw InputError("DEM/Boundary particles/" + which_base + " selects no sphere: " + range + ".");
      if (clump_above && model.actuator_layer_first < 0 && clump_members.empty())
        throw InputError("DEM/Boundary particles/" + which_clump + " selects no sphere: " + range + ".");
      const Index free = n - static_cast<Index>(model.fixed_particles.size() + clump_members.size());
      if (n > 0 && free == 0)
        throw InputError("DEM/Boundary particles: " + which_base + " and " + which_clump +
                         " leave no free sphere between the base and the clump (" + range + ").");
      if (clump_members.empty())
        return;
      model.clump = model.system.add_clump(clump_members);
      dem::Clump &clump = model.system.clumps[model.clump];
      clump.rotation_locked = bp.clump_rotation_locked;
      if (bp.clump_force_rate != 0)
        clump.applied_force = dem::ForceHistory::ramp(bp.clump_force_rate, bp.clump_force_direction);
    }

    void add_walls(const SceneParameters &scene, DemModel &model)
    {
      const auto &d = scene.dem;
      // The system's domain: ballistic deposition may have raised its upper z.
      const dem::Domain &domain = model.system.domain;
      const Vec3 length = domain.upper - domain.lower;
      for (int f = 0; f < 6; ++f)
      {
        const auto &face = d.walls.face[f];
        if (!face.active)
          continue;
        const int a = Walls::axis(f);
        dem::Wall wall;
        wall.name = Walls::face_names[f];
        wall.normal = Vec3::Zero();
        wall.normal[a] = -Walls::side(f); // inward
        wall.point = Walls::side(f) < 0 ? domain.lower : domain.upper;
        wall.control = face.control;
        wall.velocity = face.control == dem::WallControl::velocity ? Vec3(face.velocity * wall.normal) :
                                                                     Vec3::Zero();
        wall.contact = d.material.contact;
        wall.target_stress = face.target_stress;
        wall.area = length[(a + 1) % 3] * length[(a + 2) % 3];
        wall.servo_gain = face.servo_gain;
        wall.max_speed = face.max_speed;
        model.system.walls.push_back(wall);
        model.wall_face.push_back(f);
      }
    }
  } // namespace

  std::unique_ptr<DemModel> build_dem_model(const SceneParameters &scene, const int threads)
  {
    const auto &d = scene.dem;
    const auto start = std::chrono::steady_clock::now();
    auto model = std::make_unique<DemModel>();
    dem::DemSystem &system = model->system;
    apply_thread_count(threads);

    try
    {
      system.domain.lower = d.domain.lower;
      system.domain.upper = d.domain.upper;
      system.domain.periodic = d.domain.periodic;

      dem::Material material;
      material.density = d.material.density;
      material.contact = d.material.contact;
      material.bond = d.bond.bond;
      system.materials.add(material);

      add_sample(scene, *model);
      if (system.particles.size() == 0)
        throw InputError("DEM/Sample: the sample has no spheres.");
      // After the sample: the sticky-hard-sphere sampler sets its own domain.
      const Vec3 length = system.domain.upper - system.domain.lower;
      model->base_area = length[0] * length[1];
      // Clump before bonds: bonds inside the rigid clump would carry no load but cost time.
      add_boundary_particles(scene, *model);
      if (d.bond.bond.enabled)
      {
        // Sticky hard spheres: the adhesive contacts the sampler drew among the pairs in its well
        // (gap <= delta sigma = 2 delta R) become the bonds.
        dem::BondingRule rule;
        rule.gap_tolerance = d.bond.gap_tolerance;
        if (model->sticky_hard_spheres)
        {
          rule.gap_tolerance = 2 * d.sample.well_width * (1 + 1e-9);
          rule.only_pairs.insert(model->sticky_hard_spheres->bonded_pairs.begin(),
                                 model->sticky_hard_spheres->bonded_pairs.end());
        }
        model->initial_bonds =
          model->imported_bonds ? system.bonds.size() : system.bond_touching_pairs(rule);
        if (d.bedding.enabled)
          model->bedding_bonds = dem::apply_bedding(system, d.bedding.spec);
      }
      add_walls(scene, *model);
      if (d.loading.test == parameters::Loading::Test::triaxial)
      {
        model->box_walls = dem::add_box_walls(system, d.material.contact);
        for (int f = 0; f < 6; ++f)
          model->wall_face.push_back(f);
      }
      system.settings = d.integration.settings;
      system.initialise();
      model->critical_time_step = system.critical_time_step();
    }
    catch (const dem::SetupError &e)
    {
      throw InputError("Invalid scene file <" + scene.file + ">: the DEM model cannot be set up: " +
                       e.what());
    }
    catch (const dem::NumericalError &e)
    {
      // At set-up this can only be a fixed time step above the critical one.
      throw InputError("Invalid scene file <" + scene.file + ">: " + e.what() +
                       " (DEM/Integration/Time step [s])");
    }
    catch (const InputError &e)
    {
      throw InputError("Invalid scene file <" + scene.file + ">: " + e.what());
    }
    model->build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return model;
  }

  std::unique_ptr<dem::LabProtocol> make_lab_protocol(const SceneParameters &scene, DemModel &model)
  {
    const auto &d = scene.dem;
    using Test = parameters::Loading::Test;
    if (d.loading.test == Test::triaxial)
    {
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
    if (d.loading.test == Test::platen_compression)
    {
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
    if (model.clump < 0)
      return nullptr;
    // Strains are relative to the specimen's initial height (the z extent of its spheres).
    const auto [low, high] = dem::sphere_extent(model.system.particles, 2);
    if (d.loading.test == Test::simple_shear)
    {
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
    const bool tilted = d.loading.test == Test::tilted_gravity;
    if (!(tilted || d.loading.adaptive || d.loading.stop_strain > 0))
      return nullptr;
    auto ramp = std::make_unique<dem::ClumpForceRamp>(
      model.clump, model.fixed_particles, d.boundary.clump_force_direction, d.loading.ramp, d.loading.adaptive,
      d.loading.stop_strain * (high - low), tilted ? d.integration.settings.gravity.norm() : 0.0);
    ramp->start(model.system);
    return ramp;
  }

  void describe_dem_model(std::ostream &out, const SceneParameters &scene, const DemModel &model)
  {
    const auto &d = scene.dem;
    const auto &system = model.system;
    const auto &o = scene.output;
    const char *axis_name[3] = {"x", "y", "z"};
    std::ostringstream s;
    s << std::setprecision(6);

    s << "Scene " << scene.file << "\n"
      << "  file sha256         " << scene.file_sha256 << "\n"
      << "  parameters sha256   " << scene.parameters_sha256 << "\n"
      << "Components: ";
    for (std::size_t k = 0; k < scene.components.size(); ++k)
      s << (k ? ", " : "") << scene.components[k];
    const auto &domain = system.domain; // the generators may change the scene's domain
    s << "\n\nDEM\n"
      << "  domain              [" << format_vector(domain.lower) << "] - [" << format_vector(domain.upper)
      << "] m, periodic in";
    bool any_periodic = false;
    for (int a = 0; a < 3; ++a)
      if (domain.periodic[a])
        s << " " << axis_name[a], any_periodic = true;
    if (!any_periodic)
      s << " none";
    s << "\n  sample              ";
    if (d.sample.type == parameters::Sample::Type::simple_cubic_lattice)
      s << "simple cubic lattice " << d.sample.lattice_size[0] << " x " << d.sample.lattice_size[1] << " x "
        << d.sample.lattice_size[2] << ", R = " << d.sample.radius << " m, spacing " << d.sample.spacing << " m";
    else if (model.sticky_hard_spheres)
    {
      const auto &r = *model.sticky_hard_spheres;
      s << "sticky hard spheres, N = " << d.sample.particle_count << ", R = " << system.particles.radius.front()
        << (d.sample.box_edge > 0 ? " (from Box edge [m])" : "")
        << " m, well width delta/sigma = " << d.sample.well_width << ", " << d.sample.sweeps << " sweeps\n"
        << "                      (DEM/Domain is replaced by the sampler's periodic cube, edge " << r.box_length
        << " m)\n"
        << "  generator report    phi = " << r.volume_fraction << ", tau = " << r.stickiness
        << (d.sample.target_coordination > 0 ? " (from the target z)" : "") << ", z = " << r.coordination
        << " (Percus-Yevick " << r.percus_yevick_coordination << "), contacts " << r.contacts
        << ",\n                      largest cluster " << r.largest_cluster_fraction << " of the spheres, "
        << (r.percolating ? "percolating" : "not percolating") << ", acceptance " << r.acceptance
        << "\n                      (`check` runs the generator: the sample is the one `run` builds)";
    }
    else if (model.ballistic_deposition)
    {
      const auto &r = *model.ballistic_deposition;
      s << "ballistic deposition (" << (d.sample.rolling ? "rolling" : "sticky") << "), N = "
        << d.sample.particle_count << ", R = " << d.sample.radius << " +- " << d.sample.radius_half_width
        << " m\n"
        << "  generator report    bulk solid fraction " << r.solid_fraction_bulk << " (z in [" << r.bulk_lower
        << ", " << r.bulk_upper << "] m), mean contacts " << r.mean_contacts << " (bulk), "
        << r.mean_contacts_all << " (all),\n                      height " << r.height << " m, "
        << r.on_base << " on the base, " << r.fallbacks << " sticky fallbacks"
        << "\n                      (`check` runs the generator: the sample is the one `run` builds)";
    }
    else if (model.dense_packing)
    {
      const auto &r = *model.dense_packing;
      s << "dense random packing, N = " << d.sample.particle_count << ", R = " << d.sample.radius << " +- "
        << d.sample.radius_half_width << " m, formation friction " << d.sample.formation_friction << "\n"
        << "  generator report    solid fraction " << r.solid_fraction << ", coordination " << r.coordination
        << " (mechanical " << r.mechanical_coordination << ", " << r.rattlers << " rattlers), p = " << r.pressure
        << " Pa after " << r.steps << " steps, mean radius " << r.mean_radius << " m";
      if (d.sample.disc_diameter > 0)
        s << "\n                      disc of diameter " << d.sample.disc_diameter << " m carved (axis y): "
          << system.particles.size() << " spheres kept";
      s << "\n                      (`check` runs the generator: the sample is the one `run` builds)";
    }
    else
      s << "snapshot " << d.sample.snapshot_file;
    s << "\n  particles           " << system.particles.size() << " (" << model.fixed_particles.size()
      << " fixed";
    if (model.clump >= 0)
      s << ", " << system.clumps[model.clump].members.size() << " in the clump";
    s << ")\n  bonds               " << model.initial_bonds;
    if (!d.bond.bond.enabled)
      s << " (bonding disabled)";
    if (d.bedding.enabled)
      s << " (" << model.bedding_bonds << " of them in the bedding bands, inclination " << d.bedding.inclination_deg
        << " deg)";
    s << "\n  contact law         "
      << dem::contact_law_name(d.material.contact.law) << "\n";
    s << "  walls               " << (system.walls.empty() ? "none\n" : "\n");
    for (const auto &w : system.walls)
    {
      s << "    " << std::left << std::setw(4) << w.name << std::right << to_string(w.control);
      if (w.control == dem::WallControl::velocity)
        s << ", " << w.velocity.dot(w.normal) << " m/s inwards";
      if (w.control == dem::WallControl::servo)
        s << ", target " << w.target_stress << " Pa on " << w.area << " m^2";
      s << "\n";
    }
    s << "  clump               ";
    if (model.clump < 0)
      s << "none\n";
    else
    {
      const auto &c = system.clumps[model.clump];
      s << c.members.size() << " spheres, mass " << c.mass << " kg, force F(t) = "
        << d.boundary.clump_force_rate << " N/s x t x (" << format_vector(d.boundary.clump_force_direction)
        << ")" << (c.rotation_locked ? ", rotation locked" : "") << "\n";
    }
    const double dt = system.dt;
    s << "  critical time step  " << model.critical_time_step << " s\n"
      << "  time step           " << dt << " s ("
      << (d.integration.settings.time_step > 0 ? "fixed" : "automatic, safety factor ");
    if (!(d.integration.settings.time_step > 0))
      s << d.integration.settings.time_step_safety;
    s << ")\n"
      << "  steps               " << d.steps << "\n"
      << "  simulated time      " << d.steps * dt << " s"
      << (d.integration.settings.time_step > 0 ? "" : " (approximately: dt is re-evaluated)") << "\n"
      << "  local damping       " << d.integration.settings.local_damping << "\n"
      << "  threads             " << dem::DemSystem::threads() << "\n";

    auto every = [&](Index interval, const std::string &what) {
      if (interval > 0)
        s << "  " << what << " every " << interval << " steps (" << (d.steps + interval - 1) / interval + 1
          << " files at most)\n";
    };
    s << "\nOutputs (into the -o directory)\n"
      << "  summary.json\n"
      << "  history.h5          every " << (o.history_interval > 0 ? std::to_string(o.history_interval) : "-")
      << " steps (" << (o.history_interval > 0 ? d.steps / o.history_interval + 2 : 2) << " rows at most)\n";
    every(o.snapshot_interval, "snapshots/         ");
    if (o.snapshot_interval > 0 && o.write_paraview)
      s << "  paraview/           .vtp and .pvd at every snapshot\n";
    if (o.checkpoint_interval > 0)
      s << "  checkpoint.h5       every " << o.checkpoint_interval << " steps and at the end\n";
    out << s.str();
  }
} // namespace anticrack::dem
