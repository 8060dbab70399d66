// ParaView output of the DEM state: VTK XML PolyData files (.vtp, ASCII, shortest round-trip
// decimal form of every double) and a .pvd collection that ties them into a time series.
//
//   particles .vtp  one vertex per sphere; point data radius [m], velocity [m/s],
//                   angular_velocity [rad/s], force [N], material_id, group_id, clump_id.
//                   Show as spheres with the "Point Gaussian" representation (Scale Array: radius,
//                   Gaussian Radius 1, shader "Sphere") or with a Glyph filter scaled by radius.
//   bonds .vtp      one line per bond (intact and broken; threshold on `state` to pick). The points
//                   are the particle centres, plus one extra point x_j + shift for each bond across
//                   a periodic boundary, so no line spans the box. Cell data: state (0 intact,
//                   1 broken in tension, 2 broken in shear), normal_force [N] (compression
//                   positive), shear_force [N] (magnitude), sigma and tau [Pa] (rim stresses).
//
// Every file is written to `file + ".tmp"` and renamed, so ParaView never reads a partial file.
#pragma once

#include "dem/core/system.h"

#include <limits>
#include <string>
#include <vector>

namespace anticrack::dem::io
{
  void write_particles_vtp(const std::string &file, const DemSystem &system);
  void write_bonds_vtp(const std::string &file, const DemSystem &system);

  /// A ParaView collection (.pvd) of datasets at given times. Every add() rewrites the .pvd so
  /// that it can be opened while the run goes on.
  class PvdCollection
  {
  public:
    struct Entry
    {
      double time; ///< [s]
      std::string file; ///< as written into the .pvd: relative to the .pvd's directory
    };

    explicit PvdCollection(std::string pvd_file);

    /// Records `dataset_file` (a path as the program opens it: absolute or relative to the working
    /// directory) at `time` and rewrites the .pvd.
    void add(double time, const std::string &dataset_file);

    /// For restarts: takes over the entries of an existing .pvd written by this class, keeping
    /// those with time <= `up_to_time` (the checkpoint time), and rewrites the file. No-op when the
    /// file does not exist.
    void load_existing(double up_to_time = std::numeric_limits<double>::infinity());

    [[nodiscard]] const std::vector<Entry> &entries() const { return entries_; }
    [[nodiscard]] const std::string &file() const { return pvd_file_; }

  private:
    void write() const;
    std::string pvd_file_;
    std::vector<Entry> entries_;
  };
} // namespace anticrack::dem::io
