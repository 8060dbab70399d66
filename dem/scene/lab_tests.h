// The values of DEM/Loading/Test: one LabTest per laboratory test, each in its own file of
// dem/scene/lab_tests/ (its name, documentation, entries, parsing, checks, what it adds to the
// model and the loading programme it runs, a dem::LabProtocol of dem/lab/), gathered in the table
// of dem/scene/lab_tests.cpp. dem/scene/parameters.cpp and dem/scene/model.cpp only iterate over
// the table.
#pragma once

#include "dem/lab/failure_point.h"
#include "dem/scene/variant.h"

#include <initializer_list>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace anticrack::dem
{
  class LabProtocol;
  namespace parameters
  {
    struct Loading;
  }

  struct LabTest : Variant
  {
    /// Reads its own entries into `loading` (Loading::parse_parameters reads the shared ones).
    void (*parse_parameters)(dealii::ParameterHandler &prm, parameters::Loading &loading);
    /// What it needs of its entries and of the rest of `dem` (the DEM/ `loading` belongs to).
    void (*check)(const parameters::Loading &loading, const parameters::Dem &dem, Problems &problems);
    /// Adds what the test brings to the model before it is initialised (walls), or null.
    void (*add_to_model)(const SceneParameters &scene, DemModel &model);
    /// The loading programme for a fresh run, started; nullptr when the scene only runs its steps.
    std::unique_ptr<LabProtocol> (*make_protocol)(const SceneParameters &scene, DemModel &model);
    /// Why a campaign (Campaign/Loading angles [deg]) cannot run this test; null if it can.
    const char *why_no_campaign;
    /// How the clump is driven, which decides how analyse_test_history finds failure: the run-away
    /// of a load-controlled test, or the peak of the base stress of a displacement-controlled one.
    ActuatorControl control;
  };

  /// Every lab test; the first is the default.
  const std::vector<LabTest> &lab_tests();
  /// The test of that DEM/Loading/Test name; std::logic_error if there is none.
  const LabTest &lab_test(const std::string &name);
  /// The documentation of DEM/Loading/Test: every test's paragraph.
  std::string lab_test_documentation();
  /// The entries of DEM/Loading that several tests read (their declare_parameters name them).
  const std::vector<SharedEntry> &shared_loading_entries();
  /// Reads the entries of shared_loading_entries() that `loading.test` has.
  void parse_shared_loading_entries(dealii::ParameterHandler &prm, parameters::Loading &loading);

  // ------------------------------------------------------ what the tests' files have in common
  /// LabTest::why_no_campaign of the wall-driven tests (triaxial, platen compression).
  inline constexpr const char *wall_tests_have_no_loading_angles =
    "campaigns run the clump tests at loading angles; the triaxial and platen tests have none";
  /// Entries of DEM/Loading that a test needs positive, though their patterns allow zero.
  void require_positive(Problems &problems, std::initializer_list<std::pair<const char *, double>> entries,
                        const std::string &why);
  /// The compaction curve's strain between two history rows (dem/lab/compaction_test.h), shared by
  /// DEM/Loading/Curve strain interval of a compaction scene and Campaign/Compaction curve strain
  /// interval: the default (docs/work_precision.md measures it), the documentation, and the check
  /// that a curve to `final_strain` gets the rows the fit needs.
  inline constexpr const char *curve_strain_interval_default = "5e-5";
  extern const char *const curve_strain_interval_help;
  void check_curve_strain_interval(Problems &problems, const std::string &entry, double interval,
                                   double final_strain);
  /// Tilted gravity and simple shear load the clump against the fixed base.
  void check_fixed_base_and_clump(const parameters::Loading &loading, const parameters::Dem &dem,
                                  Problems &problems);
} // namespace anticrack::dem
