// `anticrack bench dem`: the fixed benchmark of the DEM engine, comparable across codes (see
// tests/bench/yade_lattice.py for the YADE counterpart). An n x n x n simple-cubic lattice of
// touching spheres (R = 1 mm, spacing 2 mm, rho = 10 000 kg/m^3) in a fully periodic cube, every
// touching pair bonded (Ritter et al.'s (2020) parameters: E_c = E_bar = 1 GPa, kappa = 3, sigma_c = c = 1 MPa),
// tiny random velocities, local damping 0.7, automatic time step. Only system.run(steps) is timed;
// one JSON line goes to stdout and nothing else.
#pragma once

#include "dem/common/types.h"

namespace anticrack::app
{
  struct BenchOptions
  {
    dem::Index lattice = 20;
    dem::Index steps = 1000;
    int threads = 0; ///< 0: all available
  };

  int bench_dem(const BenchOptions &options);
} // namespace anticrack::app
