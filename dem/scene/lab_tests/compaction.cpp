// DEM/Loading/Test = compaction (dem/lab/compaction_test.h): the clump, a rigid platen, is driven
// down at a constant strain rate, so that the run follows the strength drop past the peak, the
// collapse plateau and the lock-up of the collapsed layer (dem/lab/compaction_curve.h). Campaigns
// run it at psi = 0 beside their load-controlled tests (Campaign/Compaction strain rate [1/s]).
#include "dem/lab/compaction_test.h"
#include "dem/lab/measurements.h"
#include "dem/scene/lab_tests.h"
#include "dem/scene/model.h"
#include "dem/scene/scene_entries.h"
#include "util/problems.h"

#include <sstream>

namespace anticrack::dem
{
  const char *const curve_strain_interval_help =
    "Strain between two history rows of the compaction curve, in (0, final strain / 20]: the test "
    "records its curve in strain, not every Output/History interval [steps], so that the peak, the "
    "drop and the lock-up read from it depend neither on the time step (the sphere size) nor on an "
    "output interval (dem/lab/compaction_test.h; docs/work_precision.md measures it). Dimensionless.";

  void check_curve_strain_interval(Problems &problems, const std::string &entry, const double interval,
                                   const double final_strain)
  {
    const double largest = final_strain / static_cast<double>(compaction_minimum_samples);
    if (!(interval > 0 && interval <= largest))
    {
      std::ostringstream why;
      why << "must lie in (0, " << largest << "]: the final strain " << final_strain << " over the "
          << compaction_minimum_samples << " rows the curve's fit needs at the least";
      problems.add(entry, interval, why.str());
    }
  }

  namespace
  {
    using parameters::Loading;

    void declare(VariantEntries &entries)
    {
      entries.shared("Stop strain");
      entries.entry("Compaction strain rate [1/s]", "0", Patterns::Double(0),
                    "gamma_dot = v / H0: the platen's constant speed over the specimen's initial height "
                    "(compaction); slow enough for a stress wave to cross the layer many times before the peak "
                    "(dem/lab/compaction_test.h). Units: 1/s.");
      entries.entry("Curve strain interval", curve_strain_interval_default, Patterns::Double(0),
                    curve_strain_interval_help);
    }

    void parse(dealii::ParameterHandler &prm, Loading &l)
    {
      l.compaction_strain_rate = prm.get_double("Compaction strain rate [1/s]");
      l.curve_strain_interval = prm.get_double("Curve strain interval");
    }

    void check(const Loading &l, const parameters::Dem &d, Problems &problems)
    {
      check_fixed_base_and_clump(l, d, problems);
      require_positive(problems, {{"Compaction strain rate [1/s]", l.compaction_strain_rate}},
                       "must be positive for the compaction test");
      if (!(l.stop_strain > 0 && l.stop_strain < 1))
        problems.add("DEM/Loading/Stop strain", l.stop_strain,
                     "the compaction test ends at this strain: it must lie in (0, 1), past the lock-up of the "
                     "collapsed layer");
      else
        check_curve_strain_interval(problems, "DEM/Loading/Curve strain interval", l.curve_strain_interval,
                                    l.stop_strain);
    }

    std::unique_ptr<LabProtocol> make_protocol(const SceneParameters &scene, DemModel &model)
    {
      const auto &d = scene.dem;
      if (model.clump < 0)
        return nullptr;
      // Strains are relative to the specimen's initial height (the z extent of its spheres), as
      // the history's normal_strain column.
      const auto [low, high] = dem::sphere_extent(model.system.particles, 2);
      dem::CompactionSettings s;
      s.strain_rate = d.loading.compaction_strain_rate;
      s.height = high - low;
      s.final_strain = d.loading.stop_strain;
      s.curve_strain_interval = d.loading.curve_strain_interval;
      auto test = std::make_unique<dem::CompactionTest>(model.clump, model.fixed_particles, model.base_area, s);
      test->start(model.system);
      return test;
    }
  } // namespace

  LabTest compaction_test()
  {
    return {{"compaction",
             "displacement-controlled compaction: the clump, a rigid platen with its rotation locked, moves down "
             "at Compaction strain rate [1/s] x H0 to Stop strain, through the peak, the strength drop, the "
             "collapse plateau and the lock-up (the softening and collapse height of the calibration).",
             declare},
            parse,
            check,
            nullptr,
            make_protocol,
            "campaigns run the compaction test at psi = 0 beside their load-controlled tests: set "
            "Campaign/Compaction strain rate [1/s]",
            ActuatorControl::normal_displacement};
  }
} // namespace anticrack::dem
