// HDF5 output of the DEM state: snapshots for post-processing and checkpoints for restarts.
//
// Snapshot ("anticrack-dem-snapshot", version 1): one self-describing file per output time.
//   /                 attributes time [s], step, dt [s], format, version, units
//   /particles        position, velocity, angular_velocity, force, torque (N x 3), radius, mass,
//                     inertia, material_id, group_id, clump_id, blocked (N)
//   /bonds            i, j (int64), shift (M x 3), state (uint8: 0 intact, 1 broken in tension,
//                     2 broken in shear), radius, normal_force, shear_force (M x 3), twist_moment,
//                     bending_moment (M x 3), sigma, tau (rim stresses, BondList::rim_stresses)
//   /domain           lower, upper (3) [m], periodic (3 ints)
//   /walls            name (strings), point, normal, velocity, force (W x 3) and the remaining
//                     wall fields (control, contact law and parameters, servo settings)
//   /energy           attributes kinetic, elastic_contacts, ... external_work [J] of system.energy()
// Every dataset carries a `units` string attribute ("m", "m/s", "N", "-" for ids and flags) and
// every array group a `count` attribute (its number of rows); empty datasets (no bonds, no walls)
// are written with zero rows. Strings are variable-length UTF-8: h5py reads them as str (datasets
// via .asstr()); C readers must ask for H5T_CSET_UTF8, HDF5 does not convert from ASCII.
//
// Checkpoint ("anticrack-dem-checkpoint", version 1): the complete run state, such that
// read_checkpoint + DemSystem::resume() continue a run bit for bit. It holds every array of the
// ParticleStore, previous_velocity / previous_angular_velocity, the whole ContactList (incl.
// overlap) and BondList (except the per-step `load` buffers), clumps (ragged members,
// member_offset and applied-force samples stored concatenated with a per-clump `<name>_count`;
// quaternions as w, x, y, z), walls, wall_shear, the domain, the IntegrationSettings (attributes
// of /settings), time, step_count, dt, the EnergyLedger (attributes of /energy) and
// initial_balance. State added to those structs must be added to the field lists in state_hdf5.cpp.
//
// Bit-for-bit restarts: the checkpoint also holds the neighbour list's reference positions and the
// last critical-step estimate, and resume() does not rebuild the list, so a checkpoint can be
// written at any step without changing the run, and a resumed run continues bit for bit.
//
// The MaterialTable is NOT stored: materials come from the scene, so the system passed to
// read_checkpoint must already hold the same materials as the one that wrote the checkpoint
// (read_checkpoint only checks that every material id it loads exists).
//
// Checkpoints are written to `file + ".tmp"`, flushed to disk and renamed over `file`, so a crash
// never leaves a half-written checkpoint under the real name. Snapshots use the same rename
// (without the flush), so readers polling the output directory never see partial files.
// Files are written with serial HDF5 (default file access); any failure throws std::runtime_error
// naming the file and the dataset (plus HDF5's own description of the innermost error).
#pragma once

#include "dem/core/system.h"

#include <string>
#include <vector>

namespace anticrack::dem::io
{
  /// A sample made elsewhere (e.g. grains segmented from tomography, Mede et al. 2018) or an earlier run's
  /// snapshot: spheres, optional rigid clumps of (overlapping) spheres, optional bonds with their
  /// cross-section. File layout (SI units):
  ///   /particles/position (N x 3), /particles/radius (N)          required
  ///   /particles/clump_id (N, int; -1 = free sphere)               optional: spheres sharing an id
  ///                                                                form one rigid clump
  ///   /bonds/i, /bonds/j (M, int64)                                optional
  ///   /bonds/area (M) [m^2] or /bonds/radius (M) [m]                optional bond cross-section
  ///   /bonds/state (M, uint8)                                      optional: only state 0 is taken
  /// An anticrack snapshot is such a file.
  struct ExternalSample
  {
    std::vector<Vec3> position;
    std::vector<double> radius;
    std::vector<int> clump_id;          ///< empty or one per sphere
    std::vector<Index> bond_i, bond_j;  ///< intact bonds
    std::vector<double> bond_radius;    ///< empty or one per bond (from area or radius)
  };

  /// Reads and validates an external sample (sizes, indices, positive radii and areas); errors name
  /// the file and the dataset.
  ExternalSample read_sample(const std::string &file);

  /// Writes the post-processing snapshot of `system` (format above) to `file`.
  void write_snapshot(const std::string &file, const DemSystem &system);

  /// Writes the complete restart state of `system` atomically to `file`.
  void write_checkpoint(const std::string &file, const DemSystem &system);

  /// Loads a checkpoint into `system`, replacing its particles, interactions, clumps, walls, domain,
  /// settings and run state; `system.materials` is kept (it must match the writer's). Validates
  /// the format, the version, the array sizes and the indices, and leaves `system` unchanged when
  /// any of that fails. Does not call resume(): the caller does, after any further set-up.
  void read_checkpoint(const std::string &file, DemSystem &system);
} // namespace anticrack::dem::io
