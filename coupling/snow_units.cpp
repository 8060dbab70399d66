#include "coupling/snow_units.h"

#include "util/input_error.h"

#include <cmath>

namespace anticrack::coupling
{
  double stress_scale(const params::MicrostructureCalibration &c, const SnowUnits &snow)
  {
    const double dem = c.material.bond_tensile_strength;
    if (!(dem > 0) || !std::isfinite(dem))
      throw InputError("microstructure " + std::to_string(c.index) + " of the campaign has no bond tensile strength (" +
                       std::to_string(dem) + " Pa): its stresses cannot be scaled to snow by the bond strength");
    if (!(snow.bond_tensile_strength > 0))
      throw InputError("Snow units/Bond tensile strength [Pa] must be > 0 (is " +
                       std::to_string(snow.bond_tensile_strength) + ")");
    return snow.bond_tensile_strength / dem;
  }

  fem::MaterialFile in_snow_units(const fem::MaterialFile &dem_units, const params::MicrostructureCalibration &c,
                                  const SnowUnits &snow)
  {
    using fem::material_file_number;
    if (!(snow.particle_density > 0))
      throw InputError("Snow units/Particle density [kg/m^3] must be > 0 (is " + std::to_string(snow.particle_density) +
                       ")");
    const double S = stress_scale(c, snow);
    fem::MaterialFile file = dem_units;
    fem::ContinuumMaterial &m = file.material;
    m.youngs_modulus *= S;
    m.p0 *= S;
    m.density = c.solid_fraction * snow.particle_density;
    for (fem::MaterialInterval *interval : {&file.uncertainty.youngs_modulus, &file.uncertainty.p0,
                                            &file.collapse.fracture_energy_density_interval})
      interval->lower *= S, interval->upper *= S;
    // The collapse: its modulus and energy densities (stress x strain) scale by S, its strain not.
    for (double *collapse_value : {&file.collapse.lock_up_modulus, &file.collapse.fracture_energy_density,
                                   &file.collapse.collapse_energy_density})
      *collapse_value *= S;
    m.name += " in snow units";
    file.comment.push_back("");
    file.comment.push_back("In snow units (coupling/snow_units.h): every modulus and strength of the DEM scaled by");
    file.comment.push_back("S = " + material_file_number(snow.bond_tensile_strength) + " Pa / " +
                           material_file_number(c.material.bond_tensile_strength) + " Pa = " +
                           material_file_number(S) + " (the snow's bond tensile strength over the DEM's; its bond");
    file.comment.push_back("modulus is then " + material_file_number(S * c.material.particle_modulus) +
                           " Pa): E and p0 and their intervals times S, exact for quasi-static");
    file.comment.push_back("tests without gravity (all forces scale by S, displacements are unchanged). Density");
    file.comment.push_back("phi rho = " + material_file_number(c.solid_fraction) + " x " +
                           material_file_number(snow.particle_density) + " kg/m^3 (the grains' density sets only the "
                           "time scale of the tests).");
    file.comment.push_back("nu, beta, M, xi, the residual ratio and the reference thickness are unchanged; of the");
    file.comment.push_back("collapse, the lock-up modulus and the energy densities times S, the lock-up strain unchanged.");
    return file;
  }
} // namespace anticrack::coupling
