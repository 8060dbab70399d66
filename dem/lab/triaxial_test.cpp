#include "dem/lab/triaxial_test.h"

#include "dem/lab/measurements.h"
#include "dem/lab/stress_invariants.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace anticrack::dem
{
  TriaxialTest::TriaxialTest(const DemSystem &system, const std::array<Index, 6> &walls,
                             const TriaxialSettings &settings)
    : LabProtocol(settings.interval), walls_(walls), settings_(settings)
  {
    const std::string who = "triaxial test";
    const TriaxialSettings &s = settings_;
    if (!(s.confining_pressure > 0) || !std::isfinite(s.confining_pressure))
      throw SetupError(who + ": confining pressure " + format_for_message(s.confining_pressure) + " Pa must be positive");
    if (!(s.axial_strain_rate > 0) || !std::isfinite(s.axial_strain_rate))
      throw SetupError(who + ": axial strain rate " + format_for_message(s.axial_strain_rate) + " 1/s must be positive");
    if (!(s.final_axial_strain > 0 && s.final_axial_strain < 1))
      throw SetupError(who + ": final axial strain " + format_for_message(s.final_axial_strain) + " must lie in (0, 1)");
    if (!(s.consolidation_tolerance > 0 && s.consolidation_tolerance < 1))
      throw SetupError(who + ": consolidation tolerance " + format_for_message(s.consolidation_tolerance) +
                       " must lie in (0, 1)");
    if (!(s.kinetic_energy_ratio > 0))
      throw SetupError(who + ": kinetic energy ratio " + format_for_message(s.kinetic_energy_ratio) + " must be positive");
    if (!(s.servo_relaxation > 0 && s.servo_relaxation <= 1))
      throw SetupError(who + ": servo relaxation " + format_for_message(s.servo_relaxation) + " must lie in (0, 1]");
    if (!(s.max_servo_speed > 0) || !std::isfinite(s.max_servo_speed))
      throw SetupError(who + ": max servo speed " + format_for_message(s.max_servo_speed) + " m/s must be positive");
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
      throw SetupError("triaxial test: checkpoint stage " + format_for_message(stage) + " must be 0, 1 or 2");
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
      m.wall_stress[face] = system.walls[walls_[face]].normal_force() / area;
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
} // namespace anticrack::dem
