// From scene parameters to a ready-to-run DemSystem: domain, material, sample, boundary particles
// (fixed base, loaded clump), bonds, walls and integration settings, then initialise(). Problems
// that show only once the sample exists (a `Fix below` that selects every sphere, a clump with no
// member) are InputErrors like those of the scene file; the engine's SetupErrors are re-raised as
// InputErrors too. Nothing here writes files.
#pragma once

#include "dem/scene/parameters.h"
#include "dem/sample/ballistic_deposition.h"
#include "dem/sample/dense_packing.h"
#include "dem/lab/lab_protocol.h"
#include "dem/sample/sticky_hard_spheres.h"
#include "dem/core/system.h"
#include "util/input_error.h"

#include <array>
#include <iosfwd>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace anticrack::dem
{
  /// The DEM model of a scene and the bookkeeping the application needs beside the system.
  struct DemModel
  {
    dem::DemSystem system;
    std::vector<Index> fixed_particles;   ///< the base (Boundary particles/Fix below)
    Index clump = -1;                     ///< index into system.clumps, -1 without a clump
    std::vector<int> wall_face;           ///< face index (0..5 = x-..z+) of system.walls[w]
    Index initial_bonds = 0;              ///< bonds created when the sample was built
    Index bedding_bonds = 0;              ///< bonds given the bedding strengths (DEM/Bedding)
    Index actuator_layer_first = -1;      ///< first sphere of the actuator layer (DEM/Sample), -1 = none
    bool imported_bonds = false;          ///< the sample file brought its own bonds
    double base_area = 0;                 ///< x-y cross-section of the domain [m^2]
    double critical_time_step = 0;        ///< dt_crit at initialise() [s]
    /// Statistics of the sample generator (DEM/Sample/Type = sticky hard spheres, ballistic
    /// deposition, dense random packing); summary.json records them under dem.sample, `anticrack
    /// check` prints them (SampleType::summarize, describe).
    std::optional<dem::shs::SamplerReport> sticky_hard_spheres;
    std::optional<dem::DepositionReport> ballistic_deposition;
    std::optional<dem::DensePackingReport> dense_packing;
    std::array<Index, 6> box_walls{-1, -1, -1, -1, -1, -1}; ///< the triaxial test's walls (BoxFace order)
    /// Wall time of build_dem_model (the sample generator, bonds, walls) [s]; a run reports it as
    /// its "sample and model" phase (0 for a copy of a model built for an earlier test).
    double build_seconds = 0;
  };

  /// A specimen whose bonds do not connect the fixed base to the actuator clump: the test would load
  /// nothing. One realization of a random sample can be such (found at N = 4096 in a 1 cm cube). A
  /// single run refuses it like bad input (exit 2); a campaign records that realization's tests as
  /// `no load path` and goes on, and the calibration names them among the tests it leaves out.
  class SpecimenWithoutLoadPath : public InputError
  {
  public:
    using InputError::InputError;
  };

  /// A test loads the sample from the actuator clump against the fixed base: the intact bonds, with
  /// the rigid clump and the fixed base each one body, must connect the two. Throws
  /// SpecimenWithoutLoadPath naming both ends and the size of the base's bonded cluster when they
  /// do not. build_dem_model() calls it for every model with a clump and a base.
  void require_load_path(const dem::DemSystem &system, const DemModel &model);

  /// Builds and initialises the model; `threads` <= 0 means all available.
  std::unique_ptr<DemModel> build_dem_model(const SceneParameters &scene, int threads);

  /// The loading programme of the scene's test (dem/lab/lab_protocol.h), or nullptr when the scene
  /// only runs its steps: the clump force ramp, the tilted-gravity actuator or simple shear
  /// (DEM/Boundary particles, DEM/Loading). Prepares the model for a fresh run (gravity, platen).
  std::unique_ptr<dem::LabProtocol> make_lab_protocol(const SceneParameters &scene, DemModel &model);

  /// Sets the engine's thread count (0: all available) and returns the count in use.
  int apply_thread_count(int threads);

  /// Puts the engine's thread count back, when it goes out of scope, to what it was when made: a
  /// driver that sets the count for its own runs (a campaign's worker processes run on one thread
  /// each) leaves the process as it found it, for the next driver in the same process.
  class ThreadCountRestorer
  {
  public:
    ThreadCountRestorer();
    ~ThreadCountRestorer();
    ThreadCountRestorer(const ThreadCountRestorer &) = delete;
    ThreadCountRestorer &operator=(const ThreadCountRestorer &) = delete;

  private:
    int threads_;
  };

  /// What `anticrack check` prints: components, sample, walls, clump, time step, outputs.
  void describe_dem_model(std::ostream &out, const SceneParameters &scene, const DemModel &model);

  /// Names of wall controls and contact laws for messages and summaries.
  std::string to_string(dem::WallControl control);
} // namespace anticrack::dem
