#include "dem/sample/lattice.h"

#include <random>

namespace anticrack::dem
{
  Index add_simple_cubic_lattice(DemSystem &system, const LatticeSpec &spec)
  {
    if (spec.radius <= 0 || spec.spacing <= 0)
      throw SetupError("lattice: radius and spacing must be positive");
    const double density = system.materials[spec.material].density;
    const Index first = system.particles.size();
    std::mt19937_64 rng(spec.seed);
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    for (Index k = 0; k < spec.cells[2]; ++k)
      for (Index j = 0; j < spec.cells[1]; ++j)
        for (Index i = 0; i < spec.cells[0]; ++i)
        {
          const Vec3 x = spec.origin + spec.spacing * Vec3(i + 0.5, j + 0.5, k + 0.5);
          const Index p = system.particles.add_sphere(x, spec.radius, density, spec.material);
          if (spec.velocity_amplitude > 0)
            for (int a = 0; a < 3; ++a)
              system.particles.velocity[p][a] = spec.velocity_amplitude * uniform(rng);
        }
    return first;
  }
} // namespace anticrack::dem
