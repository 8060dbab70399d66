// DEM/Sample/Type = simple cubic lattice (dem/sample/lattice.h).
#include "dem/sample/lattice.h"
#include "dem/scene/model.h"
#include "dem/scene/sample_types.h"
#include "dem/scene/scene_entries.h"
#include "util/problems.h"

#include <ostream>
#include <sstream>

namespace anticrack::dem
{
  namespace
  {
    using parameters::Sample;

    void declare(VariantEntries &entries)
    {
      entries.entry("Lattice size", "10, 10, 10", Patterns::List(Patterns::Integer(1), 3, 3),
                    "n_x, n_y, n_z: number of spheres along x, y and z (lattice only).");
      entries.shared("Radius [m]");
      entries.entry("Spacing [m]", "2e-3", Patterns::Double(0),
                    "s: distance between neighbouring centres; s = 2R makes touching spheres "
                    "(lattice only). Units: m.");
      entries.vector("Origin [m]", "0, 0, 0",
                     "Lower corner of the lattice's bounding box; the lattice occupies "
                     "[origin, origin + n s] and must lie inside the domain. Units: m.");
      entries.shared("Initial velocity amplitude [m/s]");
    }

    void parse(dealii::ParameterHandler &prm, Sample &s)
    {
      s.lattice_size = get_triple<std::array<Index, 3>>(prm, "Lattice size");
      s.spacing = prm.get_double("Spacing [m]");
      s.origin = get_triple<Vec3>(prm, "Origin [m]");
    }

    void check(const Sample &s, const parameters::Dem &d, Problems &problems)
    {
      check_radius(s, problems);
      if (!(s.spacing > 0))
        problems.add("DEM/Sample/Spacing [m]", s.spacing, "must be positive");
      else if (s.radius > 0.5 * s.spacing * (1 + 1e-12))
        problems.add("DEM/Sample/Radius [m]", s.radius,
                     "must be at most half of DEM/Sample/Spacing [m] = " + format_number(s.spacing) +
                       ", or neighbouring spheres start overlapping");
      const parameters::Bond &b = d.bond;
      if (b.bond.enabled && s.radius > 0 && s.spacing - 2 * s.radius > b.gap_tolerance * s.radius * (1 + 1e-12))
        problems.add("DEM/Bond/Gap tolerance", b.gap_tolerance,
                     "no lattice neighbours would be bonded: their gap spacing - 2 R = " +
                       format_number(s.spacing - 2 * s.radius) +
                       " m exceeds tolerance x R; raise the tolerance or set DEM/Bond/Enabled = "
                       "false");
      const Vec3 length = d.domain.length();
      const double tol = 1e-9 * length.cwiseAbs().maxCoeff();
      for (int a = 0; a < 3; ++a)
      {
        const double extent = s.lattice_size[a] * s.spacing;
        const double top = s.origin[a] + extent;
        if (s.origin[a] < d.domain.lower[a] - tol || top > d.domain.upper[a] + tol)
        {
          std::ostringstream why;
          why << "the lattice spans [" << s.origin[a] << ", " << top << "] m along " << axis_name[a]
              << " (origin + " << s.lattice_size[a] << " x spacing " << s.spacing
              << " m), outside the domain [" << d.domain.lower[a] << ", " << d.domain.upper[a] << "] m";
          problems.add("DEM/Sample/Origin [m]", vec(s.origin), why.str());
        }
        if (d.domain.periodic[a] && length[a] > 0)
        {
          // Minimum-image search: a contact partner must be nearer than half the period.
          const double needed = 2 * (2 * s.radius + verlet_skin(d.integration, s.radius));
          if (!(length[a] > needed))
            problems.add(std::string("DEM/Domain/Periodic axes"), axis_name[a],
                         "the period along " + std::string(axis_name[a]) + " (" + format_number(length[a]) +
                           " m) must exceed 2 (2 R + skin) = " + format_number(needed) +
                           " m for unique minimum images");
        }
      }
    }

    void build(const SceneParameters &scene, DemModel &model)
    {
      const auto &d = scene.dem;
      dem::LatticeSpec spec;
      spec.cells = d.sample.lattice_size;
      spec.radius = d.sample.radius;
      spec.spacing = d.sample.spacing;
      spec.origin = d.sample.origin;
      spec.material = 0;
      spec.velocity_amplitude = d.sample.velocity_amplitude;
      spec.seed = d.seed;
      dem::add_simple_cubic_lattice(model.system, spec);
    }

    void describe(std::ostream &s, const SceneParameters &scene, const DemModel &)
    {
      const Sample &sample = scene.dem.sample;
      s << "simple cubic lattice " << sample.lattice_size[0] << " x " << sample.lattice_size[1] << " x "
        << sample.lattice_size[2] << ", R = " << sample.radius << " m, spacing " << sample.spacing << " m";
    }
  } // namespace

  SampleType simple_cubic_lattice_sample()
  {
    return {{"simple cubic lattice", "n_x x n_y x n_z spheres with centres at origin + (k + 1/2) spacing.",
            declare}, parse, check, build, describe, nullptr};
  }
} // namespace anticrack::dem
