#include "dem/scene/lab_tests.h"

#include "dem/scene/parameters.h"
#include "dem/scene/scene_entries.h"
#include "util/problems.h"

namespace anticrack::dem
{
  // Each in its own file of dem/scene/lab_tests/.
  LabTest clump_force_test();
  LabTest tilted_gravity_test();
  LabTest simple_shear_test();
  LabTest triaxial_test();
  LabTest platen_compression_test();
  LabTest compaction_test();

  const std::vector<LabTest> &lab_tests()
  {
    static const std::vector<LabTest> tests{
      clump_force_test(), // the default
      tilted_gravity_test(),
      simple_shear_test(),
      triaxial_test(),
      platen_compression_test(),
      compaction_test(),
    };
    return tests;
  }

  const LabTest &lab_test(const std::string &name)
  {
    for (const LabTest &t : lab_tests())
      if (name == t.name)
        return t;
    throw std::logic_error("lab_test: no DEM/Loading/Test named '" + name + "'");
  }

  std::string lab_test_documentation()
  {
    return "How the clump (DEM/Boundary particles) loads the specimen. " + name_paragraphs(lab_tests());
  }

  const std::vector<SharedEntry> &shared_loading_entries()
  {
    static const std::vector<SharedEntry> entries{
      {"Adaptive rate", "false", std::make_shared<Patterns::Bool>(),
       "Adapt the clump force rate (dem/lab/load_control.h): DEM/Boundary particles/Clump "
       "force rate [N/s] is the fast rate of the elastic range; while bonds break or "
       "the base reaction lags the applied force, the rate drops to Slow rate "
       "fraction x fast, and recovers by Rate recovery factor per quiet interval. "
       "false = constant rate."},
      {"Slow rate fraction", "0.1", std::make_shared<Patterns::Double>(0, 1),
       "f_s: slow rate / fast rate, in (0, 1]. Dimensionless."},
      {"Control interval [steps]", "100", std::make_shared<Patterns::Integer>(1),
       "Steps between two rate decisions."},
      {"Rate recovery factor", "1.25", std::make_shared<Patterns::Double>(1),
       "Growth of the rate per quiet control interval, > 1. Dimensionless."},
      {"Lag tolerance", "0.02", std::make_shared<Patterns::Double>(0),
       "Relative lag |F_applied - R_base| / |F_applied| of the base reaction (projected "
       "on the force direction) above which the ramp slows. Dimensionless."},
      {"Stop strain", "0", std::make_shared<Patterns::Double>(0),
       "End the run once the clump has moved by this fraction of the specimen's "
       "initial height (|u_clump| / H0; Ritter et al. (2020) follow the collapse to ~8 %); "
       "DEM/Steps remains the upper limit. 0 = run DEM/Steps. Dimensionless."},
      {"Final axial strain", "0.2", std::make_shared<Patterns::Double>(0, 1),
       "Axial strain at which the triaxial test ends (Elyashiv et al. 2020: 0.2); the platen test's "
       "strain limit. Dimensionless."},
    };
    return entries;
  }

  void parse_shared_loading_entries(dealii::ParameterHandler &prm, parameters::Loading &l)
  {
    // Entries of other tests are not declared for this scene: they keep their defaults.
    const auto uses = [&](const std::string &entry) { return l.test->has_entry(entry); };
    if (uses("Adaptive rate"))
      l.adaptive = prm.get_bool("Adaptive rate");
    if (uses("Slow rate fraction"))
      l.ramp.slow_fraction = prm.get_double("Slow rate fraction");
    if (uses("Control interval [steps]"))
      l.ramp.interval = prm.get_integer("Control interval [steps]");
    if (uses("Rate recovery factor"))
      l.ramp.recovery_factor = prm.get_double("Rate recovery factor");
    if (uses("Lag tolerance"))
      l.ramp.lag_tolerance = prm.get_double("Lag tolerance");
    if (uses("Stop strain"))
      l.stop_strain = prm.get_double("Stop strain");
    if (uses("Final axial strain"))
      l.final_axial_strain = prm.get_double("Final axial strain");
  }

  void require_positive(Problems &problems, std::initializer_list<std::pair<const char *, double>> entries,
                        const std::string &why)
  {
    for (const auto &[name, value] : entries)
      if (!(value > 0))
        problems.add(std::string("DEM/Loading/") + name, value, why);
  }

  void check_fixed_base_and_clump(const parameters::Loading &l, const parameters::Dem &d, Problems &problems)
  {
    if (!(d.has_clump() && d.boundary.has_fixed_base()))
      problems.add("DEM/Loading/Test", std::string(l.test->name),
                   "needs a fixed base and a clump (DEM/Boundary particles: Fix below [m] or Base thickness "
                   "[mean radii], Clump above [m] or Actuator thickness [mean radii])");
  }
} // namespace anticrack::dem
