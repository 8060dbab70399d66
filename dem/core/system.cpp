#include "dem/core/system.h"

#include "dem/contact/contact_law.h"
#include "dem/contact/parallel_bond.h"
#include "dem/core/parallel_sum.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <set>
#include <sstream>

namespace anticrack::dem
{
  namespace
  {
    // Incidence entries: (pair index << 2) | (is_bond << 1) | (particle is the pair's j).
    constexpr Index incidence_bond = 2;
    constexpr Index incidence_side_j = 1;

    std::string format_vector(const Vec3 &v)
    {
      std::ostringstream s;
      s.precision(6);
      s << "(" << v[0] << ", " << v[1] << ", " << v[2] << ")";
      return s.str();
    }

    /// Adds the stiffness of a pair with normal n to a particle's diagonal stiffness sums
    /// (translation: k_n n_a^2 + k_s (1 - n_a^2); rotation: twist/bending springs plus the shear
    /// spring acting at the lever arm).
    void add_pair_stiffness(const Vec3 &n, double kn, double ks, double k_twist, double k_bend,
                            double arm, Vec3 &k_translation, Vec3 &k_rotation)
    {
      for (int a = 0; a < 3; ++a)
      {
        const double along = n[a] * n[a];
        k_translation[a] += kn * along + ks * (1 - along);
        k_rotation[a] += k_twist * along + (k_bend + ks * arm * arm) * (1 - along);
      }
    }

    /// Cundall's local damping force for one body, docs/physics.md §1.3: per component
    /// F_d = -alpha |F| sign(v), with v predicted at the full step.
    inline Vec3 local_damping_force(double alpha, const Vec3 &force, const Vec3 &velocity, double dt,
                             double mass)
    {
      Vec3 damping = Vec3::Zero();
      if (alpha <= 0)
        return damping;
      for (int a = 0; a < 3; ++a)
      {
        const double v = velocity[a] + 0.5 * dt * force[a] / mass;
        if (v != 0)
          damping[a] = -alpha * std::abs(force[a]) * (v > 0 ? 1.0 : -1.0);
      }
      return damping;
    }

    /// Leapfrog for one set of translational (or rotational) DOFs:
    /// v(n+1/2) = v(n-1/2) + dt (F + F_d)/m, unless the DOFs are blocked, in which case the velocity
    /// is the prescribed one and the work of the holding agent, (m dv/dt - F).v_mean dt, is booked.
    /// `v_minus` receives v(n-1/2); returns v(n+1/2).
    inline Vec3 leapfrog_update(bool blocked, double alpha, const Vec3 &force, double mass, double dt,
                         const Vec3 &velocity, const Vec3 &held_velocity, Vec3 &v_minus,
                         double &damping_work, double &external_work)
    {
      if (blocked)
      {
        v_minus = held_velocity;
        const Vec3 mean = 0.5 * (velocity + held_velocity);
        external_work += (mass * (velocity - held_velocity) / dt - force).dot(mean) * dt;
        return velocity;
      }
      v_minus = velocity;
      const Vec3 damping = local_damping_force(alpha, force, velocity, dt, mass);
      const Vec3 v_plus = velocity + dt * (force + damping) / mass;
      damping_work -= damping.dot(0.5 * (velocity + v_plus)) * dt;
      return v_plus;
    }

    /// The same with some components held (bit a of `held_axes`: component a keeps `velocity[a]`,
    /// a prescribed velocity, and the holding agent's work -F_a v_a dt is booked), the others
    /// integrated; used for clumps driven along some axes and free along others (simple shear).
    inline Vec3 leapfrog_update_partly_held(std::uint8_t held_axes, double alpha, const Vec3 &force, double mass,
                                            double dt, const Vec3 &velocity, Vec3 &v_minus, double &damping_work,
                                            double &external_work)
    {
      Vec3 free_force = force, held_force = Vec3::Zero();
      for (int a = 0; a < 3; ++a)
        if (held_axes & (1u << a))
          free_force[a] = 0, held_force[a] = force[a];
      // Zero force on a held component: no damping there, and its velocity is restored below.
      Vec3 v_plus = leapfrog_update(false, alpha, free_force, mass, dt, velocity, velocity, v_minus, damping_work,
                                    external_work);
      for (int a = 0; a < 3; ++a)
        if (held_axes & (1u << a))
          v_plus[a] = velocity[a];
      external_work -= held_force.dot(velocity) * dt;
      return v_plus;
    }
  } // namespace

  // ---------------------------------------------------------------------------------------------
  // Set-up

  void DemSystem::set_threads(int threads)
  {
    omp_set_num_threads(threads > 0 ? threads : omp_get_num_procs());
  }

  int DemSystem::threads() { return omp_get_max_threads(); }

  Index DemSystem::bond_touching_pairs(const BondingRule &rule)
  {
    if (!(rule.gap_tolerance >= 0))
      throw SetupError("bonding: gap tolerance must be >= 0");
    double r_max = 0;
    for (const double r : particles.radius)
      r_max = std::max(r_max, r);
    // Search with a skin just wide enough for the tolerance (and round-off on touching pairs).
    const double search_skin = std::max(rule.gap_tolerance, 1e-9) * r_max;
    ContactList candidates;
    NeighborList search;
    search.build(particles, domain, search_skin, candidates);

    std::set<std::pair<Index, Index>> existing;
    for (Index b = 0; b < bonds.size(); ++b)
      existing.emplace(std::min(bonds.i[b], bonds.j[b]), std::max(bonds.i[b], bonds.j[b]));

    Index added = 0;
    for (Index c = 0; c < candidates.size(); ++c)
    {
      const Index i = candidates.i[c], j = candidates.j[c];
      const Material &mi = materials[particles.material_id[i]];
      const Material &mj = materials[particles.material_id[j]];
      if (!mi.bond.enabled || !mj.bond.enabled || existing.count({i, j}) ||
          (!rule.only_pairs.empty() && !rule.only_pairs.count({i, j})))
        continue;
      const double ri = particles.radius[i], rj = particles.radius[j];
      const Vec3 branch = particles.position[j] + candidates.shift[c] - particles.position[i];
      const double gap = branch.norm() - ri - rj;
      if (gap > std::max(rule.gap_tolerance, 1e-9) * std::min(ri, rj))
        continue;
      add_bond(i, j);
      ++added;
    }
    return added;
  }

  Index DemSystem::add_bond(Index i, Index j, double bond_radius)
  {
    if (i < 0 || j < 0 || i >= particles.size() || j >= particles.size() || i == j)
      throw SetupError("add_bond: particle ids " + std::to_string(i) + " and " + std::to_string(j) +
                       " must be distinct and below " + std::to_string(particles.size()));
    const int mi = particles.material_id[i], mj = particles.material_id[j];
    const BondParameters &p = materials[std::min(mi, mj)].bond;
    const double ri = particles.radius[i], rj = particles.radius[j];
    const Vec3 shift = domain.minimum_image_shift(particles.position[i], particles.position[j]);
    const Vec3 branch = particles.position[j] + shift - particles.position[i];
    const double radius = bond_radius > 0 ? bond_radius : p.radius_multiplier * std::min(ri, rj);
    incidence_valid_ = false;
    return bonds.add(i, j, shift, branch.normalized(), radius, ri + rj, p.modulus, p.stiffness_ratio,
                     p.tensile_strength, p.cohesion, p.friction_angle, p.moment_factor);
  }

  Index DemSystem::add_clump(const std::vector<Index> &members)
  {
    // Members straddling a periodic face are brought next to the first member first.
    for (const Index p : members)
      if (p >= 0 && p < particles.size() && !members.empty())
        particles.position[p] +=
          domain.minimum_image_shift(particles.position[members.front()], particles.position[p]);
    clumps.push_back(make_clump(particles, members, static_cast<int>(clumps.size())));
    incidence_valid_ = false;
    return static_cast<Index>(clumps.size()) - 1;
  }

  void DemSystem::initialise()
  {
    if (!particles.consistent())
      throw SetupError("particle arrays have inconsistent lengths");
    for (int a = 0; a < 3; ++a)
      if (!(domain.upper[a] > domain.lower[a]))
        throw SetupError("domain: upper corner must exceed the lower corner along every axis");
    for (Index p = 0; p < particles.size(); ++p)
    {
      if (particles.material_id[p] < 0 || particles.material_id[p] >= materials.size())
        throw SetupError("particle " + std::to_string(p) + " has material id " +
                         std::to_string(particles.material_id[p]) + ", but only " +
                         std::to_string(materials.size()) + " materials are defined");
      if (!(particles.radius[p] > 0) || !(particles.mass[p] > 0))
        throw SetupError("particle " + std::to_string(p) + " has a non-positive radius or mass");
    }
    const IntegrationSettings &s = settings;
    if (!(s.local_damping >= 0 && s.local_damping < 1))
      throw SetupError("local damping must lie in [0, 1)");
    if (!(s.time_step_safety > 0 && s.time_step_safety <= 1))
      throw SetupError("time step safety factor must lie in (0, 1]");
    if (!(s.time_step >= 0) || s.time_step_interval < 1 || s.stability_check_interval < 1)
      throw SetupError("time step must be >= 0 and the check intervals >= 1");
    for (const Wall &w : walls)
      if (std::abs(w.normal.norm() - 1) > 1e-12)
        throw SetupError("wall '" + w.name + "' needs a unit normal");

    choose_skin();
    previous_velocity = particles.velocity;
    previous_angular_velocity = particles.angular_velocity;
    wall_shear.assign(walls.size() * particles.size(), Vec3::Zero());
    wall_dashpot.assign(walls.size() * particles.size(), Vec3::Zero());
    rebuild_neighbors();
    update_wall_overlaps();
    initial_balance = energy().balance();
    // Leapfrog treats the initial velocities as v(-1/2). The first step books gravity's work as
    // m g.v(-1/2) dt while the kinetic energy 1/2 m v(-1/2).v(1/2) grows by only half of it; the
    // other half belongs to the fictitious step before the start. Count it in the reference.
    double first_step_offset = 0;
    for (Index p = 0; p < particles.size(); ++p)
      if (particles.clump_id[p] < 0 && !(particles.blocked[p] & block_translation))
        first_step_offset += 0.5 * particles.mass[p] * settings.gravity.dot(particles.velocity[p]) * dt;
    for (const Clump &clump : clumps)
      first_step_offset += 0.5 * clump.mass * settings.gravity.dot(clump.velocity) * dt;
    initial_balance -= first_step_offset;
  }

  void DemSystem::resume()
  {
    choose_skin();
    const std::size_t wall_slots = walls.size() * particles.size();
    if (wall_shear.size() != wall_slots || wall_dashpot.size() != wall_slots)
      throw SetupError("checkpoint: sphere-wall state does not match the walls and particles");
    if (static_cast<Index>(neighbor_list_.reference_positions().size()) != particles.size())
      throw SetupError("checkpoint: the neighbour-list reference positions do not match the particles");
    // Derived data only; the contact list, positions and dt stay exactly as loaded.
    match_bonds_to_contacts();
    build_incidence();
    wall_load_.assign(wall_slots, Vec3::Zero());
    wall_overlap_.assign(wall_slots, 0.0);
    update_wall_overlaps();
    if (!(dt_critical_ > 0))
      dt_critical_ = critical_time_step(&dt_limiting_particle_);
  }

  void DemSystem::rebuild_neighbors()
  {
    for (Clump &clump : clumps)
    {
      clump.centre = domain.wrap(clump.centre);
      const Mat3 rotation = clump.orientation.toRotationMatrix();
      for (std::size_t m = 0; m < clump.members.size(); ++m)
        particles.position[clump.members[m]] = clump.centre + rotation * clump.member_offset[m];
    }
    neighbor_list_.build(particles, domain, skin_, contacts);
    for (Index b = 0; b < bonds.size(); ++b)
      bonds.shift[b] = domain.minimum_image_shift(particles.position[bonds.i[b]],
                                                   particles.position[bonds.j[b]]);
    match_bonds_to_contacts();
    build_incidence();
    // Sphere-wall loads and overlaps belong to the last step and survive a rebuild.
    if (wall_load_.size() != walls.size() * particles.size())
      wall_load_.assign(walls.size() * particles.size(), Vec3::Zero());
    if (wall_overlap_.size() != walls.size() * particles.size())
      wall_overlap_.assign(walls.size() * particles.size(), 0.0);
    update_time_step();
  }

  void DemSystem::choose_skin()
  {
    // The scene's skin, or a tenth of the mean radius: few rebuilds, few extra candidate pairs.
    if (particles.size() == 0)
      return;
    const double mean_radius =
      std::accumulate(particles.radius.begin(), particles.radius.end(), 0.0) / particles.size();
    skin_ = settings.verlet_skin > 0 ? settings.verlet_skin : 0.1 * mean_radius;
  }

  void DemSystem::update_wall_overlaps()
  {
    // Sphere-wall overlaps from the current geometry (the kernels store them during a step), so
    // that energy() counts initial or restored wall contacts before the first step.
    const Index n = particles.size();
    for (std::size_t w = 0; w < walls.size(); ++w)
      for (Index p = 0; p < n; ++p)
        wall_overlap_[w * n + p] = particles.radius[p] - (particles.position[p] - walls[w].point).dot(walls[w].normal);
  }

  void DemSystem::build_incidence()
  {
    const Index n = particles.size();
    incidence_offset_.assign(n + 1, 0);
    for (Index c = 0; c < contacts.size(); ++c)
    {
      ++incidence_offset_[contacts.i[c] + 1];
      ++incidence_offset_[contacts.j[c] + 1];
    }
    for (const Index b : unlisted_bonds_)
    {
      ++incidence_offset_[bonds.i[b] + 1];
      ++incidence_offset_[bonds.j[b] + 1];
    }
    for (Index p = 0; p < n; ++p)
      incidence_offset_[p + 1] += incidence_offset_[p];
    incidence_.resize(incidence_offset_[n]);
    std::vector<Index> fill(incidence_offset_.begin(), incidence_offset_.end() - 1);
    for (Index c = 0; c < contacts.size(); ++c)
    {
      incidence_[fill[contacts.i[c]]++] = c << 2;
      incidence_[fill[contacts.j[c]]++] = (c << 2) | incidence_side_j;
    }
    for (const Index b : unlisted_bonds_)
    {
      incidence_[fill[bonds.i[b]]++] = (b << 2) | incidence_bond;
      incidence_[fill[bonds.j[b]]++] = (b << 2) | incidence_bond | incidence_side_j;
    }
    incidence_valid_ = true;
  }

  void DemSystem::match_bonds_to_contacts()
  {
    // Both lists hold pairs with i < j; the contact list is sorted by (i, j).
    bond_of_contact_.assign(contacts.size(), -1);
    unlisted_bonds_.clear();
    bond_load_.assign(bonds.size(), PairLoad{});
    for (Index b = 0; b < bonds.size(); ++b)
    {
      Index lo = 0, hi = contacts.size();
      const std::pair<Index, Index> key(bonds.i[b], bonds.j[b]);
      while (lo < hi)
      {
        const Index mid = (lo + hi) / 2;
        if (std::make_pair(contacts.i[mid], contacts.j[mid]) < key)
          lo = mid + 1;
        else
          hi = mid;
      }
      if (lo < contacts.size() && contacts.i[lo] == key.first && contacts.j[lo] == key.second &&
          bond_of_contact_[lo] < 0)
        bond_of_contact_[lo] = b;
      else
        unlisted_bonds_.push_back(b);
    }
  }

  // ---------------------------------------------------------------------------------------------
  // Time step

  double DemSystem::critical_time_step(Index *where) const
  {
    const Index n = particles.size();
    std::vector<Vec3> k_translation(n, Vec3::Zero()), k_rotation(n, Vec3::Zero());
    auto add_to_both = [&](Index i, Index j, const Vec3 &normal, double kn, double ks, double kt,
                           double kb) {
      add_pair_stiffness(normal, kn, ks, kt, kb, particles.radius[i], k_translation[i], k_rotation[i]);
      add_pair_stiffness(normal, kn, ks, kt, kb, particles.radius[j], k_translation[j], k_rotation[j]);
    };
    for (Index c = 0; c < contacts.size(); ++c)
    {
      const Index i = contacts.i[c], j = contacts.j[c];
      const ContactParameters &p =
        materials.contact(particles.material_id[i], particles.material_id[j]);
      // A law whose stiffness does not depend on the overlap (the linear one) counts every candidate
      // pair, so that contacts forming before the next evaluation are covered.
      if (contact_stiffness_depends_on_overlap(p) && contacts.overlap[c] <= 0)
        continue;
      double kn, ks;
      contact_tangent_stiffness(p, particles.radius[i], particles.radius[j], contacts.overlap[c], kn, ks);
      const Vec3 normal = (particles.position[j] + contacts.shift[c] - particles.position[i]).normalized();
      add_to_both(i, j, normal, kn, ks, 0, 0);
    }
    for (Index b = 0; b < bonds.size(); ++b)
      if (bonds.state[b] == BondState::intact)
      {
        const Index i = bonds.i[b], j = bonds.j[b];
        const Vec3 normal = (particles.position[j] + bonds.shift[b] - particles.position[i]).normalized();
        add_to_both(i, j, normal, bonds.normal_stiffness[b], bonds.shear_stiffness[b],
                    bonds.twist_stiffness[b], bonds.bending_stiffness[b]);
      }
    for (std::size_t w = 0; w < walls.size(); ++w)
      for (Index p = 0; p < n; ++p)
      {
        const double gap = (particles.position[p] - walls[w].point).dot(walls[w].normal) - particles.radius[p];
        if (gap > skin_)
          continue;
        double kn, ks;
        contact_tangent_stiffness(walls[w].contact, particles.radius[p], 0,
                                  std::max(-gap, 0.01 * particles.radius[p]), kn, ks);
        add_pair_stiffness(walls[w].normal, kn, ks, 0, 0, particles.radius[p], k_translation[p],
                           k_rotation[p]);
      }

    double dt2 = std::numeric_limits<double>::infinity();
    Index limiting = -1;
    auto consider = [&](double mass, double inertia, const Vec3 &kt, const Vec3 &kr, Index id) {
      for (int a = 0; a < 3; ++a)
      {
        if (kt[a] > 0 && mass / kt[a] < dt2)
          dt2 = mass / kt[a], limiting = id;
        if (kr[a] > 0 && inertia / kr[a] < dt2)
          dt2 = inertia / kr[a], limiting = id;
      }
    };
    for (Index p = 0; p < n; ++p)
      if (particles.clump_id[p] < 0 && particles.blocked[p] != block_all)
        consider(particles.mass[p], particles.inertia[p], k_translation[p], k_rotation[p], p);
    for (std::size_t c = 0; c < clumps.size(); ++c)
    {
      const Clump &clump = clumps[c];
      Vec3 kt = Vec3::Zero(), kr = Vec3::Zero();
      for (std::size_t m = 0; m < clump.members.size(); ++m)
      {
        const Index p = clump.members[m];
        kt += k_translation[p];
        kr += k_rotation[p] + clump.member_offset[m].squaredNorm() * k_translation[p].maxCoeff() * Vec3::Ones();
      }
      consider(clump.mass, clump.principal_inertia.minCoeff(), kt, kr, -1 - static_cast<Index>(c));
    }
    if (!std::isfinite(dt2))
    {
      // Nothing touches: the P-wave estimate R sqrt(rho/E) of Bobillier et al. (2020), Eq. (1).
      for (Index p = 0; p < n; ++p)
      {
        const ContactParameters &c = materials[particles.material_id[p]].contact;
        const double modulus = contact_law_modulus(c);
        const double density = particles.mass[p] / sphere_volume(particles.radius[p]);
        const double estimate = particles.radius[p] * std::sqrt(density / modulus);
        if (estimate * estimate < dt2)
          dt2 = estimate * estimate, limiting = p;
      }
    }
    if (where)
      *where = limiting;
    return std::sqrt(dt2);
  }

  void DemSystem::update_time_step()
  {
    Index limiting = -1;
    dt_critical_ = critical_time_step(&limiting);
    dt_limiting_particle_ = limiting;
    if (settings.time_step > 0)
    {
      if (settings.enforce_critical_step && settings.time_step > dt_critical_)
      {
        std::ostringstream message;
        message << "time step " << settings.time_step << " s exceeds the critical time step "
                << dt_critical_ << " s at step " << step_count << " (t = " << time << " s), limited by "
                << (limiting >= 0 ? "particle " + std::to_string(limiting)
                                  : "clump " + std::to_string(-1 - limiting))
                << "; use a smaller fixed time step or the automatic one (time step = 0)";
        throw NumericalError(message.str());
      }
      dt = settings.time_step;
    }
    else
      dt = settings.time_step_safety * dt_critical_;
  }

  // ---------------------------------------------------------------------------------------------
  // The step

  void DemSystem::step()
  {
    if (!incidence_valid_ || neighbor_list_.needs_rebuild(particles, skin_))
      rebuild_neighbors();
    else if (step_count % settings.time_step_interval == 0)
      update_time_step();
    compute_pair_loads();
    compute_unlisted_bond_loads();
    gather_and_integrate();
    move_walls();
    time += dt;
    ++step_count;
    if (step_count % settings.stability_check_interval == 0)
      check_stability();
  }

  void DemSystem::run(Index n, const std::function<void(const DemSystem &)> &observer)
  {
    for (Index k = 0; k < n; ++k)
    {
      step();
      if (observer)
        observer(*this);
    }
  }

  void DemSystem::compute_pair_loads()
  {
    const auto &x = particles.position;
    const auto &v = particles.velocity;
    const auto &w = particles.angular_velocity;
    const auto &r = particles.radius;
    const FixedBlocks blocks(contacts.size());
    std::vector<std::array<double, 3>> partial(blocks.count());
#pragma omp parallel for schedule(static)
    for (Index block = 0; block < blocks.count(); ++block)
    {
      double friction = 0, viscous = 0, released = 0;
      for (Index c = blocks.begin(block); c < blocks.end(block); ++c)
      {
        const Index i = contacts.i[c], j = contacts.j[c];
        const Vec3 xj = x[j] + contacts.shift[c];
        const double reach = r[i] + r[j];
        const double distance2 = (xj - x[i]).squaredNorm();
        const Index b = bond_of_contact_[c];
        const bool bonded = b >= 0 && bonds.state[b] == BondState::intact;
        const bool touching = distance2 < reach * reach;
        PairLoad &load = contacts.load[c];
        const ContactParameters &p = materials.contact(particles.material_id[i], particles.material_id[j]);
        if (!touching && contacts.active[c])
        {
          // Separation: the tangential spring's energy is released, the contact stops acting, its
          // dashpot books its last half step.
          friction += contact_shear_energy_at_separation(p, r[i], r[j], contacts.shear_force[c]);
          if (p.damping_ratio > 0)
          {
            ContactDissipation dissipation;
            const PairKinematics k = pair_kinematics(x[i], xj, r[i], r[j], v[i], v[j], w[i], w[j]);
            book_dashpot_work(contacts.dashpot_force[c], Vec3::Zero(), k.relative_velocity, dt, dissipation);
            viscous += dissipation.viscous;
          }
          contacts.active[c] = 0;
          contacts.overlap[c] = reach - std::sqrt(distance2);
          contacts.shear_force[c].setZero();
          load = PairLoad{};
        }
        if (!touching && !bonded)
        {
          if (b >= 0)
            load = PairLoad{}; // a bond that broke earlier leaves nothing behind
          continue;
        }

        const PairKinematics k = pair_kinematics(x[i], xj, r[i], r[j], v[i], v[j], w[i], w[j]);
        load = PairLoad{};
        if (bonded)
        {
          // A bond and a contact that were both acting last step share the plane and its rotation.
          const bool shared_plane = touching && contacts.active[c] && contacts.normal[c] == bonds.normal[b];
          const ContactPlaneRotation rotation(bonds.normal[b], k.normal, k.mean_spin, dt);
          released += update_parallel_bond(bonds, b, k, rotation, dt, load);
          if (shared_plane)
          {
            rotation.apply(contacts.shear_force[c]);
            contacts.active[c] = 2; // rotated already
          }
        }
        if (!touching)
          continue;

        const double delta = reach - k.distance;
        if (contacts.active[c] == 1)
          rotate_with_contact_plane(contacts.shear_force[c], contacts.normal[c], k.normal, k.mean_spin, dt);
        else if (contacts.active[c] == 0)
          contacts.shear_force[c].setZero();
        contacts.normal[c] = k.normal;
        contacts.active[c] = 1;
        contacts.overlap[c] = delta;
        // Dashpot mass (only the dashpots need it): a blocked particle behaves as infinitely heavy.
        double m_eff = 0;
        if (p.damping_ratio > 0)
        {
          const double inv_mi = (particles.blocked[i] & block_translation) ? 0 : 1 / particles.mass[i];
          const double inv_mj = (particles.blocked[j] & block_translation) ? 0 : 1 / particles.mass[j];
          m_eff = inv_mi + inv_mj > 0 ? 1 / (inv_mi + inv_mj) : particles.mass[i];
        }
        ContactDissipation dissipation;
        const Vec3 f = contact_force(p, r[i], r[j], m_eff, delta, k, dt, contacts.shear_force[c],
                                     contacts.dashpot_force[c], dissipation);
        load.force_on_j += f;
        load.torque_on_j += k.arm_j.cross(f);
        load.torque_on_i -= k.arm_i.cross(f);
        friction += dissipation.friction;
        viscous += dissipation.viscous;
      }
      partial[block] = {friction, viscous, released};
    }
    const auto sums = add_in_order(partial);
    ledger.friction += sums[0];
    ledger.viscous += sums[1];
    ledger.bond_breakage += sums[2];
  }

  void DemSystem::compute_unlisted_bond_loads()
  {
    const auto &x = particles.position;
    const auto &v = particles.velocity;
    const auto &w = particles.angular_velocity;
    const auto &r = particles.radius;
    const FixedBlocks blocks(static_cast<Index>(unlisted_bonds_.size()));
    std::vector<std::array<double, 1>> partial(blocks.count());
#pragma omp parallel for schedule(static)
    for (Index block = 0; block < blocks.count(); ++block)
    {
      double released = 0;
      for (Index u = blocks.begin(block); u < blocks.end(block); ++u)
      {
        const Index b = unlisted_bonds_[u];
        if (bonds.state[b] != BondState::intact)
          continue; // its load was cleared when it broke
        const Index i = bonds.i[b], j = bonds.j[b];
        const PairKinematics k = pair_kinematics(x[i], x[j] + bonds.shift[b], r[i], r[j], v[i], v[j], w[i], w[j]);
        const ContactPlaneRotation rotation(bonds.normal[b], k.normal, k.mean_spin, dt);
        released += update_parallel_bond(bonds, b, k, rotation, dt, bond_load_[b]);
      }
      partial[block] = {released};
    }
    const auto sums = add_in_order(partial);
    ledger.bond_breakage += sums[0];
  }

  void DemSystem::gather_and_integrate()
  {
    const Index n = particles.size();
    const Index wall_count = static_cast<Index>(walls.size());
    const Vec3 gravity = settings.gravity;
    const double alpha = settings.local_damping;
    if (static_cast<Index>(previous_velocity.size()) != n)
    {
      previous_velocity = particles.velocity;
      previous_angular_velocity = particles.angular_velocity;
    }
    const FixedBlocks blocks(n);
    std::vector<std::array<double, 6>> partial(blocks.count());
#pragma omp parallel for schedule(static)
    for (Index block = 0; block < blocks.count(); ++block)
    {
      double damping_work = 0, external_work = 0, gravity_work = 0, wall_friction = 0, wall_viscous = 0, non_finite = 0;
      for (Index p = blocks.begin(block); p < blocks.end(block); ++p)
      {
        Vec3 force = Vec3::Zero(), torque = Vec3::Zero();
        for (Index e = incidence_offset_[p]; e < incidence_offset_[p + 1]; ++e)
        {
          const Index entry = incidence_[e];
          const PairLoad &load = (entry & incidence_bond) ? bond_load_[entry >> 2] : contacts.load[entry >> 2];
          if (entry & incidence_side_j)
          {
            force += load.force_on_j;
            torque += load.torque_on_j;
          }
          else
          {
            force -= load.force_on_j;
            torque += load.torque_on_i;
          }
        }
        // Sphere-wall contacts: the wall plays particle j, at rest in its own frame of rotation.
        const double radius = particles.radius[p];
        for (Index wi = 0; wi < wall_count; ++wi)
        {
          const Wall &wall = walls[wi];
          const Index slot = wi * n + p;
          const double distance = (particles.position[p] - wall.point).dot(wall.normal);
          const double delta = radius - distance;
          wall_overlap_[slot] = delta;
          Vec3 &shear = wall_shear[slot];
          if (delta <= 0 && wall_dashpot[slot].squaredNorm() == 0)
          {
            shear.setZero();
            wall_load_[slot].setZero();
            continue;
          }
          PairKinematics k;
          k.normal = -wall.normal;
          k.distance = distance;
          k.arm_i = 0.5 * (radius + distance) * k.normal;
          k.arm_j = Vec3::Zero();
          k.relative_velocity = wall.velocity - (particles.velocity[p] + particles.angular_velocity[p].cross(k.arm_i));
          k.relative_spin = -particles.angular_velocity[p];
          k.mean_spin = 0.5 * particles.angular_velocity[p];
          ContactDissipation dissipation;
          if (delta <= 0)
          {
            // Just separated with its dashpot acting: book the dashpot's last half step.
            book_dashpot_work(wall_dashpot[slot], Vec3::Zero(), k.relative_velocity, dt, dissipation);
            wall_viscous += dissipation.viscous;
            shear.setZero();
            wall_load_[slot].setZero();
            continue;
          }
          rotate_with_contact_plane(shear, k.normal, k.normal, k.mean_spin, dt);
          const double m_eff = particles.mass[p];
          const Vec3 on_wall =
            contact_force(wall.contact, radius, 0, m_eff, delta, k, dt, shear, wall_dashpot[slot], dissipation);
          wall_load_[slot] = -on_wall;
          force -= on_wall;
          torque -= k.arm_i.cross(on_wall);
          wall_friction += dissipation.friction;
          wall_viscous += dissipation.viscous;
        }
        particles.force[p] = force;
        particles.torque[p] = torque;
        if (particles.clump_id[p] >= 0)
          continue; // moved with its clump

        const double mass = particles.mass[p];
        const Vec3 total_force = force + mass * gravity;
        const Vec3 old_velocity = particles.velocity[p];
        const Vec3 old_spin = particles.angular_velocity[p];
        const bool translation_blocked = particles.blocked[p] & block_translation;
        const bool rotation_blocked = particles.blocked[p] & block_rotation;
        Vec3 v_minus, w_minus;
        const Vec3 v_plus = leapfrog_update(translation_blocked, alpha, total_force, mass, dt, old_velocity,
                                            previous_velocity[p], v_minus, damping_work, external_work);
        const Vec3 w_plus = leapfrog_update(rotation_blocked, alpha, torque, particles.inertia[p], dt, old_spin,
                                            previous_angular_velocity[p], w_minus, damping_work, external_work);
        // Gravity's work up to the state the ledger reports (forces of this step, i.e. positions
        // x(n)): m g.(x(n) - x(n-1)) = m g.v(n-1/2) dt. See initialise() for the first step.
        gravity_work += mass * gravity.dot(v_minus) * dt;
        // Blocked DOFs keep the prescribed velocity as their "previous" one (see leapfrog_update).
        previous_velocity[p] = translation_blocked ? v_plus : v_minus;
        previous_angular_velocity[p] = rotation_blocked ? w_plus : w_minus;
        particles.velocity[p] = v_plus;
        particles.angular_velocity[p] = w_plus;
        particles.position[p] += dt * v_plus;
        if (!std::isfinite(particles.position[p].squaredNorm() + v_plus.squaredNorm() + w_plus.squaredNorm()))
          non_finite += 1;
      }
      partial[block] = {damping_work, external_work, gravity_work, wall_friction, wall_viscous, non_finite};
    }
    const auto sums = add_in_order(partial);
    ledger.local_damping += sums[0];
    ledger.external_work += sums[1];
    ledger.gravity_potential -= sums[2];
    ledger.friction += sums[3];
    ledger.viscous += sums[4];
    if (sums[5] > 0)
    {
      Index first_bad = 0;
      while (first_bad < n && std::isfinite(particles.position[first_bad].squaredNorm() +
                                            particles.velocity[first_bad].squaredNorm() +
                                            particles.angular_velocity[first_bad].squaredNorm()))
        ++first_bad;
      std::ostringstream message;
      message << "non-finite state of particle " << first_bad << " at step " << step_count << " (t = " << time
              << " s): position " << format_vector(particles.position[first_bad]) << ", velocity "
              << format_vector(particles.velocity[first_bad]) << ", force "
              << format_vector(particles.force[first_bad]) << "; dt = " << dt << " s, critical estimate "
              << dt_critical_ << " s";
      throw NumericalError(message.str());
    }
    integrate_clumps();
  }

  void DemSystem::integrate_clumps()
  {
    const Vec3 gravity = settings.gravity;
    const double alpha = settings.local_damping;
    for (std::size_t c = 0; c < clumps.size(); ++c)
    {
      Clump &clump = clumps[c];
      const Mat3 rotation = clump.orientation.toRotationMatrix();
      Vec3 force = clump.applied_force(time) + clump.mass * gravity;
      Vec3 torque = Vec3::Zero();
      for (std::size_t m = 0; m < clump.members.size(); ++m)
      {
        const Index p = clump.members[m];
        force += particles.force[p];
        torque += (rotation * clump.member_offset[m]).cross(particles.force[p]) + particles.torque[p];
      }
      clump.force = force;
      clump.torque = torque;

      const Vec3 v_old = clump.velocity;
      Vec3 v_minus;
      double damping = 0, external = 0;
      const Vec3 v_plus =
        clump.held_axes != 0 && !(clump.blocked & block_translation) ?
          leapfrog_update_partly_held(clump.held_axes, alpha, force, clump.mass, dt, v_old, v_minus, damping,
                                      external) :
          leapfrog_update(clump.blocked & block_translation, alpha, force, clump.mass, dt, v_old, v_old, v_minus,
                          damping, external);
      const Vec3 v_mean = 0.5 * (v_minus + v_plus);
      external += clump.applied_force(time).dot(v_mean) * dt;
      ledger.gravity_potential -= clump.mass * gravity.dot(v_minus) * dt;

      // Rotation: leapfrog on the angular momentum, omega = I_world^-1 L.
      if (clump.rotation_locked)
      {
        clump.angular_momentum.setZero();
        clump.angular_velocity.setZero();
      }
      else
      {
        const Vec3 damping_torque =
          local_damping_force(alpha, torque, clump.angular_velocity, 0.0, 1.0);
        const Vec3 w_old = clump.angular_velocity;
        clump.angular_momentum += dt * (torque + damping_torque);
        clump.angular_velocity = clump.inverse_inertia_world() * clump.angular_momentum;
        damping -= damping_torque.dot(0.5 * (w_old + clump.angular_velocity)) * dt;
        const double angle = clump.angular_velocity.norm() * dt;
        if (angle > 0)
          clump.orientation =
            (Quat(Eigen::AngleAxisd(angle, clump.angular_velocity.normalized())) * clump.orientation).normalized();
      }
      ledger.local_damping += damping;
      ledger.external_work += external;

      clump.velocity = v_plus;
      clump.centre += dt * v_plus;
      clump.displacement += dt * v_plus;
      const Mat3 new_rotation = clump.orientation.toRotationMatrix();
      for (std::size_t m = 0; m < clump.members.size(); ++m)
      {
        const Index p = clump.members[m];
        const Vec3 arm = new_rotation * clump.member_offset[m];
        particles.position[p] = clump.centre + arm;
        particles.velocity[p] = clump.velocity + clump.angular_velocity.cross(arm);
        particles.angular_velocity[p] = clump.angular_velocity;
      }
      if (!std::isfinite(clump.centre.squaredNorm() + clump.angular_velocity.squaredNorm()))
        throw NumericalError("non-finite state of clump " + std::to_string(c) + " at step " +
                             std::to_string(step_count) + " (t = " + std::to_string(time) + " s)");
    }
  }

  void DemSystem::move_walls()
  {
    const Index n = particles.size();
    for (std::size_t w = 0; w < walls.size(); ++w)
    {
      Wall &wall = walls[w];
      Vec3 on_particles = Vec3::Zero();
      for (Index p = 0; p < n; ++p)
        on_particles += wall_load_[w * n + p];
      wall.force = -on_particles;
      ledger.external_work += on_particles.dot(wall.velocity) * dt;
      if (wall.control == WallControl::servo)
      {
        // Compressive force on the wall along its normal, driven towards target_stress * area.
        const double compressive = -wall.force.dot(wall.normal);
        double speed = wall.servo_gain * (wall.target_stress * wall.area - compressive);
        if (wall.max_speed > 0)
          speed = std::clamp(speed, -wall.max_speed, wall.max_speed);
        wall.velocity = speed * wall.normal;
      }
      else if (wall.control == WallControl::fixed)
        wall.velocity.setZero();
      wall.point += dt * wall.velocity;
    }
  }

  // ---------------------------------------------------------------------------------------------
  // Energies and stability

  EnergyLedger DemSystem::energy() const
  {
    EnergyLedger e = ledger;
    const Index n = particles.size();
    const bool have_previous = static_cast<Index>(previous_velocity.size()) == n;
    const auto kinetic = thread_independent_sum<1>(n, [&](Index p, std::array<double, 1> &sum) {
      if (particles.clump_id[p] >= 0)
        return;
      // 1/2 m v(n-1/2).v(n+1/2): the kinetic energy the leapfrog conserves with linear springs.
      const Vec3 &v_minus = have_previous ? previous_velocity[p] : particles.velocity[p];
      const Vec3 &w_minus = have_previous ? previous_angular_velocity[p] : particles.angular_velocity[p];
      sum[0] += 0.5 * particles.mass[p] * v_minus.dot(particles.velocity[p]) +
                0.5 * particles.inertia[p] * w_minus.dot(particles.angular_velocity[p]);
    })[0];
    double clump_kinetic = 0;
    for (const Clump &clump : clumps)
      clump_kinetic += 0.5 * clump.mass * clump.velocity.squaredNorm() +
                       0.5 * clump.angular_velocity.dot(clump.angular_momentum);
    double elastic_contacts =
      thread_independent_sum<1>(contacts.size(), [&](Index c, std::array<double, 1> &sum) {
        if (contacts.overlap[c] <= 0) // apart at the last evaluation (or at the build)
          return;
        const Index i = contacts.i[c], j = contacts.j[c];
        sum[0] += contact_elastic_energy(materials.contact(particles.material_id[i], particles.material_id[j]),
                                         particles.radius[i], particles.radius[j], contacts.overlap[c],
                                         contacts.shear_force[c]);
      })[0];
    for (std::size_t w = 0; w < walls.size(); ++w)
      for (Index p = 0; p < n && wall_overlap_.size() == walls.size() * n; ++p)
        elastic_contacts += contact_elastic_energy(walls[w].contact, particles.radius[p], 0,
                                                   wall_overlap_[w * n + p], wall_shear[w * n + p]);
    const double elastic_bonds = thread_independent_sum<1>(bonds.size(), [&](Index b, std::array<double, 1> &sum) {
      if (bonds.state[b] == BondState::intact)
        sum[0] += bonds.elastic_energy(b);
    })[0];
    e.kinetic = kinetic + clump_kinetic;
    e.elastic_contacts = elastic_contacts;
    e.elastic_bonds = elastic_bonds;
    return e;
  }

  double DemSystem::energy_scale(const EnergyLedger &e) const
  {
    // Absolute floor: 1/2 m (1e-6 R / dt_c)^2 per particle, i.e. a 1e-6 R deflection of its
    // stiffest springs. Below it the balance is round-off (a sample at rest); above it an unstable
    // step grows exponentially.
    double floor = 0;
    if (dt_critical_ > 0)
      for (Index p = 0; p < particles.size(); ++p)
      {
        const double v = 1e-6 * particles.radius[p] / dt_critical_;
        floor += 0.5 * particles.mass[p] * v * v;
      }
    return std::max({std::abs(initial_balance), e.kinetic + e.elastic_contacts + e.elastic_bonds,
                     std::abs(e.external_work), e.dissipated(), std::abs(e.gravity_potential), floor});
  }

  void DemSystem::check_stability()
  {
    const EnergyLedger e = energy();
    const double drift = std::abs(e.balance() - initial_balance);
    const double scale = energy_scale(e);
    if (!std::isfinite(e.balance()) || (drift > 0 && drift > settings.energy_drift_tolerance * scale))
    {
      std::ostringstream message;
      message << "unstable integration detected at step " << step_count << " (t = " << time
              << " s): the energy balance drifted by " << drift << " J, " << 100 * drift / scale
              << " % of the energy scale " << scale << " J (tolerance "
              << 100 * settings.energy_drift_tolerance << " %); kinetic energy " << e.kinetic
              << " J. dt = " << dt << " s, critical estimate " << dt_critical_ << " s (limiting "
              << (dt_limiting_particle_ >= 0 ? "particle " + std::to_string(dt_limiting_particle_)
                                             : "clump " + std::to_string(-1 - dt_limiting_particle_))
              << "). Reduce the time step or its safety factor.";
      throw NumericalError(message.str());
    }
  }
} // namespace anticrack::dem
