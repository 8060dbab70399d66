#include "profile/layer_properties.h"

#include "profile/profile_reader.h"
#include "util/format.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace anticrack::profile
{
  namespace
  {
    /// Geldsetzer & Jamieson (2000), density regressions on the hand hardness index h per grain-form
    /// class: rho = a + b h, and for rounded grains the power law rho = a + b h^c.
    struct DensityRegression
    {
      const char *grain_class;
      double a, b, c; ///< rho = a + b h^c [kg/m^3]
    };
    constexpr DensityRegression geldsetzer_jamieson_2000[] = {
      {"PP", 45, 36, 1},   {"PPgp", 83, 37, 1}, {"DF", 65, 36, 1},   {"RG", 154, 1.51, 3.15},
      {"RGmx", 91, 42, 1}, {"FC", 112, 46, 1},  {"FCmx", 56, 64, 1}, {"DH", 185, 25, 1},
    };

    /// The ice density of Sigrist's (2006) (rho/rho_ice) [kg/m^3].
    constexpr double rho_ice = 917.0;

    // Young's modulus laws as docs/physics.md §3 states them, E in Pa from rho in kg/m^3.
    double gerling_2017(double rho) { return 6.0e-10 * std::pow(rho, 4.6) * 1e6; }
    double scapozza_2004(double rho) { return 0.1873 * std::exp(0.0149 * rho) * 1e6; }
    double bergfeld_2023(double rho) { return 6.5e3 * std::pow(rho / 916.7, 4.4) * 1e6; }
  } // namespace

  std::string geldsetzer_jamieson_class(const std::string &g)
  {
    // Their classes are the IACS main classes; mixed forms are their own classes: rounding facets
    // (FCxr) and faceted rounded grains (RGxf) are FCmx and RGmx, and so are the other subclasses
    // of FC and RG.
    if (g == "PPgp")
      return "PPgp";
    for (const char *main : {"PP", "DF", "DH"})
      if (g.rfind(main, 0) == 0)
        return main;
    if (g == "FC" || g == "RG")
      return g;
    if (g.rfind("FC", 0) == 0)
      return "FCmx";
    if (g.rfind("RG", 0) == 0)
      return "RGmx";
    return "";
  }

  std::optional<double> geldsetzer_jamieson_density(const std::string &grain_form, double h, std::string *why)
  {
    const std::string grain_class = geldsetzer_jamieson_class(grain_form);
    for (const DensityRegression &r : geldsetzer_jamieson_2000)
      if (grain_class == r.grain_class)
        return r.a + r.b * std::pow(h, r.c);
    if (why)
      *why = grain_form.empty() ? "no grain form" :
                                  "grain form " + grain_form + " is not among Geldsetzer & Jamieson's (2000) classes "
                                  "(PP, PPgp, DF, RG and its subclasses, FC and its subclasses, DH)";
    return std::nullopt;
  }

  const std::vector<ModulusLaw> &modulus_laws()
  {
    static const std::vector<ModulusLaw> laws = {
      {"Gerling 2017", "Gerling, Löwe & van Herwijnen (2017), Geophys. Res. Lett. 44, acoustic fit: E = 6.0e-10 rho^4.6 MPa",
       gerling_2017},
      {"Scapozza 2004", "Scapozza (2004): E = 0.1873 exp(0.0149 rho) MPa", scapozza_2004},
      {"Bergfeld 2023", "Bergfeld et al. (2023), Nat. Hazards Earth Syst. Sci. 23: E = 6.5e3 (rho/916.7)^4.4 MPa",
       bergfeld_2023},
    };
    return laws;
  }

  const ModulusLaw &modulus_law(const std::string &name)
  {
    std::string names;
    for (const ModulusLaw &law : modulus_laws())
    {
      if (name == law.name)
        return law;
      names += std::string(names.empty() ? "" : ", ") + law.name;
    }
    throw std::out_of_range("`" + name + "` is not a modulus law (" + names + ")");
  }

  double sigrist_tensile_strength(double rho) { return 240e3 * std::pow(rho / rho_ice, 2.44); }

  namespace
  {
    /// Layer k's density: measured in it; else the density samples of the profile that overlap it,
    /// weighted by their overlap, counting only a sample with more than `inside` of its height in
    /// the layer (any overlap for inside = 0); else inferred from hand hardness and grain form (Geldsetzer & Jamieson 2000).
    Sourced layer_density(const SnowProfile &p, std::size_t k, double inside)
    {
      const ProfileLayer &l = p.layers.at(k);
      const std::string where = p.file + ": layer " + std::to_string(k + 1) + " (top at " +
                                format_number(100 * l.depth_top_m, 4) + " cm)";
      if (l.density_kg_m3)
        return {*l.density_kg_m3, true, "measured (the layer's density)"};
      double weight = 0, sum = 0;
      int count = 0, left_out = 0;
      for (const DensitySample &s : p.density_samples)
      {
        const double overlap =
          std::min(s.depth_top_m + s.thickness_m, l.depth_bottom_m()) - std::max(s.depth_top_m, l.depth_top_m);
        // (1 um: depths are given to the mm, and half a sample must not count by round-off.)
        if (overlap > inside * s.thickness_m + 1e-6)
          weight += overlap, sum += overlap * s.density_kg_m3, ++count;
        else if (overlap > 0)
          ++left_out;
      }
      if (count > 0)
        return {sum / weight, true,
                "measured (" + std::to_string(count) + " density sample(s) of the profile over the layer, "
                "weighted by their overlap)"};
      if (!l.hardness)
        throw ProfileError(where + ": no density (measured or from the density profile) and no hand hardness to "
                           "infer it from; give its density");
      std::string why;
      const auto top = geldsetzer_jamieson_density(l.grain_form, l.hardness->index, &why);
      if (!top)
        throw ProfileError(where + ": no density measured in it" +
                           (left_out > 0 ? " (its " + std::to_string(left_out) + " overlapping density sample(s) lie "
                                           "mostly outside it)" : std::string()) +
                           ", and it cannot be inferred: " + why + "; give its density (a layer table's density_kg_m3)");
      double rho = *top;
      std::string hardness = l.hardness->text;
      if (l.hardness_bottom)
      {
        rho = 0.5 * (rho + *geldsetzer_jamieson_density(l.grain_form, l.hardness_bottom->index));
        hardness += " (top) and " + l.hardness_bottom->text + " (bottom), mean of both";
      }
      return {rho, false,
              "Geldsetzer & Jamieson (2000), class " + geldsetzer_jamieson_class(l.grain_form) + " (" + l.grain_form +
                "), hand hardness " + hardness +
                (left_out > 0 ? " (its " + std::to_string(left_out) + " overlapping density sample(s) lie mostly "
                                "outside it: they measure its neighbours)" : std::string())};
    }
  } // namespace

  Sourced weak_layer_density(const SnowProfile &p, std::size_t k) { return layer_density(p, k, 0.5); }

  LayerProperties layer_properties(const SnowProfile &p, std::size_t k, const ModulusLaw &law, double poisson_ratio)
  {
    LayerProperties props;
    props.density = layer_density(p, k, 0);
    props.youngs_modulus = {law.modulus(props.density.value), false, law.citation};
    props.poisson_ratio = {poisson_ratio, false, "given (Slab Poisson's ratio)"};
    props.tensile_strength = {sigrist_tensile_strength(props.density.value), false,
                              "Sigrist (2006), sigma_t = 240 kPa (rho/917)^2.44"};
    return props;
  }
} // namespace anticrack::profile
