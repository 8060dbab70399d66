#include "coupling/snow_units.h"

#include "dem/scene/parameters.h"
#include "util/format.h"
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

  std::vector<std::pair<std::string, std::string>> snow_ratio_changes(const dem::SceneParameters &scene,
                                                                      const SnowUnits &snow, const std::string &where)
  {
    const auto &dem = scene.dem;
    if (!dem.bond.bond.enabled || !(dem.bond.bond.modulus > 0) || !(dem.bond.bond.tensile_strength > 0))
      throw InputError(where + ": the weak layer's DEM has no bonds (DEM/Bond/Enabled), so it cannot be run at the "
                               "snow's bond modulus over strength");
    const double k = snow.stiffness_to_strength() / (dem.bond.bond.modulus / dem.bond.bond.tensile_strength);
    if (std::abs(k - 1) <= 1e-12)
      return {};
    if (dem.material.contact.law != dem::ContactLaw::linear)
      throw InputError(where + ": the weak layer's DEM uses a contact law other than `linear` (DEM/Material/Contact "
                               "law); only the linear law's modulus is scaled with the bonds' to run it at the snow's "
                               "Snow units/Bond modulus [Pa] over Bond tensile strength [Pa]");
    if (!scene.campaign.microstructures.empty())
      throw InputError(where + ": the weak layer's campaign has Campaign/Microstructures (" +
                       scene.campaign.microstructures_text +
                       "); the snow's bond modulus over strength is applied to the scene's own sample only");
    const auto text = [](double value) { return format_number(value, 17); };
    // σ̄_c stays the DEM's; Ē, E_c and ρ grow by k together, so sqrt(k/m) and every time scale of
    // the tests stay as they were; the strains to failure grow by about 1/k.
    std::vector<std::pair<std::string, std::string>> changes = {
      {"DEM/Bond/Modulus [Pa]", text(dem.bond.bond.modulus * k)},
      {"DEM/Material/Contact modulus [Pa]", text(dem.material.contact.contact_modulus * k)},
      {"DEM/Material/Density [kg/m^3]", text(dem.material.density * k)}};
    if (dem.loading.stop_strain > 0)
      changes.emplace_back("DEM/Loading/Stop strain", text(dem.loading.stop_strain / k));
    return changes;
  }

  double length_scale(const params::MicrostructureCalibration &c, const SnowUnits &snow)
  {
    if (!(c.grain_diameter > 0) || !std::isfinite(c.grain_diameter))
      throw InputError("microstructure " + std::to_string(c.index) +
                       " of the campaign records no grain diameter (campaigns of format 3 and older do not): its "
                       "lengths cannot be scaled to the snow's grains; run the campaign again");
    if (!(snow.grain_diameter > 0))
      throw InputError("Snow units/Grain diameter [m] must be > 0 (is " + std::to_string(snow.grain_diameter) + ")");
    return snow.grain_diameter / c.grain_diameter;
  }

  fem::MaterialFile in_snow_units(const fem::MaterialFile &dem_units, const params::MicrostructureCalibration &c,
                                  const SnowUnits &snow)
  {
    using fem::material_file_number;
    if (!(snow.particle_density > 0))
      throw InputError("Snow units/Particle density [kg/m^3] must be > 0 (is " + std::to_string(snow.particle_density) +
                       ")");
    const double S = stress_scale(c, snow);
    const double L = length_scale(c, snow);
    const double dem_ratio = c.material.particle_modulus / c.material.bond_tensile_strength;
    if (!(std::abs(dem_ratio / snow.stiffness_to_strength() - 1) <= 1e-9))
      throw InputError("microstructure " + std::to_string(c.index) + " of the campaign was run at a bond modulus over "
                       "tensile strength of " + std::to_string(dem_ratio) + ", the snow's is " +
                       std::to_string(snow.stiffness_to_strength()) +
                       " (Snow units/Bond modulus [Pa] over Bond tensile strength [Pa]): the DEM's response depends "
                       "on it, so the campaign must be run at the snow's (a pipeline does so)");
    fem::MaterialFile file = dem_units;
    fem::ContinuumMaterial &m = file.material;
    m.youngs_modulus *= S;
    m.p0 *= S;
    m.density = c.solid_fraction * snow.particle_density;
    m.reference_thickness *= L;
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
    file.comment.push_back("modulus, " + material_file_number(S * c.material.particle_modulus) +
                           " Pa, is the snow's: the DEM ran at its ratio): E and p0 and their intervals times S,");
    file.comment.push_back("exact for quasi-static tests without gravity (all forces scale by S, displacements are");
    file.comment.push_back("unchanged). Lengths times L = " + material_file_number(snow.grain_diameter) + " m / " +
                           material_file_number(c.grain_diameter) + " m = " + material_file_number(L) +
                           " (the snow's grain diameter over the DEM's;");
    file.comment.push_back("stresses and strains do not change with it): the reference thickness " +
                           material_file_number(m.reference_thickness) + " m. Density");
    file.comment.push_back("phi rho = " + material_file_number(c.solid_fraction) + " x " +
                           material_file_number(snow.particle_density) + " kg/m^3 (the grains' density sets only the "
                           "time scale of the tests).");
    file.comment.push_back("nu, beta, M, xi and the residual ratio are unchanged; of the");
    file.comment.push_back("collapse, the lock-up modulus and the energy densities times S, the lock-up strain unchanged.");
    return file;
  }

  fem::MaterialFile with_grain_diameter(const fem::MaterialFile &snow_units, double from, double to,
                                        const std::string &why)
  {
    using fem::material_file_number;
    if (!(from > 0) || !(to > 0))
      throw InputError("grain diameters must be > 0 to rescale a material's lengths (are " + material_file_number(from) +
                       " m and " + material_file_number(to) + " m)");
    fem::MaterialFile file = snow_units;
    file.material.reference_thickness *= to / from;
    file.comment.push_back("");
    file.comment.push_back("For grains of " + material_file_number(to) + " m (" + why + "), not " +
                           material_file_number(from) + " m: the reference thickness times");
    file.comment.push_back(material_file_number(to / from) + ", " + material_file_number(file.material.reference_thickness) +
                           " m (lengths scale with the grains; stresses and strains do not).");
    return file;
  }
} // namespace anticrack::coupling
