// DEM/Sample/Type = snapshot: the spheres of an anticrack HDF5 snapshot (dem/io/state_hdf5.h
// read_sample), with their clumps and bonds if it has them.
#include "dem/io/state_hdf5.h"
#include "dem/scene/model.h"
#include "dem/scene/sample_types.h"
#include "dem/scene/scene_entries.h"
#include "util/input_error.h"
#include "util/problems.h"

#include <fstream>
#include <map>
#include <ostream>
#include <random>

namespace anticrack::dem
{
  namespace
  {
    using parameters::Sample;

    void declare(VariantEntries &entries)
    {
      entries.shared("Initial velocity amplitude [m/s]");
      entries.entry("Snapshot file", "", Patterns::Anything(),
                    "HDF5 snapshot (snapshots/snapshot_NNNNNN.h5 of an earlier run) to take "
                    "the spheres from when Type = snapshot. A relative path is relative to "
                    "the working directory.");
    }

    void parse(dealii::ParameterHandler &prm, Sample &s)
    {
      s.snapshot_file = dealii::Utilities::trim(prm.get("Snapshot file"));
    }

    void check(const Sample &s, const parameters::Dem &, Problems &problems)
    {
      if (s.snapshot_file.empty())
        problems.add("DEM/Sample/Snapshot file", "(empty)",
                     "name the HDF5 snapshot to read when DEM/Sample/Type = snapshot");
      else if (!std::ifstream(s.snapshot_file))
        problems.add("DEM/Sample/Snapshot file", s.snapshot_file, "cannot be opened");
    }

    void build(const SceneParameters &scene, DemModel &model)
    {
      dem::DemSystem &system = model.system;
      const auto &d = scene.dem;
      dem::io::ExternalSample sample;
      try
      {
        sample = dem::io::read_sample(d.sample.snapshot_file);
      }
      catch (const std::exception &e)
      {
        throw InputError("DEM/Sample/Snapshot file = " + d.sample.snapshot_file + ": " + e.what());
      }
      const std::vector<Vec3> &position = sample.position;
      std::mt19937_64 rng(d.seed);
      std::uniform_real_distribution<double> uniform(-1.0, 1.0);
      const Index first = system.particles.size();
      for (std::size_t k = 0; k < position.size(); ++k)
      {
        for (int a = 0; a < 3; ++a)
          if (!d.domain.periodic[a] &&
              !(position[k][a] >= d.domain.lower[a] && position[k][a] <= d.domain.upper[a]))
            throw InputError("DEM/Sample/Snapshot file = " + d.sample.snapshot_file + ": sphere " +
                             std::to_string(k) + " at (" + format_vector(position[k]) +
                             ") m lies outside DEM/Domain");
        const Index p = system.particles.add_sphere(system.domain.wrap(position[k]), sample.radius[k],
                                                    d.material.density, 0);
        if (d.sample.velocity_amplitude > 0)
          for (int a = 0; a < 3; ++a)
            system.particles.velocity[p][a] = d.sample.velocity_amplitude * uniform(rng);
      }
      // Rigid grains: spheres sharing a clump id.
      std::map<int, std::vector<Index>> grains;
      for (std::size_t k = 0; k < sample.clump_id.size(); ++k)
        if (sample.clump_id[k] >= 0)
          grains[sample.clump_id[k]].push_back(first + static_cast<Index>(k));
      for (const auto &[id, members] : grains)
        system.add_clump(members);
      // Bonds given by the file replace the bonding of touching pairs.
      model.imported_bonds = !sample.bond_i.empty();
      for (std::size_t b = 0; b < sample.bond_i.size(); ++b)
        system.add_bond(first + sample.bond_i[b], first + sample.bond_j[b],
                        sample.bond_radius.empty() ? 0.0 : sample.bond_radius[b]);
    }

    void describe(std::ostream &s, const SceneParameters &scene, const DemModel &)
    {
      s << "snapshot " << scene.dem.sample.snapshot_file;
    }
  } // namespace

  SampleType snapshot_sample()
  {
    return {{"snapshot",
            "the positions and radii of an anticrack HDF5 snapshot (velocities start at zero; materials, bonds, "
            "walls and the rest come from this scene).",
            declare}, parse, check, build, describe, nullptr};
  }
} // namespace anticrack::dem
