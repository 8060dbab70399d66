#include "dem/lab/lab_tests.h"

#include "dem/contact/contact_law.h"
#include "dem/lab/stress_invariants.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>
#include <vector>

namespace anticrack::dem
{
  namespace
  {
    const char *const face_name[6] = {"x-", "x+", "y-", "y+", "z-", "z+"};

    std::string number(const double x)
    {
      std::ostringstream s;
      s.precision(6);
      s << x;
      return s.str();
    }

    /// Per-wall blocks [w * n + p] of sphere-wall state, compacted to the kept particles (resized to
    /// the new count if the block layout does not match the old one).
    void keep_wall_slots(std::vector<Vec3> &slots, const std::vector<char> &keep, std::size_t walls, Index kept)
    {
      const std::size_t n = keep.size();
      if (slots.size() != walls * n)
      {
        slots.assign(walls * static_cast<std::size_t>(kept), Vec3::Zero());
        return;
      }
      std::vector<Vec3> compact;
      compact.reserve(walls * static_cast<std::size_t>(kept));
      for (std::size_t w = 0; w < walls; ++w)
        for (std::size_t p = 0; p < n; ++p)
          if (keep[p])
            compact.push_back(slots[w * n + p]);
      slots = std::move(compact);
    }

    /// Removes the particles with keep[p] == 0 (see carve_cylinder for the rules); returns the count.
    Index remove_particles(DemSystem &system, const std::vector<char> &keep, const std::string &who)
    {
      if (system.bonds.size() > 0 || !system.clumps.empty() || system.step_count > 0)
        throw SetupError(who + ": carve the specimen before bonding, clumping and stepping (the system has " +
                         std::to_string(system.bonds.size()) + " bonds, " + std::to_string(system.clumps.size()) +
                         " clumps and has run " + std::to_string(system.step_count) + " steps)");
      ParticleStore &ps = system.particles;
      const Index before = ps.size();
      ps.keep(keep);
      if (!ps.consistent())
        throw SetupError(who + ": particle arrays became inconsistent");
      const Index kept = ps.size();
      // Run state sized by the particle count (present after initialise()).
      if (static_cast<Index>(system.previous_velocity.size()) == before)
        keep_entries(system.previous_velocity, keep);
      if (static_cast<Index>(system.previous_angular_velocity.size()) == before)
        keep_entries(system.previous_angular_velocity, keep);
      keep_wall_slots(system.wall_shear, keep, system.walls.size(), kept);
      keep_wall_slots(system.wall_dashpot, keep, system.walls.size(), kept);
      // Candidate pairs hold old ids; initialise() builds the list again.
      system.contacts.clear();
      return before - kept;
    }

    Vec3 axis_vector(const int axis)
    {
      Vec3 e = Vec3::Zero();
      e[axis] = 1;
      return e;
    }

    /// Compressive normal force of a wall [N] (the particles push it against its normal).
    double compressive_force(const Wall &wall) { return -wall.force.dot(wall.normal); }
  } // namespace

  // ---------------------------------------------------------------------------------------------
  // Walls, specimens, formulas

  std::array<Index, 6> add_box_walls(DemSystem &system, const ContactParameters &contact)
  {
    const Domain &d = system.domain;
    for (int a = 0; a < 3; ++a)
    {
      if (d.periodic[a])
        throw SetupError("add_box_walls: domain axis " + std::string(1, "xyz"[a]) +
                         " is periodic; box walls need all three axes open (periodic = false)");
      if (!(d.upper[a] > d.lower[a]))
        throw SetupError("add_box_walls: domain upper corner must exceed the lower corner along " +
                         std::string(1, "xyz"[a]));
    }
    const Vec3 length = d.length();
    std::array<Index, 6> indices{};
    for (int face = 0; face < 6; ++face)
    {
      const int axis = face / 2;
      const bool upper = face % 2 == 1;
      Wall wall;
      wall.name = face_name[face];
      wall.normal = (upper ? -1.0 : 1.0) * axis_vector(axis);
      wall.point = upper ? d.upper : d.lower;
      wall.contact = contact;
      wall.control = WallControl::fixed;
      wall.area = length[(axis + 1) % 3] * length[(axis + 2) % 3];
      indices[face] = static_cast<Index>(system.walls.size());
      system.walls.push_back(wall);
    }
    return indices;
  }

  Index carve_cylinder(DemSystem &system, const int axis, const Vec3 &centre, const double radius)
  {
    if (axis < 0 || axis > 2)
      throw SetupError("carve_cylinder: axis " + std::to_string(axis) + " must be 0, 1 or 2 (x, y, z)");
    if (!(radius > 0) || !std::isfinite(radius))
      throw SetupError("carve_cylinder: radius " + number(radius) + " m must be positive and finite");
    const auto &x = system.particles.position;
    std::vector<char> keep(x.size());
    for (std::size_t p = 0; p < x.size(); ++p)
    {
      Vec3 off = x[p] - centre;
      off[axis] = 0;
      keep[p] = off.squaredNorm() <= radius * radius;
    }
    return remove_particles(system, keep, "carve_cylinder");
  }

  Index carve_box(DemSystem &system, const Vec3 &lower, const Vec3 &upper)
  {
    for (int a = 0; a < 3; ++a)
      if (!(upper[a] > lower[a]))
        throw SetupError("carve_box: upper corner must exceed the lower corner along " + std::string(1, "xyz"[a]) +
                         " (lower " + number(lower[a]) + " m, upper " + number(upper[a]) + " m)");
    const auto &x = system.particles.position;
    std::vector<char> keep(x.size());
    for (std::size_t p = 0; p < x.size(); ++p)
      keep[p] = (x[p].array() >= lower.array()).all() && (x[p].array() <= upper.array()).all();
    return remove_particles(system, keep, "carve_box");
  }

  double servo_gain_for(const DemSystem &system, const Wall &wall, const double relaxation)
  {
    if (!(relaxation > 0 && relaxation <= 1))
      throw SetupError("servo gain: relaxation " + number(relaxation) + " must lie in (0, 1]");
    if (!(system.dt > 0))
      throw SetupError("servo gain: the system has no time step yet; call DemSystem::initialise() first");
    const ParticleStore &ps = system.particles;
    double stiffness = 0, mean_radius = 0;
    for (Index p = 0; p < ps.size(); ++p)
    {
      mean_radius += ps.radius[p];
      const double overlap = ps.radius[p] - (ps.position[p] - wall.point).dot(wall.normal);
      if (overlap <= 0)
        continue;
      double kn, ks;
      contact_tangent_stiffness(wall.contact, ps.radius[p], 0, overlap, kn, ks);
      stiffness += kn;
    }
    if (ps.size() > 0)
      mean_radius /= static_cast<double>(ps.size());
    // Floor: one contact of the mean sphere (Hertz-Mindlin at 1 % overlap, as the critical time step
    // estimate of DemSystem assumes for a wall contact about to form).
    double kn_one = 0, ks_one;
    if (mean_radius > 0)
      contact_tangent_stiffness(wall.contact, mean_radius, 0, 0.01 * mean_radius, kn_one, ks_one);
    stiffness = std::max(stiffness, kn_one);
    if (!(stiffness > 0))
      throw SetupError("servo gain: wall '" + wall.name + "' has no contact stiffness (no particles?)");
    return relaxation / (stiffness * system.dt);
  }

  double mobilised_friction_angle(const double major, const double minor)
  {
    if (!(minor > 0) || !(major >= minor))
      throw SetupError("mobilised friction angle: needs major >= minor > 0 (compressive positive), got " +
                       number(major) + " and " + number(minor) + " Pa");
    return std::asin((major - minor) / (major + minor));
  }

  double brazilian_tensile_strength(const double force, const double diameter, const double thickness)
  {
    if (!(diameter > 0) || !(thickness > 0))
      throw SetupError("Brazilian tensile strength: diameter " + number(diameter) + " m and thickness " +
                       number(thickness) + " m must be positive");
    return 2 * force / (M_PI * diameter * thickness);
  }

  // ---------------------------------------------------------------------------------------------
  // Triaxial test

  namespace
  {
    /// Checks that walls[face] exist and are the inward faces of an axis-aligned box.
    void check_box_walls(const DemSystem &system, const std::array<Index, 6> &walls, const std::string &who)
    {
      for (int face = 0; face < 6; ++face)
      {
        const Index w = walls[face];
        if (w < 0 || w >= static_cast<Index>(system.walls.size()))
          throw SetupError(who + ": wall index " + std::to_string(w) + " of face " + face_name[face] +
                           " must lie in [0, " + std::to_string(system.walls.size()) +
                           ") (system.walls; create them with add_box_walls)");
        const int axis = face / 2;
        const Vec3 inward = (face % 2 == 1 ? -1.0 : 1.0) * axis_vector(axis);
        if ((system.walls[w].normal - inward).norm() > 1e-9)
          throw SetupError(who + ": wall " + std::to_string(w) + " ('" + system.walls[w].name + "') of face " +
                           face_name[face] + " must have the inward normal " +
                           (face % 2 == 1 ? "-e_" : "+e_") + std::string(1, "xyz"[axis]));
      }
      for (int axis = 0; axis < 3; ++axis)
      {
        const double lower = system.walls[walls[2 * axis]].point[axis];
        const double upper = system.walls[walls[2 * axis + 1]].point[axis];
        if (!(upper > lower))
          throw SetupError(who + ": the " + face_name[2 * axis + 1] + " wall must lie above the " +
                           face_name[2 * axis] + " wall along " + std::string(1, "xyz"[axis]));
      }
    }
  } // namespace

  TriaxialTest::TriaxialTest(const DemSystem &system, const std::array<Index, 6> &walls,
                             const TriaxialSettings &settings)
    : walls_(walls), settings_(settings)
  {
    const std::string who = "triaxial test";
    const TriaxialSettings &s = settings_;
    if (!(s.confining_pressure > 0) || !std::isfinite(s.confining_pressure))
      throw SetupError(who + ": confining pressure " + number(s.confining_pressure) + " Pa must be positive");
    if (!(s.axial_strain_rate > 0) || !std::isfinite(s.axial_strain_rate))
      throw SetupError(who + ": axial strain rate " + number(s.axial_strain_rate) + " 1/s must be positive");
    if (!(s.final_axial_strain > 0 && s.final_axial_strain < 1))
      throw SetupError(who + ": final axial strain " + number(s.final_axial_strain) + " must lie in (0, 1)");
    if (!(s.consolidation_tolerance > 0 && s.consolidation_tolerance < 1))
      throw SetupError(who + ": consolidation tolerance " + number(s.consolidation_tolerance) +
                       " must lie in (0, 1)");
    if (!(s.kinetic_energy_ratio > 0))
      throw SetupError(who + ": kinetic energy ratio " + number(s.kinetic_energy_ratio) + " must be positive");
    if (!(s.servo_relaxation > 0 && s.servo_relaxation <= 1))
      throw SetupError(who + ": servo relaxation " + number(s.servo_relaxation) + " must lie in (0, 1]");
    if (!(s.max_servo_speed > 0) || !std::isfinite(s.max_servo_speed))
      throw SetupError(who + ": max servo speed " + number(s.max_servo_speed) + " m/s must be positive");
    if (s.interval < 1)
      throw SetupError(who + ": control interval " + std::to_string(s.interval) + " steps must be >= 1");
    check_box_walls(system, walls_, who);
  }

  Vec3 TriaxialTest::box_length(const DemSystem &system) const
  {
    Vec3 length;
    for (int axis = 0; axis < 3; ++axis)
      length[axis] = system.walls[walls_[2 * axis + 1]].point[axis] - system.walls[walls_[2 * axis]].point[axis];
    return length;
  }

  void TriaxialTest::update_areas_and_gains(DemSystem &system) const
  {
    // The faces shrink and grow with the box: the lateral areas follow the axial shortening and the
    // target force sigma_c A must use the current area (Elyashiv et al. (2020) keep sigma_2 = sigma_3 constant).
    const Vec3 length = box_length(system);
    for (int face = 0; face < 6; ++face)
    {
      Wall &wall = system.walls[walls_[face]];
      const int axis = face / 2;
      wall.area = length[(axis + 1) % 3] * length[(axis + 2) % 3];
      if (wall.control == WallControl::servo)
        wall.servo_gain = servo_gain_for(system, wall, settings_.servo_relaxation);
    }
  }

  void TriaxialTest::start(DemSystem &system)
  {
    check_box_walls(system, walls_, "triaxial test");
    if (!(system.dt > 0))
      throw SetupError("triaxial test: start() needs the time step; call DemSystem::initialise() first");
    for (const Index w : walls_)
    {
      Wall &wall = system.walls[w];
      wall.control = WallControl::servo;
      wall.target_stress = settings_.confining_pressure;
      wall.max_speed = settings_.max_servo_speed;
      wall.velocity.setZero();
    }
    update_areas_and_gains(system);
    const Vec3 length = box_length(system);
    reference_height_ = length.z();
    reference_volume_ = length.prod();
    stage_ = TriaxialStage::consolidation;
    consolidation_end_step_ = -1;
  }

  void TriaxialTest::control(DemSystem &system)
  {
    update_areas_and_gains(system);
    if (stage_ == TriaxialStage::consolidation)
    {
      const TriaxialState now = measure(system);
      const double sigma_c = settings_.confining_pressure;
      bool converged = std::all_of(now.wall_stress.begin(), now.wall_stress.end(), [&](double s) {
        return std::abs(s - sigma_c) <= settings_.consolidation_tolerance * sigma_c;
      });
      if (converged)
      {
        const EnergyLedger e = system.energy();
        converged = e.kinetic <= settings_.kinetic_energy_ratio * (e.elastic_contacts + e.elastic_bonds);
      }
      if (!converged)
        return;
      // Stage (c) of Elyashiv et al. (2020): strains from here on are relative to the consolidated box.
      stage_ = TriaxialStage::axial_loading;
      consolidation_end_step_ = system.step_count;
      reference_height_ = now.box_length.z();
      reference_volume_ = now.volume;
      for (const int face : {z_lower, z_upper})
        system.walls[walls_[face]].control = WallControl::velocity;
    }
    if (stage_ == TriaxialStage::axial_loading)
    {
      const TriaxialState now = measure(system);
      if (now.deviator_stress > peak_deviator_)
      {
        peak_deviator_ = now.deviator_stress;
        peak_axial_strain_ = now.axial_strain;
        peak_axial_stress_ = now.axial_stress;
        peak_lateral_stress_ = now.lateral_stress;
      }
      const double height = box_length(system).z();
      const bool reached = (reference_height_ - height) / reference_height_ >= settings_.final_axial_strain;
      if (reached)
        stage_ = TriaxialStage::done;
      // Both z walls move towards the centre at strain_rate H / 2 (symmetric loading, Elyashiv et al. 2020), so
      // that dH/dt = -strain_rate H; they stop once the final strain is reached.
      const double speed = reached ? 0.0 : settings_.axial_strain_rate * height / 2;
      for (const int face : {z_lower, z_upper})
      {
        Wall &wall = system.walls[walls_[face]];
        wall.control = WallControl::velocity;
        wall.velocity = speed * wall.normal;
      }
    }
  }

  bool TriaxialTest::finished(const DemSystem &system) const
  {
    if (stage_ == TriaxialStage::done)
      return true;
    if (stage_ != TriaxialStage::axial_loading)
      return false;
    return measure(system).axial_strain >= settings_.final_axial_strain;
  }

  std::string TriaxialTest::stage(const DemSystem &system) const
  {
    const TriaxialState now = measure(system);
    std::ostringstream s;
    s.precision(6);
    if (finished(system))
      s << "axial strain " << now.axial_strain << " reached (final " << settings_.final_axial_strain
        << "), deviator " << now.deviator_stress << " Pa";
    else if (stage_ == TriaxialStage::axial_loading)
      s << "axial loading at " << settings_.axial_strain_rate << " 1/s, axial strain " << now.axial_strain
        << ", deviator " << now.deviator_stress << " Pa, lateral stress " << now.lateral_stress << " Pa";
    else
      s << "consolidation to " << settings_.confining_pressure << " Pa, mean wall stress " << now.mean_stress
        << " Pa";
    return s.str();
  }

  std::map<std::string, double> TriaxialTest::state() const
  {
    return {{"stage", static_cast<double>(stage_)},
            {"reference_height", reference_height_},
            {"reference_volume", reference_volume_},
            {"consolidation_end_step", static_cast<double>(consolidation_end_step_)},
            {"peak_deviator", peak_deviator_},
            {"peak_axial_strain", peak_axial_strain_},
            {"peak_axial_stress", peak_axial_stress_},
            {"peak_lateral_stress", peak_lateral_stress_}};
  }

  std::map<std::string, double> TriaxialTest::results(const DemSystem &system) const
  {
    const TriaxialState now = measure(system);
    std::map<std::string, double> r = {{"confining_pressure_Pa", settings_.confining_pressure},
                                       {"axial_strain", now.axial_strain},
                                       {"volumetric_strain", now.volumetric_strain},
                                       {"deviator_stress_Pa", now.deviator_stress},
                                       {"consolidation_end_step", static_cast<double>(consolidation_end_step_)}};
    if (peak_deviator_ > 0)
    {
      r["peak_deviator_stress_Pa"] = peak_deviator_;
      r["axial_strain_at_peak"] = peak_axial_strain_;
      r["peak_friction_angle_deg"] =
        mobilised_friction_angle(peak_axial_stress_, peak_lateral_stress_) * 180.0 / M_PI;
    }
    return r;
  }

  void TriaxialTest::restore(const std::map<std::string, double> &state)
  {
    const auto get = [&](const char *name, double fallback) {
      const auto it = state.find(name);
      return it != state.end() ? it->second : fallback;
    };
    const double stage = get("stage", static_cast<double>(stage_));
    if (!(stage >= 0 && stage <= 2))
      throw SetupError("triaxial test: checkpoint stage " + number(stage) + " must be 0, 1 or 2");
    stage_ = static_cast<TriaxialStage>(static_cast<int>(stage));
    reference_height_ = get("reference_height", reference_height_);
    reference_volume_ = get("reference_volume", reference_volume_);
    consolidation_end_step_ = static_cast<Index>(get("consolidation_end_step", static_cast<double>(consolidation_end_step_)));
    peak_deviator_ = get("peak_deviator", peak_deviator_);
    peak_axial_strain_ = get("peak_axial_strain", peak_axial_strain_);
    peak_axial_stress_ = get("peak_axial_stress", peak_axial_stress_);
    peak_lateral_stress_ = get("peak_lateral_stress", peak_lateral_stress_);
  }

  TriaxialState TriaxialTest::measure(const DemSystem &system) const
  {
    TriaxialState m;
    m.box_length = box_length(system);
    m.volume = m.box_length.prod();
    for (int face = 0; face < 6; ++face)
    {
      const int axis = face / 2;
      const double area = m.box_length[(axis + 1) % 3] * m.box_length[(axis + 2) % 3];
      m.wall_stress[face] = compressive_force(system.walls[walls_[face]]) / area;
    }
    m.lateral_stress_x = 0.5 * (m.wall_stress[x_lower] + m.wall_stress[x_upper]);
    m.lateral_stress_y = 0.5 * (m.wall_stress[y_lower] + m.wall_stress[y_upper]);
    m.axial_stress = 0.5 * (m.wall_stress[z_lower] + m.wall_stress[z_upper]);
    m.lateral_stress = 0.5 * (m.lateral_stress_x + m.lateral_stress_y);
    m.deviator_stress = m.axial_stress - m.lateral_stress;
    // Principal stresses of the box, tension positive for dem/lab/stress_invariants.h.
    const Mat3 boundary_stress = -Vec3(m.lateral_stress_x, m.lateral_stress_y, m.axial_stress).asDiagonal().toDenseMatrix();
    m.mean_stress = mean_pressure(boundary_stress);
    if (reference_height_ > 0)
      m.axial_strain = (reference_height_ - m.box_length.z()) / reference_height_;
    if (reference_volume_ > 0)
      m.volumetric_strain = (reference_volume_ - m.volume) / reference_volume_;
    return m;
  }

  // ---------------------------------------------------------------------------------------------
  // Platen compression

  PlatenCompression::PlatenCompression(const DemSystem &system, const Index platen_a, const Index platen_b,
                                       const PlatenSettings &settings)
    : a_(platen_a), b_(platen_b), settings_(settings)
  {
    const std::string who = "platen compression";
    const PlatenSettings &s = settings_;
    if (!(s.platen_speed > 0) || !std::isfinite(s.platen_speed))
      throw SetupError(who + ": platen speed " + number(s.platen_speed) + " m/s must be positive");
    if (!(s.post_peak_fraction > 0 && s.post_peak_fraction < 1))
      throw SetupError(who + ": post-peak fraction " + number(s.post_peak_fraction) + " must lie in (0, 1)");
    if (!(s.max_strain > 0 && s.max_strain <= 1))
      throw SetupError(who + ": max strain " + number(s.max_strain) + " must lie in (0, 1]");
    if (s.interval < 1)
      throw SetupError(who + ": control interval " + std::to_string(s.interval) + " steps must be >= 1");
    const Index count = static_cast<Index>(system.walls.size());
    for (const Index w : {a_, b_})
      if (w < 0 || w >= count)
        throw SetupError(who + ": platen wall index " + std::to_string(w) + " must lie in [0, " +
                         std::to_string(count) + ") (system.walls)");
    if (a_ == b_)
      throw SetupError(who + ": the two platens must be different walls (both are " + std::to_string(a_) + ")");
    const Wall &a = system.walls[a_], &b = system.walls[b_];
    if (a.normal.dot(b.normal) > -1 + 1e-9)
      throw SetupError(who + ": platens '" + a.name + "' and '" + b.name +
                       "' must be parallel with opposite normals (normal_a . normal_b = -1, got " +
                       number(a.normal.dot(b.normal)) + ")");
    if (!(gap(system) > 0))
      throw SetupError(who + ": platen '" + b.name + "' must lie on the particle side of platen '" + a.name +
                       "' (gap " + number(gap(system)) + " m must be positive)");
  }

  double PlatenCompression::gap(const DemSystem &system) const
  {
    const Wall &a = system.walls[a_], &b = system.walls[b_];
    return (b.point - a.point).dot(a.normal);
  }

  void PlatenCompression::start(DemSystem &system)
  {
    for (const Index w : {a_, b_})
    {
      Wall &wall = system.walls[w];
      wall.control = WallControl::velocity;
      wall.velocity = settings_.platen_speed * wall.normal;
    }
    initial_gap_ = gap(system);
    peak_force_ = 0;
    displacement_at_peak_ = 0;
  }

  void PlatenCompression::control(DemSystem &system)
  {
    const PlatenState now = measure(system);
    if (now.force > peak_force_)
    {
      peak_force_ = now.force;
      displacement_at_peak_ = now.displacement;
    }
  }

  bool PlatenCompression::post_peak(const DemSystem &system) const
  {
    return peak_force_ > 0 && measure(system).force < settings_.post_peak_fraction * peak_force_;
  }

  bool PlatenCompression::finished(const DemSystem &system) const
  {
    return post_peak(system) || measure(system).strain >= settings_.max_strain;
  }

  std::string PlatenCompression::stage(const DemSystem &system) const
  {
    const PlatenState now = measure(system);
    std::ostringstream s;
    s.precision(6);
    if (post_peak(system))
      s << "force " << now.force << " N fell below " << settings_.post_peak_fraction << " of the peak "
        << peak_force_ << " N";
    else if (now.strain >= settings_.max_strain)
      s << "strain " << now.strain << " reached the maximum " << settings_.max_strain << ", peak force "
        << peak_force_ << " N";
    else
      s << "platens at " << settings_.platen_speed << " m/s each, strain " << now.strain << ", force "
        << now.force << " N, peak " << peak_force_ << " N";
    return s.str();
  }

  std::map<std::string, double> PlatenCompression::state() const
  {
    return {{"initial_gap", initial_gap_}, {"peak_force", peak_force_}, {"displacement_at_peak", displacement_at_peak_}};
  }

  void PlatenCompression::restore(const std::map<std::string, double> &state)
  {
    for (auto [name, field] : {std::pair<const char *, double *>{"initial_gap", &initial_gap_},
                               {"peak_force", &peak_force_},
                               {"displacement_at_peak", &displacement_at_peak_}})
    {
      const auto it = state.find(name);
      if (it != state.end())
        *field = it->second;
    }
  }

  PlatenState PlatenCompression::measure(const DemSystem &system) const
  {
    PlatenState m;
    m.force_a = compressive_force(system.walls[a_]);
    m.force_b = compressive_force(system.walls[b_]);
    // The mean of the two platens: the inertial imbalance of the specimen cancels to first order.
    m.force = 0.5 * (m.force_a + m.force_b);
    if (initial_gap_ > 0)
    {
      m.displacement = initial_gap_ - gap(system);
      m.strain = m.displacement / initial_gap_;
    }
    m.peak_force = peak_force_;
    m.displacement_at_peak = displacement_at_peak_;
    return m;
  }
} // namespace anticrack::dem

namespace anticrack::dem
{
  std::map<std::string, double> PlatenCompression::results(const DemSystem &system) const
  {
    const PlatenState now = measure(system);
    return {{"peak_force_N", now.peak_force},
            {"displacement_at_peak_m", now.displacement_at_peak},
            {"initial_gap_m", initial_gap_},
            {"strain", now.strain},
            {"force_N", now.force}};
  }
} // namespace anticrack::dem
