#include "params/stress_path.h"

#include <cmath>

namespace anticrack::params
{
  double TestPath::lateral_stress_ratio() const
  {
    // Uniaxial strain of an isotropic solid: ε_xx = [σ_xx − ν (σ_yy + σ_zz)]/E = 0 with σ_xx = σ_yy.
    return laterally_confined ? poisson_ratio / (1.0 - poisson_ratio) : 0.0;
  }

  StressPoint TestPath::invariants(double sigma, double tau) const
  {
    const double k = lateral_stress_ratio();
    // Eq. (P1): σ = diag(−kσ, −kσ, −σ) + τ (e_x ⊗ e_z + e_z ⊗ e_x); s_zz − s_xx = −(1 − k) σ.
    return {(1.0 + 2.0 * k) * sigma / 3.0, std::sqrt((1.0 - k) * (1.0 - k) * sigma * sigma + 3.0 * tau * tau)};
  }

  double least_cam_clay_shear_ratio(const TestPath &path)
  {
    return (1.0 - path.lateral_stress_ratio()) / std::sqrt(3.0);
  }

  double chord_shear_deficit(const TestPath &path, double compression, double shear, double tension)
  {
    const StressPoint c = path.invariants(compression, 0), s = path.invariants(0, shear),
                      t = path.invariants(tension, 0);
    // The chord from the tensile point (p_t < 0) to the compressive one (p_c > 0), at p = 0.
    const double q_chord = t.shear + (c.shear - t.shear) * (0.0 - t.normal) / (c.normal - t.normal);
    return (q_chord - s.shear) / q_chord;
  }
} // namespace anticrack::params
