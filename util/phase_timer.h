// Where the time of a run goes: wall time per named phase (set-up, sample, each test, fits, mesh,
// assembly, solves, output, ...), accumulated over every time a phase is entered, in the order the
// phases first ran; summary.json records them under "timing"/"phases". The role of deal.II's
// TimerOutput, without deal.II, so that every run kind (DEM, campaign, calibration, FE) uses the
// same one.
//
//   PhaseTimer timer;
//   { auto scope = timer.scope("sample"); build_sample(); }
//   summary["timing"]["phases"] = timer.to_json();
#pragma once

#include <nlohmann/json.hpp>

#include <chrono>
#include <string>
#include <utility>
#include <vector>

namespace anticrack
{
  class PhaseTimer
  {
  public:
    /// Adds the wall time from construction to destruction to the phase `name`.
    class Scope
    {
    public:
      Scope(PhaseTimer &timer, std::string name)
        : timer_(timer), name_(std::move(name)), start_(std::chrono::steady_clock::now())
      {}
      Scope(const Scope &) = delete;
      Scope &operator=(const Scope &) = delete;
      ~Scope() { timer_.add(name_, std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count()); }

    private:
      PhaseTimer &timer_;
      std::string name_;
      std::chrono::steady_clock::time_point start_;
    };

    [[nodiscard]] Scope scope(const std::string &name) { return Scope(*this, name); }

    /// Adds `seconds` (and one call) to the phase `name`.
    void add(const std::string &name, const double seconds)
    {
      for (Phase &phase : phases_)
        if (phase.name == name)
        {
          phase.seconds += seconds;
          ++phase.calls;
          return;
        }
      phases_.push_back({name, seconds, 1});
    }

    [[nodiscard]] double seconds(const std::string &name) const
    {
      for (const Phase &phase : phases_)
        if (phase.name == name)
          return phase.seconds;
      return 0;
    }

    /// {"sample": {"wall_s": 1.2, "calls": 1}, ...} in the order the phases first ran.
    [[nodiscard]] nlohmann::ordered_json to_json() const
    {
      nlohmann::ordered_json phases = nlohmann::ordered_json::object();
      for (const Phase &phase : phases_)
        phases[phase.name] = {{"wall_s", phase.seconds}, {"calls", phase.calls}};
      return phases;
    }

  private:
    struct Phase
    {
      std::string name;
      double seconds = 0;
      long calls = 0;
    };
    std::vector<Phase> phases_;
  };
} // namespace anticrack
