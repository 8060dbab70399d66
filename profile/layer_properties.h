// The mechanical properties of a profile's layers, each with where it came from: measured (a layer
// table's density, a CAAML density profile averaged over the layer) or inferred by a cited law, which
// is named in the help, the summary and the report. docs/profile.md lists the laws with their ranges.
#pragma once

#include "profile/snow_profile.h"

#include <optional>
#include <string>
#include <vector>

namespace anticrack::profile
{
  /// A value and its provenance: "measured (...)" or the law that gave it.
  struct Sourced
  {
    double value = 0;
    bool measured = false;
    std::string source;
  };

  /// Density [kg/m^3] of a layer of grain form `grain_form` and hand hardness index `h` by the
  /// regressions of Geldsetzer & Jamieson (2000), per grain-form class (PP, PPgp, DF, RG, RGmx, FC,
  /// FCmx, DH); the class of a subclass code ("FCxr" -> FCmx) as in their grouping. nullopt for a
  /// grain form they do not cover (SH, MF, IF, MM, ...), `why` saying so.
  std::optional<double> geldsetzer_jamieson_density(const std::string &grain_form, double h, std::string *why = nullptr);

  /// The Geldsetzer & Jamieson (2000) class of an IACS grain-form code, or "" if none.
  std::string geldsetzer_jamieson_class(const std::string &grain_form);

  /// Young's modulus of snow [Pa] from its density: a law a user chooses (`Slab modulus law`).
  struct ModulusLaw
  {
    const char *name;     ///< the entry's value: "Gerling 2017"
    const char *citation; ///< "Gerling, Löwe & van Herwijnen (2017), GRL 44, acoustic fit"
    double (*modulus)(double density_kg_m3);
  };
  const std::vector<ModulusLaw> &modulus_laws();
  const ModulusLaw &modulus_law(const std::string &name); ///< throws std::out_of_range naming the laws

  /// Tensile strength of snow [Pa] from its density: Sigrist (2006), sigma_t = 240 kPa (rho/rho_ice)^2.44.
  double sigrist_tensile_strength(double density_kg_m3);

  struct LayerProperties
  {
    Sourced density;          ///< kg/m^3
    Sourced youngs_modulus;   ///< Pa
    Sourced poisson_ratio;
    Sourced tensile_strength; ///< Pa
  };

  /// The properties of layer `k` of `profile`: the density measured in the layer (a layer table's
  /// value; else the CAAML density samples that overlap the layer, weighted by their overlap), else
  /// inferred from hand hardness and grain form (Geldsetzer & Jamieson 2000; a layer with a top and
  /// a bottom hardness takes the mean of both); E by `law`, nu as given, the tensile strength by
  /// Sigrist (2006). Throws ProfileError naming the file, the layer and what is missing when no
  /// density can be had.
  LayerProperties layer_properties(const SnowProfile &profile, std::size_t k, const ModulusLaw &law, double poisson_ratio);

  /// The density of weak layer `k` [kg/m^3]: as layer_properties', except that a density sample of
  /// the profile counts only if more than half its height lies in the layer. A weak layer is often
  /// thinner than the cutter (a 100 cm^3 cutter is 4 cm tall): a sample mostly outside it measures
  /// its neighbours (pit 65798's 5 cm of facets between an ice crust and denser rounds got 460 kg/m^3
  /// from two such samples, where Geldsetzer & Jamieson give 204). Throws ProfileError as
  /// layer_properties does.
  Sourced weak_layer_density(const SnowProfile &profile, std::size_t k);
} // namespace anticrack::profile
