#include "dem/lab/platen_compression_test.h"

#include <cmath>
#include <sstream>
#include <utility>

namespace anticrack::dem
{
  PlatenCompression::PlatenCompression(const DemSystem &system, const Index platen_a, const Index platen_b,
                                       const PlatenSettings &settings)
    : LabProtocol(settings.interval), a_(platen_a), b_(platen_b), settings_(settings)
  {
    const std::string who = "platen compression";
    const PlatenSettings &s = settings_;
    if (!(s.platen_speed > 0) || !std::isfinite(s.platen_speed))
      throw SetupError(who + ": platen speed " + format_for_message(s.platen_speed) + " m/s must be positive");
    if (!(s.post_peak_fraction > 0 && s.post_peak_fraction < 1))
      throw SetupError(who + ": post-peak fraction " + format_for_message(s.post_peak_fraction) + " must lie in (0, 1)");
    if (!(s.max_strain > 0 && s.max_strain <= 1))
      throw SetupError(who + ": max strain " + format_for_message(s.max_strain) + " must lie in (0, 1]");
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
                       format_for_message(a.normal.dot(b.normal)) + ")");
    if (!(gap(system) > 0))
      throw SetupError(who + ": platen '" + b.name + "' must lie on the particle side of platen '" + a.name +
                       "' (gap " + format_for_message(gap(system)) + " m must be positive)");
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
    m.force_a = system.walls[a_].normal_force();
    m.force_b = system.walls[b_].normal_force();
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
