// subsection Campaign of a DEM scene (dem/scene/parameters.h, parameters::Campaign): the loading
// angles, realizations and microstructures of a virtual-laboratory campaign, its quasi-static
// check, and the displacement-controlled tests it adds per realization (compaction, friction of the
// collapsed layer). The campaign itself is dem/campaign/campaign.h.
#include "dem/scene/lab_tests.h"
#include "dem/scene/parameters.h"
#include "util/parameter_files.h"
#include "util/problems.h"

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/utilities.h>

#include <stdexcept>
#include <string>

namespace anticrack::dem
{
  using dealii::ParameterHandler;
  namespace Patterns = dealii::Patterns;

  namespace parameters
  {
    // ----------------------------------------------------------------------------- Campaign
    const EnumTable<Campaign::QuasiStaticCheck> &Campaign::check_names()
    {
      static const EnumTable<QuasiStaticCheck> names{{"none", QuasiStaticCheck::none},
                                                     {"first realization", QuasiStaticCheck::first_realization},
                                                     {"all", QuasiStaticCheck::all}};
      return names;
    }

    void Campaign::declare_parameters(ParameterHandler &prm)
    {
      prm.enter_subsection("Campaign");
      prm.declare_entry("Loading angles [deg]", "", Patterns::List(Patterns::Double(-180, 360)),
                        "psi: loading angles of the mixed-mode test, the clump force direction being "
                        "(sin psi, 0, -cos psi): 0 = compression, 90 = shear, 180 = tension (Ritter et al. 2020). "
                        "Empty: the scene is a single run; otherwise `anticrack run` runs every angle x "
                        "realization x microstructure as a separate test (DEM/Boundary particles/Clump "
                        "force direction is then ignored) and writes campaign.h5. Units: degrees.");
      prm.declare_entry("Realizations", "1", Patterns::Integer(1),
                        "Samples per microstructure; realization r uses DEM/Random seed + r.");
      prm.declare_entry("Microstructures", "", Patterns::Anything(),
                        "Variants of DEM/Sample, separated by ';', each a comma-separated list of "
                        "`entry = value` of DEM/Sample (e.g. `Volume fraction = 0.3, Target "
                        "coordination number = 2.9; Volume fraction = 0.35, Target coordination "
                        "number = 3.5`). An entry with a '/' is a path below DEM, so that material "
                        "sweeps run the same way (`Bond/Tensile strength [Pa] = 2e6, Bond/Cohesion [Pa] = "
                        "2e6`). Empty: the scene's own sample is the one microstructure.");
      prm.declare_entry("Quasi-static check", "none", Patterns::Selection(check_names().pattern()),
                        "Which tests are repeated with every loading rate divided by Quasi-static "
                        "slowdown, to show that the failure point does not depend on the rate: none, "
                        "every angle and microstructure of the first realization, or all tests.");
      prm.declare_entry("Quasi-static slowdown", "4", Patterns::Double(1),
                        "Factor by which the reference runs load more slowly (>= 1). Dimensionless.");
      prm.declare_entry("Quasi-static tolerance", "0.02", Patterns::Double(0),
                        "Allowed relative difference |s - s_ref| / |s_ref| of the failure point "
                        "s = (p, q) of the Love-Weber stress between a test and its slow reference; "
                        "summary.json reports every difference (and that of the base stresses "
                        "(sigma, tau)) and whether it is within. Dimensionless.");
      prm.declare_entry("Compaction strain rate [1/s]", "0", Patterns::Double(0),
                        "Besides the tests at the loading angles, every realization of every microstructure "
                        "gets a displacement-controlled compaction test (DEM/Loading/Test = compaction, "
                        "psi = 0) at this strain rate, to Compaction final strain: the calibration reads "
                        "the softening, the residual strength, the fracture energy and the collapse height "
                        "from it (docs/calibration.md). Quasi-static check repeats it at the slower rate like "
                        "the others. 0 = no compaction tests. Units: 1/s.");
      prm.declare_entry("Compaction final strain", "0", Patterns::Double(0, 1),
                        "-u_z / H0 at which the compaction tests end: past the lock-up of the collapsed layer "
                        "(the calibration refuses a test that ends before it). Dimensionless.");
      prm.declare_entry("Compaction curve strain interval", curve_strain_interval_default, Patterns::Double(0),
                        std::string("The compaction tests' DEM/Loading/Curve strain interval. ") +
                          curve_strain_interval_help);
      prm.declare_entry("Friction normal stress [Pa]", "0", Patterns::Double(0),
                        "Besides the other tests, every realization of every microstructure gets a simple shear "
                        "of the collapsed layer (DEM/Loading/Test = simple shear, Mede et al. 2018) at this "
                        "constant normal stress, which must exceed the layer's compressive strength: the layer "
                        "collapses while the normal force ramps up, then the platen shears the collapsed grains. "
                        "The steady shear over normal stress is the failed layer's friction coefficient, which "
                        "the calibration hands to the FE (docs/calibration.md). 0 = no friction tests. Units: Pa.");
      prm.declare_entry("Friction shear velocity [m/s]", "0", Patterns::Double(0),
                        "The platen's velocity in the friction tests (> 0 when Friction normal stress is set; "
                        "the shear strain rate is this over the specimen height). Units: m/s.");
      prm.declare_entry("Friction consolidation time [s]", "0", Patterns::Double(0),
                        "The friction tests' normal-force ramp (> 0 when Friction normal stress is set): the "
                        "layer collapses during it. Units: s.");
      prm.declare_entry("Friction final shear strain", "0", Patterns::Double(0, 10),
                        "The shear strain at which the friction tests end (> 0 when Friction normal stress is "
                        "set); the steady sliding is read over its second half. Dimensionless.");
      prm.declare_entry("Friction sample", "", Patterns::Anything(),
                        "Entries of DEM/Sample that the friction tests' sample sets after the microstructure's, "
                        "as a comma-separated list of `entry = value` (an item without '=' continues the value "
                        "before it: `Particle count = 1405, Box aspect ratios = 1, 1, 1`). A collapsed layer "
                        "slides steadily only when it is thick enough: a 10-grain specimen sticks and slips, "
                        "15 grains slide (docs/calibration.md). The friction tests then have samples of their own, "
                        "one per microstructure and realization, with the same seeds. Empty: the friction tests "
                        "shear the microstructure's own sample.");
      prm.leave_subsection();
    }

    void Campaign::parse_parameters(ParameterHandler &prm)
    {
      prm.enter_subsection("Campaign");
      loading_angles_deg.clear();
      for (const std::string &a : dealii::Utilities::split_string_list(prm.get("Loading angles [deg]"), ','))
        loading_angles_deg.push_back(dealii::Utilities::string_to_double(a));
      realizations = prm.get_integer("Realizations");
      microstructures_text = prm.get("Microstructures");
      microstructures.clear();
      Problems problems("subsection Campaign");
      for (const std::string &variant : dealii::Utilities::split_string_list(microstructures_text, ';'))
        microstructures.push_back(entry_changes_in_list(variant, "Campaign/Microstructures", problems));
      friction_sample_text = prm.get("Friction sample");
      friction_sample = entry_changes_in_list(friction_sample_text, "Campaign/Friction sample", problems);
      for (const auto &[entry, value] : friction_sample)
        if (entry.find('/') != std::string::npos)
          problems.add("Campaign/Friction sample", "`" + entry + "` is not an entry of DEM/Sample (the friction "
                       "tests' sample differs from the microstructure's in its sample only; write the entry's "
                       "name without a path)");
      if (!problems.empty()) // read_scene names the file
        throw std::invalid_argument(problems.text());
      quasi_static_check = check_names().value(prm.get("Quasi-static check"));
      quasi_static_slowdown = prm.get_double("Quasi-static slowdown");
      quasi_static_tolerance = prm.get_double("Quasi-static tolerance");
      compaction_strain_rate = prm.get_double("Compaction strain rate [1/s]");
      compaction_final_strain = prm.get_double("Compaction final strain");
      compaction_curve_strain_interval = prm.get_double("Compaction curve strain interval");
      friction_normal_stress = prm.get_double("Friction normal stress [Pa]");
      friction_shear_velocity = prm.get_double("Friction shear velocity [m/s]");
      friction_consolidation_time = prm.get_double("Friction consolidation time [s]");
      friction_final_shear_strain = prm.get_double("Friction final shear strain");
      prm.leave_subsection();
    }

    void Campaign::check(Problems &problems, const SceneKind kind, const Dem &dem) const
    {
      if (!enabled())
      {
        if (kind != SceneKind::dem)
          problems.add("Campaign/Loading angles [deg]", "(empty)",
                       "a " + scene_kind_names().name(kind) + " scene runs the test at these angles: give at "
                       "least one (or make it one run: set Scene = dem, without subsection Campaign)");
        return;
      }
      if (const char *why_not = dem.loading.test->why_no_campaign)
        problems.add("Campaign/Loading angles [deg]", "(set)", why_not);
      const std::string why = "Campaign/Loading angles [deg] runs mixed-mode tests, which need ";
      if (!dem.has_clump() || !dem.boundary.has_fixed_base() || !(dem.boundary.clump_force_rate > 0))
        problems.add("Campaign/Loading angles [deg]", "(" + std::to_string(loading_angles_deg.size()) + " angles)",
                     why + "a fixed base (DEM/Boundary particles/Fix below [m] or Base thickness [mean "
                     "radii]), a clump (Clump above [m] or Actuator thickness [mean radii]) and Clump force "
                     "rate [N/s] > 0");
      if (!(dem.loading.stop_strain > 0))
        problems.add("DEM/Loading/Stop strain", dem.loading.stop_strain,
                     "must be positive in a campaign (allowed: > 0, e.g. 0.02), or every test runs all "
                     "DEM/Steps after its failure");
      if (has_compaction_tests() && !(compaction_final_strain > 0 && compaction_final_strain < 1))
        problems.add("Campaign/Compaction final strain", compaction_final_strain,
                     "must lie in (0, 1) when Compaction strain rate [1/s] is set: the compaction tests end there");
      else if (has_compaction_tests())
        check_curve_strain_interval(problems, "Campaign/Compaction curve strain interval",
                                    compaction_curve_strain_interval, compaction_final_strain);
      if (has_friction_tests())
      {
        const std::string why = "must be > 0 when Friction normal stress [Pa] is set: the friction tests need it";
        if (!(friction_shear_velocity > 0))
          problems.add("Campaign/Friction shear velocity [m/s]", friction_shear_velocity, why);
        if (!(friction_consolidation_time > 0))
          problems.add("Campaign/Friction consolidation time [s]", friction_consolidation_time, why);
        if (!(friction_final_shear_strain > 0))
          problems.add("Campaign/Friction final shear strain", friction_final_shear_strain, why);
      }
      else if (!friction_sample.empty())
        problems.add("Campaign/Friction sample", friction_sample_text,
                     "is the friction tests' sample, and there are none: set Friction normal stress [Pa] > 0, or "
                     "leave Friction sample empty");
    }
  } // namespace parameters

} // namespace anticrack::dem
