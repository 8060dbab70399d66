#include "dem/sample/dense_packing.h"

#include "dem/contact/contact_law.h"
#include "dem/lab/measurements.h"
#include "dem/core/particles.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace anticrack::dem
{
  namespace
  {
    const std::string who = "dense packing: ";
    const char *const axis_name[3] = {"x", "y", "z"};

    std::string num(double x)
    {
      std::ostringstream s;
      s.precision(6);
      s << x;
      return s.str();
    }

    void require(bool ok, const std::string &message)
    {
      if (!ok)
        throw SetupError(who + message);
    }

    /// Mean volume of a sphere whose radius is uniform in [mean - h, mean + h]:
    /// 4/3 pi <R^3> with <R^3> = mean^3 + mean h^2.
    double mean_sphere_volume(const RadiusDistribution &radius)
    {
      const double relative_width = radius.half_width / radius.mean;
      return sphere_volume(radius.mean) * (1 + relative_width * relative_width);
    }

    void validate_radius(const RadiusDistribution &radius)
    {
      require(radius.mean > 0 && std::isfinite(radius.mean),
              "radius.mean must be > 0 m (got " + num(radius.mean) + ")");
      require(radius.half_width >= 0 && radius.half_width < radius.mean,
              "radius.half_width must satisfy 0 <= half_width < mean = " + num(radius.mean) + " m (got " +
                num(radius.half_width) + ")");
    }

    void validate_box(const Vec3 &lower, const Vec3 &upper)
    {
      for (int a = 0; a < 3; ++a)
        require(upper[a] > lower[a] && std::isfinite(upper[a] - lower[a]),
                std::string("box_upper.") + axis_name[a] + " must exceed box_lower." + axis_name[a] + " (got " +
                  num(lower[a]) + " .. " + num(upper[a]) + " m)");
    }

    void validate(const DemSystem &system, const DensePackingSpec &spec)
    {
      require(spec.particle_count >= 1,
              "particle_count must be >= 1 (got " + std::to_string(spec.particle_count) + ")");
      validate_radius(spec.radius);
      validate_box(spec.box_lower, spec.box_upper);
      require(spec.material >= 0 && spec.material < system.materials.size(),
              "material " + std::to_string(spec.material) + " is not in system.materials (0 .. " +
                std::to_string(system.materials.size() - 1) + ")");
      require(spec.formation_friction >= 0 && std::isfinite(spec.formation_friction),
              "formation_friction must be >= 0 (got " + num(spec.formation_friction) + ")");
      const ContactParameters &contact = system.materials[spec.material].contact;
      const double modulus = contact_law_modulus(contact);
      require(spec.target_pressure > 0 && spec.target_pressure < 1e-2 * modulus,
              "target_pressure must satisfy 0 < p < 1e-2 x modulus = " + num(1e-2 * modulus) + " Pa (got " +
                num(spec.target_pressure) + " Pa)");
      require(spec.consolidation_pressure >= 0 && spec.consolidation_pressure <= 5e-2 * modulus,
              "consolidation_pressure must satisfy 0 <= p <= 5e-2 x modulus = " + num(5e-2 * modulus) +
                " Pa, 0 selecting 1e-2 x modulus (got " + num(spec.consolidation_pressure) + " Pa)");
      require(spec.max_steps >= 1, "max_steps must be >= 1 (got " + std::to_string(spec.max_steps) + ")");
      require(spec.initial_solid_fraction > 0 && spec.initial_solid_fraction <= 0.3,
              "initial_solid_fraction must lie in (0, 0.3] (got " + num(spec.initial_solid_fraction) + ")");
      require(spec.local_damping >= 0 && spec.local_damping < 1,
              "local_damping must lie in [0, 1) (got " + num(spec.local_damping) + ")");
      require(spec.max_growth_per_step > 0 && spec.max_growth_per_step <= 1e-2,
              "max_growth_per_step must lie in (0, 0.01] (got " + num(spec.max_growth_per_step) + ")");
      require(spec.servo_gain > 0 && spec.servo_gain <= 1,
              "servo_gain must lie in (0, 1] (got " + num(spec.servo_gain) + ")");
      require(spec.pressure_tolerance > 0 && spec.pressure_tolerance < 1,
              "pressure_tolerance must lie in (0, 1) (got " + num(spec.pressure_tolerance) + ")");
      require(spec.kinetic_energy_ratio > 0,
              "kinetic_energy_ratio must be > 0 (got " + num(spec.kinetic_energy_ratio) + ")");

      // Every edge must hold a few of the final spheres: estimate their size at a solid fraction a
      // little above random close packing (the box shape in diameters does not depend on size_by).
      const Vec3 length = spec.box_upper - spec.box_lower;
      const double densest = 0.66;
      const double factor =
        std::cbrt(densest * length.prod() / (spec.particle_count * mean_sphere_volume(spec.radius)));
      const double largest_diameter = 2 * factor * (spec.radius.mean + spec.radius.half_width);
      for (int a = 0; a < 3; ++a)
        require(length[a] >= 3 * largest_diameter,
                std::string("box_upper - box_lower: the edge along ") + axis_name[a] + " (" + num(length[a]) +
                  " m) must hold at least 3 of the largest final spheres (about " + num(largest_diameter) +
                  " m across for particle_count = " + std::to_string(spec.particle_count) +
                  "); use more particles or a less elongated box");
    }

    /// Uniform cell grid (cells at least one largest diameter wide) for the random sequential
    /// insertion; periodic axes wrap.
    class InsertionGrid
    {
    public:
      InsertionGrid(const Domain &box, double cell) : box_(box)
      {
        const Vec3 length = box.length();
        for (int a = 0; a < 3; ++a)
          cells_[a] = std::max<Index>(1, static_cast<Index>(std::floor(length[a] / cell)));
        members_.resize(cells_[0] * cells_[1] * cells_[2]);
      }

      void insert(Index id, const Vec3 &x) { members_[flat(cell_of(x))].push_back(id); }

      /// True when a sphere (x, r) overlaps none of the inserted spheres.
      bool is_free(const Vec3 &x, double r, const std::vector<Vec3> &centres, const std::vector<double> &radii) const
      {
        const std::array<Index, 3> c = cell_of(x);
        for (Index dz = -1; dz <= 1; ++dz)
          for (Index dy = -1; dy <= 1; ++dy)
            for (Index dx = -1; dx <= 1; ++dx)
            {
              std::array<Index, 3> n = {c[0] + dx, c[1] + dy, c[2] + dz};
              bool inside = true;
              for (int a = 0; a < 3; ++a)
              {
                if (box_.periodic[a])
                  n[a] = ((n[a] % cells_[a]) + cells_[a]) % cells_[a];
                else if (n[a] < 0 || n[a] >= cells_[a])
                  inside = false;
              }
              if (!inside)
                continue;
              for (const Index j : members_[flat(n)])
              {
                const Vec3 branch = centres[j] + box_.minimum_image_shift(x, centres[j]) - x;
                const double reach = r + radii[j];
                if (branch.squaredNorm() < reach * reach)
                  return false;
              }
            }
        return true;
      }

    private:
      std::array<Index, 3> cell_of(const Vec3 &x) const
      {
        std::array<Index, 3> c{};
        const Vec3 length = box_.length();
        for (int a = 0; a < 3; ++a)
          c[a] = std::clamp<Index>(static_cast<Index>((x[a] - box_.lower[a]) / length[a] * cells_[a]), 0,
                                   cells_[a] - 1);
        return c;
      }
      Index flat(const std::array<Index, 3> &c) const { return c[0] + cells_[0] * (c[1] + cells_[1] * c[2]); }

      Domain box_;
      std::array<Index, 3> cells_{};
      std::vector<std::vector<Index>> members_;
    };

    /// Random sequential insertion of spheres of the given radii in the given order (RSA jams at
    /// ~0.38, so fractions up to 0.3 fill quickly); along open axes the spheres lie inside the box.
    std::vector<Vec3> insert_randomly(const std::vector<double> &radii, const Domain &box, std::mt19937_64 &rng)
    {
      const double largest = *std::max_element(radii.begin(), radii.end());
      InsertionGrid grid(box, 2 * largest);
      std::vector<Vec3> centres;
      centres.reserve(radii.size());
      std::uniform_real_distribution<double> unit(0.0, 1.0);
      constexpr Index attempts_per_sphere = 100000;
      for (std::size_t p = 0; p < radii.size(); ++p)
      {
        const double r = radii[p];
        bool placed = false;
        for (Index attempt = 0; attempt < attempts_per_sphere && !placed; ++attempt)
        {
          Vec3 x;
          for (int a = 0; a < 3; ++a)
          {
            const double margin = box.periodic[a] ? 0.0 : r;
            x[a] = box.lower[a] + margin + unit(rng) * (box.length()[a] - 2 * margin);
          }
          if (grid.is_free(x, r, centres, radii))
          {
            grid.insert(static_cast<Index>(p), x);
            centres.push_back(x);
            placed = true;
          }
        }
        if (!placed)
          throw SetupError(who + "random sequential insertion found no room for sphere " + std::to_string(p) +
                           " after " + std::to_string(attempts_per_sphere) + " attempts");
      }
      return centres;
    }

    /// Mean compressive stress [Pa]: -sigma_aa of the Love-Weber stress over the box along periodic
    /// axes (static part), the mean normal stress of the two walls along open axes. Both are the
    /// exact static averages over the box (the frictionless walls load only their own axis).
    double mean_pressure(const DemSystem &s, const std::array<Index, 3> &first_wall)
    {
      const Vec3 length = s.domain.length();
      const Mat3 stress = love_weber_stress(s, length.prod(), false);
      double sum = 0;
      for (int a = 0; a < 3; ++a)
      {
        if (s.domain.periodic[a])
          sum -= stress(a, a);
        else
          sum += 0.5 * (s.walls[first_wall[a]].normal_stress() + s.walls[first_wall[a] + 1].normal_stress());
      }
      return sum / 3;
    }

    /// dp/dg of an affine growth of every radius by the factor 1 + g: each touching contact's
    /// overlap grows by g (R_i + R_j), so dp = g sum k_n (R_i + R_j)^2 / (3 V) (branch ~ R_i + R_j).
    double affine_stiffness(const DemSystem &s)
    {
      const ParticleStore &ps = s.particles;
      double sum = 0;
      for (Index c = 0; c < s.contacts.size(); ++c)
      {
        if (!(s.contacts.overlap[c] > 0))
          continue;
        const Index i = s.contacts.i[c], j = s.contacts.j[c];
        double kn, ks;
        contact_tangent_stiffness(s.materials.contact(ps.material_id[i], ps.material_id[j]), ps.radius[i],
                                  ps.radius[j], s.contacts.overlap[c], kn, ks);
        const double reach = ps.radius[i] + ps.radius[j];
        sum += kn * reach * reach;
      }
      return sum / (3 * s.domain.length().prod());
    }

    /// Multiplies every radius by `factor`, keeping masses and inertias those of solid spheres.
    void grow_radii(ParticleStore &ps, double factor)
    {
      const double f3 = factor * factor * factor, f5 = f3 * factor * factor;
      for (Index p = 0; p < ps.size(); ++p)
      {
        ps.radius[p] *= factor;
        ps.mass[p] *= f3;
        ps.inertia[p] *= f5;
      }
    }

    /// Largest displacement since the last neighbour-list build [m].
    double largest_displacement(const DemSystem &s)
    {
      const auto &reference = s.neighbor_reference_positions();
      double largest2 = 0;
      for (Index p = 0; p < s.particles.size(); ++p)
        largest2 = std::max(largest2, (s.particles.position[p] - reference[p]).squaredNorm());
      return std::sqrt(largest2);
    }

    /// Load-bearing spheres: those left after removing, repeatedly, every sphere with fewer than
    /// `minimum_contacts` sphere and wall contacts (with the removed spheres' contacts). 1 = bearing.
    std::vector<char> load_bearing(const DemSystem &s, int minimum_contacts)
    {
      const ParticleStore &ps = s.particles;
      const Index n = ps.size();
      std::vector<int> count(n, 0);
      std::vector<Index> offset(n + 1, 0);
      for (Index c = 0; c < s.contacts.size(); ++c)
        if (s.contacts.overlap[c] > 0)
        {
          ++offset[s.contacts.i[c] + 1];
          ++offset[s.contacts.j[c] + 1];
        }
      for (Index p = 0; p < n; ++p)
      {
        count[p] = static_cast<int>(offset[p + 1]);
        offset[p + 1] += offset[p];
      }
      std::vector<Index> partner(offset[n]);
      std::vector<Index> fill(offset.begin(), offset.end() - 1);
      for (Index c = 0; c < s.contacts.size(); ++c)
        if (s.contacts.overlap[c] > 0)
        {
          partner[fill[s.contacts.i[c]]++] = s.contacts.j[c];
          partner[fill[s.contacts.j[c]]++] = s.contacts.i[c];
        }
      for (const Wall &wall : s.walls)
        for (Index p = 0; p < n; ++p)
          if ((ps.position[p] - wall.point).dot(wall.normal) < ps.radius[p])
            ++count[p];
      std::vector<char> bearing(n, 1);
      std::vector<Index> pending;
      for (Index p = 0; p < n; ++p)
        if (count[p] < minimum_contacts)
        {
          bearing[p] = 0;
          pending.push_back(p);
        }
      while (!pending.empty())
      {
        const Index p = pending.back();
        pending.pop_back();
        for (Index k = offset[p]; k < offset[p + 1]; ++k)
        {
          const Index q = partner[k];
          if (bearing[q] && --count[q] < minimum_contacts)
          {
            bearing[q] = 0;
            pending.push_back(q);
          }
        }
      }
      return bearing;
    }

    /// Kinetic energy (translation and rotation, half-step velocities) of the marked spheres [J].
    double kinetic_energy(const ParticleStore &ps, const std::vector<char> &marked)
    {
      double sum = 0;
      for (Index p = 0; p < ps.size(); ++p)
        if (marked[p])
          sum += 0.5 * ps.mass[p] * ps.velocity[p].squaredNorm() +
                 0.5 * ps.inertia[p] * ps.angular_velocity[p].squaredNorm();
      return sum;
    }

    /// Minimum number of contacts of a load-bearing sphere: d + 1 = 4 frictionless (forces through
    /// the centre), 2 with friction (a sphere held by one contact carries no force).
    int minimum_load_bearing_contacts(double friction) { return friction > 0 ? 2 : 4; }

    struct ContactStatistics
    {
      double mechanical_coordination = 0;
      Index rattlers = 0;
      double max_overlap_ratio = 0;
    };

    ContactStatistics examine_contacts(const DemSystem &s, int minimum_contacts)
    {
      const ParticleStore &ps = s.particles;
      const std::vector<char> bearing = load_bearing(s, minimum_contacts);
      ContactStatistics out;
      Index bearing_pairs = 0, bearing_spheres = 0;
      for (Index c = 0; c < s.contacts.size(); ++c)
      {
        if (!(s.contacts.overlap[c] > 0))
          continue;
        const Index i = s.contacts.i[c], j = s.contacts.j[c];
        out.max_overlap_ratio =
          std::max(out.max_overlap_ratio, s.contacts.overlap[c] / std::min(ps.radius[i], ps.radius[j]));
        bearing_pairs += bearing[i] && bearing[j] ? 1 : 0;
      }
      for (const char b : bearing)
        bearing_spheres += b ? 1 : 0;
      out.rattlers = ps.size() - bearing_spheres;
      out.mechanical_coordination = bearing_spheres > 0 ? 2.0 * bearing_pairs / bearing_spheres : 0;
      return out;
    }

    /// Friction-free walls at the faces of the open axes (two per axis, lower then upper); returns
    /// the index of each axis' lower wall (-1 for periodic axes).
    std::array<Index, 3> add_box_walls(DemSystem &s, const ContactParameters &contact)
    {
      std::array<Index, 3> first_wall = {-1, -1, -1};
      const Vec3 length = s.domain.length();
      for (int a = 0; a < 3; ++a)
      {
        if (s.domain.periodic[a])
          continue;
        Wall wall;
        wall.contact = contact;
        wall.contact.friction = 0; // Potyondy & Cundall's frictionless vessel
        wall.control = WallControl::fixed;
        wall.area = length[(a + 1) % 3] * length[(a + 2) % 3];
        first_wall[a] = static_cast<Index>(s.walls.size());
        wall.name = std::string("dense packing ") + axis_name[a] + " lower";
        wall.normal = Vec3::Unit(a);
        wall.point = s.domain.lower;
        s.walls.push_back(wall);
        wall.name = std::string("dense packing ") + axis_name[a] + " upper";
        wall.normal = -Vec3::Unit(a);
        wall.point = s.domain.upper;
        s.walls.push_back(wall);
      }
      return first_wall;
    }

    /// Refuses particles already in the system that reach into the box [lower, upper].
    void require_outside(const ParticleStore &ps, const Vec3 &lower, const Vec3 &upper)
    {
      for (Index p = 0; p < ps.size(); ++p)
      {
        bool apart = false;
        for (int a = 0; a < 3; ++a)
          apart = apart || ps.position[p][a] + ps.radius[p] <= lower[a] || ps.position[p][a] - ps.radius[p] >= upper[a];
        if (!apart)
          throw SetupError(who + "particle " + std::to_string(p) +
                           " already in the system reaches into the packing's box");
      }
    }

    constexpr Index control_interval = 10;    ///< steps between servo updates and quiescence checks
    constexpr Index quiet_checks = 10;        ///< consecutive quiescent checks that reach a goal
    constexpr double unloading_slowdown = 10; ///< growth cap while unloading = max_growth / this
    constexpr double default_consolidation = 1e-2; ///< consolidation pressure / modulus by default
  } // namespace

  Index dense_packing_particle_count(const Vec3 &box_lower, const Vec3 &box_upper,
                                     const RadiusDistribution &radius, double solid_fraction)
  {
    validate_radius(radius);
    validate_box(box_lower, box_upper);
    require(solid_fraction > 0 && solid_fraction < 0.74,
            "solid_fraction must lie in (0, 0.74) (got " + num(solid_fraction) + ")");
    const double volume = (box_upper - box_lower).prod();
    return std::max<Index>(1, std::llround(solid_fraction * volume / mean_sphere_volume(radius)));
  }

  DensePackingReport add_dense_packing(DemSystem &system, const DensePackingSpec &spec)
  {
    validate(system, spec);
    if (spec.size_by == PackingSize::fill_box) // the final box is known: check before forming
      require_outside(system.particles, spec.box_lower, spec.box_upper);
    const Material &material = system.materials[spec.material];
    const Index n = spec.particle_count;

    // --- 1. small spheres by random sequential insertion
    Domain box;
    box.lower = spec.box_lower;
    box.upper = spec.box_upper;
    box.periodic = spec.periodic;
    const double box_volume = box.length().prod();
    std::mt19937_64 rng(spec.seed);
    std::uniform_real_distribution<double> draw_radius(spec.radius.mean - spec.radius.half_width,
                                                       spec.radius.mean + spec.radius.half_width);
    std::vector<double> radii(n);
    double solid_volume = 0;
    for (Index p = 0; p < n; ++p)
    {
      radii[p] = spec.radius.half_width > 0 ? draw_radius(rng) : spec.radius.mean;
      solid_volume += sphere_volume(radii[p]);
    }
    const double initial_factor = std::cbrt(spec.initial_solid_fraction * box_volume / solid_volume);
    for (double &r : radii)
      r *= initial_factor;
    const std::vector<Vec3> centres = insert_randomly(radii, box, rng);

    // --- 2. the scratch system: formation friction, no gravity, damping, walls on open axes
    DemSystem scratch;
    Material formation = material;
    formation.contact.friction = spec.formation_friction;
    formation.bond.enabled = false;
    scratch.materials.add(formation);
    scratch.domain = box;
    scratch.settings.gravity = Vec3::Zero();
    scratch.settings.local_damping = spec.local_damping;
    // A stiffness that does not grow with the overlap (the linear law) keeps the critical step
    // estimate valid between its evaluations, so the scratch run may step closer to it.
    if (!contact_stiffness_depends_on_overlap(formation.contact))
      scratch.settings.time_step_safety = 0.9;
    // Growing radii do work that no ledger term books: the energy balance cannot close.
    scratch.settings.energy_drift_tolerance = std::numeric_limits<double>::infinity();
    const std::array<Index, 3> first_wall = add_box_walls(scratch, formation.contact);
    for (Index p = 0; p < n; ++p)
      scratch.particles.add_sphere(centres[p], radii[p], material.density, 0);
    scratch.initialise();

    // --- 3. consolidation, then unloading to the target, each ending quiescent at its pressure
    const double target = spec.target_pressure;
    const double consolidation = spec.consolidation_pressure > 0
                                   ? spec.consolidation_pressure
                                   : default_consolidation * contact_law_modulus(formation.contact);
    std::vector<double> goals = {target};
    if (consolidation > target)
      goals.insert(goals.begin(), consolidation);
    const int minimum_contacts = minimum_load_bearing_contacts(spec.formation_friction);
    double shortest_edge = std::numeric_limits<double>::infinity();
    for (int a = 0; a < 3; ++a)
      shortest_edge = std::min(shortest_edge, box.length()[a] * (spec.periodic[a] ? 0.5 : 1.0));
    double largest_radius = *std::max_element(radii.begin(), radii.end());
    double growth_since_build = 1; // product of the growth factors > 1 since the last list build
    Index builds_seen = scratch.neighbor_builds();
    std::size_t goal = 0;
    double growth = spec.max_growth_per_step;
    double pressure = 0;
    double kinetic_ratio = std::numeric_limits<double>::infinity();
    Index quiet = 0;
    bool converged = false;
    Index steps = 0;
    while (steps < spec.max_steps)
    {
      scratch.step();
      ++steps;
      if (steps % control_interval == 0)
      {
        pressure = mean_pressure(scratch, first_wall);
        const double p_goal = goals[goal];
        bool quiescent = false;
        if (std::abs(pressure - p_goal) <= spec.pressure_tolerance * p_goal)
        {
          const double elastic = scratch.energy().elastic_contacts;
          kinetic_ratio =
            kinetic_energy(scratch.particles, load_bearing(scratch, minimum_contacts)) / elastic;
          quiescent = kinetic_ratio <= spec.kinetic_energy_ratio;
        }
        quiet = quiescent ? quiet + 1 : 0;
        if (quiet >= quiet_checks)
        {
          if (goal + 1 == goals.size())
          {
            converged = true;
            break;
          }
          ++goal;
          quiet = 0;
        }
        const bool unloading = goal > 0;
        const double cap = spec.max_growth_per_step / (unloading ? unloading_slowdown : 1.0);
        const double stiffness = affine_stiffness(scratch);
        growth = cap;
        if (stiffness > 0)
          growth = std::clamp(spec.servo_gain * (goals[goal] - pressure) / (control_interval * stiffness),
                              -cap, cap);
      }
      grow_radii(scratch.particles, 1 + growth);
      largest_radius *= 1 + growth;
      if (!(2 * largest_radius + scratch.skin() < shortest_edge)) // minimum images must stay unique
        throw SetupError(who + "the spheres grew to " + num(2 * largest_radius) +
                         " m across without reaching the pressure " + num(goals[goal]) + " Pa (at " +
                         num(pressure) + " Pa after " + std::to_string(steps) +
                         " steps): the box is too small for particle_count = " + std::to_string(n));
      // The Verlet list stays valid while every gap has closed by less than the skin since the
      // build: two displacements and two radius increments, each pair below skin / 2 in sum.
      if (scratch.neighbor_builds() != builds_seen)
      {
        builds_seen = scratch.neighbor_builds();
        growth_since_build = 1;
      }
      if (growth > 0)
        growth_since_build *= 1 + growth;
      const double radius_increment = largest_radius * (1 - 1 / growth_since_build);
      if (largest_displacement(scratch) + radius_increment >= 0.5 * scratch.skin())
      {
        scratch.rebuild_neighbors();
        builds_seen = scratch.neighbor_builds();
        growth_since_build = 1;
      }
    }
    double grown_volume = 0;
    for (const double r : scratch.particles.radius)
      grown_volume += sphere_volume(r);
    if (!converged)
      throw SetupError(who + "not converged within max_steps = " + std::to_string(spec.max_steps) + " while " +
                       (goal + 1 < goals.size() ? "consolidating at " : "unloading to target_pressure = ") +
                       num(goals[goal]) + " Pa: pressure " + num(pressure) + " Pa (tolerance " +
                       num(100 * spec.pressure_tolerance) + " %), solid fraction " + num(grown_volume / box_volume) +
                       ", kinetic / elastic energy of the load-bearing spheres " + num(kinetic_ratio) +
                       " (required <= " + num(spec.kinetic_energy_ratio) + ")");

    // --- 4. statistics of the formed packing
    DensePackingReport report;
    report.particles = n;
    report.steps = steps;
    report.pressure = pressure;
    report.consolidation_pressure = goals.size() > 1 ? goals.front() : 0.0;
    report.coordination = contact_and_bond_fabric(scratch).coordination;
    const ContactStatistics contacts = examine_contacts(scratch, minimum_contacts);
    report.mechanical_coordination = contacts.mechanical_coordination;
    report.rattlers = contacts.rattlers;
    report.max_overlap_ratio = contacts.max_overlap_ratio;
    double formed_mean_radius = 0;
    for (const double r : scratch.particles.radius)
      formed_mean_radius += r;
    formed_mean_radius /= static_cast<double>(n);

    // --- 5. final size and hand-over
    const double scale = spec.size_by == PackingSize::keep_radii ? spec.radius.mean / formed_mean_radius : 1.0;
    report.box_lower = box.lower;
    report.box_upper = box.lower + scale * box.length();
    report.mean_radius = scale * formed_mean_radius;
    report.radius_scale = report.mean_radius / spec.radius.mean;
    report.solid_fraction = grown_volume / box_volume; // invariant under the homothety

    if (spec.size_by == PackingSize::keep_radii)
      require_outside(system.particles, report.box_lower, report.box_upper);
    ParticleStore &ps = system.particles;
    report.first = ps.size();
    for (Index p = 0; p < n; ++p)
    {
      const Vec3 x = box.lower + scale * (scratch.domain.wrap(scratch.particles.position[p]) - box.lower);
      ps.add_sphere(x, scale * scratch.particles.radius[p], material.density, spec.material);
    }
    system.domain.lower = report.box_lower;
    system.domain.upper = report.box_upper;
    system.domain.periodic = spec.periodic;
    return report;
  }
} // namespace anticrack::dem
