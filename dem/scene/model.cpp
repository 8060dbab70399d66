#include "dem/scene/model.h"

#include "dem/contact/contact_law.h"
#include "dem/core/force_history.h"
#include "dem/sample/bedding.h"
#include "util/input_error.h"

#include <chrono>
#include <omp.h>

#include <algorithm>
#include <iomanip>
#include <limits>
#include <numeric>
#include <ostream>
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

  ThreadCountRestorer::ThreadCountRestorer() : threads_(dem::DemSystem::threads()) {}
  ThreadCountRestorer::~ThreadCountRestorer() { dem::DemSystem::set_threads(threads_); }

  namespace
  {
    using parameters::Walls;

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

  // A sticky-hard-sphere sample may percolate across its periodic box and yet not across the faces
  // the test opens (found at N = 4096 in a 1 cm cube: the clump then fell freely and the "failure"
  // the test reported, q = 21 Pa, was that of nothing).
  void require_load_path(const dem::DemSystem &system, const DemModel &model)
  {
    const Index n = static_cast<Index>(system.particles.size());
    std::vector<Index> parent(n);
    std::iota(parent.begin(), parent.end(), Index{0});
    const auto root = [&](Index a) {
      while (parent[a] != a)
        a = parent[a] = parent[parent[a]];
      return a;
    };
    const auto unite = [&](Index a, Index b) { parent[root(a)] = root(b); };
    const dem::BondList &bonds = system.bonds;
    for (Index b = 0; b < bonds.size(); ++b)
      if (bonds.state[b] == dem::BondState::intact)
        unite(bonds.i[b], bonds.j[b]);
    const std::vector<Index> &members = system.clumps[model.clump].members;
    for (const Index m : members)
      unite(m, members.front());
    for (const Index f : model.fixed_particles)
      unite(f, model.fixed_particles.front());
    if (root(members.front()) == root(model.fixed_particles.front()))
      return;
    Index with_base = 0;
    for (Index a = 0; a < n; ++a)
      with_base += root(a) == root(model.fixed_particles.front());
    std::ostringstream message;
    message << "the bonds do not connect the fixed base (" << model.fixed_particles.size()
            << " spheres) to the actuator clump (" << members.size() << " spheres): the test would load "
            << "nothing (the base's bonded cluster holds " << with_base << " of " << n
            << " spheres). A sample that percolates across its periodic box need not across the faces the "
               "test opens (DEM/Domain/Periodic axes): another Random seed, a higher coordination number or "
               "volume fraction, or a larger sample";
    throw SpecimenWithoutLoadPath(message.str());
  }


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

      d.sample.type->build(scene, *model);
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
        if (model->clump >= 0 && !model->fixed_particles.empty())
          require_load_path(system, *model);
      }
      add_walls(scene, *model);
      if (d.loading.test->add_to_model)
        d.loading.test->add_to_model(scene, *model);
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
    catch (const SpecimenWithoutLoadPath &e)
    {
      throw SpecimenWithoutLoadPath("Invalid scene file <" + scene.file + ">, DEM/Random seed = " +
                                    std::to_string(scene.dem.seed) + ": " + e.what());
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
    return scene.dem.loading.test->make_protocol(scene, model);
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
    d.sample.type->describe(s, scene, model);
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
      << "  summary.json\n";
    // The test that samples its own curve (dem::LabProtocol::samples_history) is the one whose
    // interval is set: only the compaction test reads DEM/Loading/Curve strain interval.
    if (d.loading.curve_strain_interval > 0)
      s << "  history.h5          a row every " << d.loading.curve_strain_interval << " of strain ("
        << static_cast<Index>(d.loading.stop_strain / d.loading.curve_strain_interval) + 2
        << " rows at most; DEM/Loading/Curve strain interval, in place of History interval [steps])\n";
    else
      s << "  history.h5          every " << (o.history_interval > 0 ? std::to_string(o.history_interval) : "-")
        << " steps (" << (o.history_interval > 0 ? d.steps / o.history_interval + 2 : 2) << " rows at most)\n";
    every(o.snapshot_interval, "snapshots/         ");
    if (o.snapshot_interval > 0 && o.write_paraview)
      s << "  paraview/           .vtp and .pvd at every snapshot\n";
    if (o.checkpoint_interval > 0)
      s << "  checkpoint.h5       every " << o.checkpoint_interval << " steps and at the end\n";
    out << s.str();
  }
} // namespace anticrack::dem
