#include "fem/material/material_file.h"

#include "fem/material/collapsed_layer_friction.h"

#include "util/atomic_file.h"
#include "util/format.h"
#include "util/input_error.h"
#include "util/parameter_files.h"
#include "util/parameter_input.h"

#include <deal.II/base/parameter_handler.h>

#include <cmath>
#include <limits>
#include <optional>

#include <cstdio>
#include <fstream>
#include <set>
#include <sstream>

namespace anticrack::fem
{
  using dealii::ParameterHandler;
  using dealii::Patterns::Anything;
  using dealii::Patterns::Double;
  using dealii::Patterns::Integer;
  using dealii::Patterns::Selection;

  namespace
  {
    using C = ContinuumMaterial;
    using U = MaterialUncertainty;

    MaterialEntry number_entry(const char *label, const char *unit, const char *meaning, const char *default_value,
                               double C::*member, double lower, double upper = std::numeric_limits<double>::max(),
                               MaterialInterval U::*interval = nullptr)
    {
      MaterialEntry e{label, unit, meaning, default_value};
      e.number = member, e.lower = lower, e.upper = upper, e.interval = interval;
      return e;
    }

    MaterialEntry text_entry(const char *label, const char *meaning, const char *default_value,
                             std::string C::*member, const char *choices)
    {
      MaterialEntry e{label, "", meaning, default_value};
      e.text = member, e.choices = choices;
      return e;
    }

    constexpr double unbounded = std::numeric_limits<double>::max();

    /// One entry of subsection Provenance; exactly one member is set.
    struct ProvenanceEntry
    {
      const char *name;
      const char *meaning;
      std::string MaterialProvenance::*text = nullptr;
      int MaterialProvenance::*integer = nullptr;
      double MaterialProvenance::*number = nullptr;
    };

    const std::vector<ProvenanceEntry> &provenance_entries()
    {
      using P = MaterialProvenance;
      constexpr const char *origin = "where the material comes from";
      static const std::vector<ProvenanceEntry> entries = {
        {"Campaign file", origin, &P::campaign_file},
        {"Campaign sha256", origin, &P::campaign_sha256},
        {"Scene file", origin, &P::scene_file},
        {"Scene sha256", origin, &P::scene_sha256},
        {"Microstructure", "index in the campaign", nullptr, &P::microstructure},
        {"Fit plane", origin, &P::fit_plane},
        {"R squared", "of the yield-surface fit", nullptr, nullptr, &P::r_squared}};
      return entries;
    }

    constexpr const char *confidence_entry = "Confidence";

    /// subsection Material/Collapse: one entry per member of MaterialCollapse (its interval apart).
    struct CollapseEntry
    {
      const char *name, *meaning;
      double MaterialCollapse::*number;
      double upper;
    };
    const std::vector<CollapseEntry> &collapse_entries()
    {
      using C = MaterialCollapse;
      static const std::vector<CollapseEntry> entries = {
        {"Lock-up strain", "eps_d: compaction of the layer at the onset of its lock-up (the collapse height over the "
                           "thickness); 0 = not given (the scene's layer gives the collapse height). Dimensionless.",
         &C::lock_up_strain, 0.999},
        {"Lock-up modulus [Pa]", "K_d: modulus of the lock-up (the layer's densification modulus). Units: Pa.",
         &C::lock_up_modulus, std::numeric_limits<double>::max()},
        {"Fracture energy density [J/m^3]", "w_f: energy dissipated by the strength drop beyond the residual, per "
                                             "unit volume; times a thickness, per unit layer area. Units: J/m^3.",
         &C::fracture_energy_density, std::numeric_limits<double>::max()},
        {"Collapse energy density [J/m^3]", "w_c: energy dissipated up to the lock-up, per unit volume. Units: J/m^3.",
         &C::collapse_energy_density, std::numeric_limits<double>::max()}};
      return entries;
    }
    /// The intervals of Material/Collapse (over the realizations, at Uncertainty/Confidence); a file
    /// may lack them (NaN).
    struct CollapseIntervalEntry
    {
      const char *name;
      MaterialInterval MaterialCollapse::*interval;
    };
    const std::vector<CollapseIntervalEntry> &collapse_interval_entries()
    {
      static const std::vector<CollapseIntervalEntry> entries = {
        {"Lock-up strain interval", &MaterialCollapse::lock_up_strain_interval},
        {"Fracture energy density interval [J/m^3]", &MaterialCollapse::fracture_energy_density_interval},
        {"Friction coefficient interval", &MaterialCollapse::friction_coefficient_interval}};
      return entries;
    }
    /// Material/Collapse/Friction coefficient: empty when the campaign had no friction tests (0 is a
    /// frictionless layer, a value).
    constexpr const char *friction_entry = "Friction coefficient";

    void declare_material_file(ParameterHandler &prm)
    {
      prm.enter_subsection("Material");
      declare_material_entries(prm, /*required=*/true);
      prm.enter_subsection("Uncertainty");
      prm.declare_entry(confidence_entry, "0.95", Double(0, 1), "level of the intervals");
      for (const MaterialEntry *e : material_interval_entries())
        prm.declare_entry(e->interval_name(), "", Anything(), "lower, upper");
      prm.leave_subsection();
      prm.enter_subsection("Collapse");
      for (const CollapseEntry &e : collapse_entries())
        prm.declare_entry(e.name, "0", Double(0, e.upper), e.meaning);
      prm.declare_entry(friction_entry, "", Anything(),
                        "mu: the failed layer's friction coefficient, steady shear over normal stress of the "
                        "collapsed layer's simple shear in the DEM (its campaign's friction tests); in [0, 2]; empty: "
                        "not measured. Dimensionless.");
      for (const CollapseIntervalEntry &e : collapse_interval_entries())
        prm.declare_entry(e.name, "", Anything(), "lower, upper");
      prm.leave_subsection();
      prm.enter_subsection("Provenance");
      for (const ProvenanceEntry &e : provenance_entries())
      {
        if (e.integer)
          prm.declare_entry(e.name, "0", Integer(0), e.meaning);
        else if (e.number)
          prm.declare_entry(e.name, "0", Double(), e.meaning);
        else
          prm.declare_entry(e.name, "", Anything(), e.meaning);
      }
      prm.leave_subsection();
      prm.leave_subsection();
    }

    /// The file parsed and checked by deal.II, positioned at the root.
    void parse_material_file(ParameterHandler &prm, const std::string &text, const std::string &name)
    {
      declare_material_file(prm);
      try
      {
        parse_parameter_text(prm, text, name, "material file");
      }
      catch (const InputError &)
      {
        throw;
      }
      catch (const std::exception &e)
      {
        throw InputError("material file " + name + ": " + e.what());
      }
      prm.enter_subsection("Material");
      prm.enter_subsection("Provenance");
      const std::string fit_plane = prm.get("Fit plane");
      prm.leave_subsection();
      prm.leave_subsection();
      if (!fit_plane.empty() && fit_plane.rfind(path_fit_plane, 0) != 0)
        throw InputError("material file " + name + ": Material/Provenance/Fit plane = " + fit_plane +
                         ": its surface was fitted in another plane than the one the FE point fails in (allowed: \"" +
                         path_fit_plane + ", ...\"); recalibrate the campaign with `anticrack calibrate`, which "
                         "fits the invariants of the FE point on every test's path (docs/calibration.md)");
      const std::set<std::string> missing = prm.get_entries_wrongly_not_set();
      if (!missing.empty())
      {
        std::string list;
        for (const std::string &entry : missing)
          list += "\n  " + demangled_parameter_path(entry);
        throw InputError("material file " + name + ": entries not set (a material file gives every entry of "
                         "subsection Material but its name; there are no defaults):" + list);
      }
    }

    /// "lower, upper" of an interval entry; an empty entry (no interval given) is (NaN, NaN).
    MaterialInterval parse_interval(const std::string &text, const std::string &entry, const std::string &name)
    {
      if (text.empty())
        return {};
      const auto comma = text.find(',');
      try
      {
        if (comma == std::string::npos)
          throw std::invalid_argument("no comma");
        return {std::stod(text.substr(0, comma)), std::stod(text.substr(comma + 1))};
      }
      catch (const std::exception &)
      {
        throw InputError("material file " + name + ": Material/" + entry + " = \"" + text +
                         "\" is not \"lower, upper\"");
      }
    }

    /// An entry that may be empty (NaN) or a number in [lower, upper].
    double parse_optional_number_in(const std::string &text, const std::string &entry, const std::string &name,
                                    double lower, double upper)
    {
      std::optional<double> value;
      try
      {
        value = parse_optional_number(text);
      }
      catch (const std::invalid_argument &)
      {
        value = std::numeric_limits<double>::quiet_NaN();
      }
      if (value && !(*value >= lower && *value <= upper))
        throw InputError("material file " + name + ": Material/" + entry + " = \"" + text + "\" must be empty or a "
                         "number in [" + material_file_number(lower) + ", " + material_file_number(upper) + "]");
      return value.value_or(std::numeric_limits<double>::quiet_NaN());
    }

    /// "lower, upper", or empty for an interval that is not known (one realization): a material
    /// file holds finite numbers only (util/parameter_input.h).
    std::string interval_text(const MaterialInterval &interval)
    {
      if (!std::isfinite(interval.lower) || !std::isfinite(interval.upper))
        return "";
      return material_file_number(interval.lower) + ", " + material_file_number(interval.upper);
    }
  } // namespace

  std::string MaterialEntry::name() const
  {
    return *unit ? std::string(label) + " [" + unit + "]" : std::string(label);
  }

  std::string MaterialEntry::interval_name() const
  {
    return std::string(label) + " interval" + (*unit ? std::string(" [") + unit + "]" : std::string());
  }

  const std::vector<MaterialEntry> &material_entries()
  {
    static const std::vector<MaterialEntry> entries = {
      text_entry("Name", "Label of the material (in messages and outputs).", "", &C::name, nullptr),
      text_entry("Yield surface plane",
                 "What p0, beta and M describe: invariants, the cohesive Cam-Clay surface in the (p, q) plane of "
                 "the stress tensor (docs/physics.md §2). Parameters of the (sigma, tau) plane of base stresses "
                 "are not accepted.",
                 "invariants", &C::yield_surface_plane, "invariants"),
      number_entry("Density", "kg/m^3", "rho: bulk density, phi rho_particle (phi the solid volume fraction). Units: kg/m^3.", "200", &C::density, 1e-3),
      number_entry("Young's modulus", "Pa", "E: Young's modulus. Units: Pa.", "1e6", &C::youngs_modulus, 0, unbounded, &U::youngs_modulus),
      number_entry("Poisson's ratio", "", "nu: Poisson's ratio. Dimensionless.", "0.2", &C::poisson_ratio, -0.999, 0.4999, &U::poisson_ratio),
      number_entry("Compressive strength p0", "Pa", "p0: compressive tip of the yield surface. Units: Pa.", "1e3", &C::p0, 0,
                   unbounded, &U::p0),
      number_entry("Tensile strength ratio beta", "", "beta: the tensile tip of the yield surface lies at -beta p0. Dimensionless.", "0.5", &C::beta, 0, unbounded,
                   &U::beta),
      number_entry("Critical state slope M", "", "M: slope of the critical state line q = M p. Dimensionless.", "1", &C::M, 0, unbounded,
                   &U::M),
      text_entry("Hardening law",
                 "collapse: every plastic volume change softens (weak layers); signed: compaction "
                 "hardens, dilation softens (docs/physics.md §2).",
                 "collapse", &C::hardening_law, "collapse|signed"),
      number_entry("Hardening factor xi", "", "xi: hardening factor of p0 = K sinh(xi max(-alpha, 0)). Dimensionless.", "10", &C::hardening_factor, 0,
                   unbounded, &U::hardening_factor),
      number_entry("Residual strength ratio", "", "Residual strength over peak strength p0. Dimensionless.", "0.2", &C::residual_strength_ratio, 0,
                   1),
      number_entry("Reference thickness", "m", "h_ref: thickness of the calibrated specimen, over which the softening strain was measured (crack band, docs/physics.md §2). Units: m.", "0.03",
                   &C::reference_thickness, 0)};
    return entries;
  }

  const std::vector<const MaterialEntry *> &material_interval_entries()
  {
    // The order of the files: the surface first, then elasticity and softening.
    static const std::vector<const MaterialEntry *> entries = [] {
      std::vector<const MaterialEntry *> with_interval;
      for (MaterialInterval U::*interval :
           {&U::p0, &U::beta, &U::M, &U::youngs_modulus, &U::poisson_ratio, &U::hardening_factor})
        for (const MaterialEntry &e : material_entries())
          if (e.interval == interval)
            with_interval.push_back(&e);
      return with_interval;
    }();
    return entries;
  }

  void declare_material_entries(ParameterHandler &prm, bool required)
  {
    for (const MaterialEntry &e : material_entries())
    {
      const bool has_to_be_set = required && e.text != &C::name;
      if (e.number)
        prm.declare_entry(e.name(), e.default_value, Double(e.lower, e.upper), e.meaning, has_to_be_set);
      else if (e.choices)
        prm.declare_entry(e.name(), e.default_value, Selection(e.choices), e.meaning, has_to_be_set);
      else
        prm.declare_entry(e.name(), e.default_value, Anything(), e.meaning, has_to_be_set);
    }
  }

  ContinuumMaterial parse_material_entries(ParameterHandler &prm)
  {
    ContinuumMaterial m;
    for (const MaterialEntry &e : material_entries())
    {
      if (e.number)
        m.*e.number = prm.get_double(e.name());
      else
        m.*e.text = prm.get(e.name());
    }
    return m;
  }

  ContinuumMaterial read_material_file(const std::string &file) { return read_whole_material_file(file).material; }

  ContinuumMaterial read_material_text(const std::string &text, const std::string &name)
  {
    ParameterHandler prm;
    parse_material_file(prm, text, name);
    prm.enter_subsection("Material");
    ContinuumMaterial m = parse_material_entries(prm);
    prm.leave_subsection();
    return m;
  }

  MaterialFile read_material_file_text(const std::string &text, const std::string &name)
  {
    ParameterHandler prm;
    parse_material_file(prm, text, name);
    MaterialFile file;
    prm.enter_subsection("Material");
    file.material = parse_material_entries(prm);
    prm.enter_subsection("Uncertainty");
    file.uncertainty.confidence = prm.get_double(confidence_entry);
    for (const MaterialEntry *e : material_interval_entries())
      file.uncertainty.*e->interval = parse_interval(prm.get(e->interval_name()), "Uncertainty/" + e->interval_name(), name);
    prm.leave_subsection();
    prm.enter_subsection("Collapse");
    for (const CollapseEntry &e : collapse_entries())
      file.collapse.*e.number = prm.get_double(e.name);
    file.collapse.friction_coefficient = parse_optional_number_in(prm.get(friction_entry), std::string("Collapse/") +
                                                                  friction_entry, name, 0, max_friction_coefficient);
    for (const CollapseIntervalEntry &e : collapse_interval_entries())
      file.collapse.*e.interval = parse_interval(prm.get(e.name), std::string("Collapse/") + e.name, name);
    prm.leave_subsection();
    prm.enter_subsection("Provenance");
    for (const ProvenanceEntry &e : provenance_entries())
    {
      if (e.integer)
        file.provenance.*e.integer = prm.get_integer(e.name);
      else if (e.number)
        file.provenance.*e.number = prm.get_double(e.name);
      else
        file.provenance.*e.text = prm.get(e.name);
    }
    prm.leave_subsection();
    prm.leave_subsection();
    return file;
  }

  MaterialFile read_whole_material_file(const std::string &file)
  {
    std::string text;
    try
    {
      text = read_text_file(file);
    }
    catch (const std::runtime_error &)
    {
      throw InputError("material file " + file + " cannot be read");
    }
    return read_material_file_text(text, file);
  }

  std::string material_file_number(double value) { return format_number(value, 6); }

  std::string material_file_text(const MaterialFile &file)
  {
    std::ostringstream out;
    for (const std::string &line : file.comment)
      out << "# " << line << "\n";
    out << "subsection Material\n";
    for (const MaterialEntry &e : material_entries())
      out << "  set " << e.name() << " = "
          << (e.number ? material_file_number(file.material.*e.number) : file.material.*e.text) << "\n";
    out << "  subsection Uncertainty\n"
        << "    set " << confidence_entry << " = " << material_file_number(file.uncertainty.confidence) << "\n";
    for (const MaterialEntry *e : material_interval_entries())
    {
      const MaterialInterval &interval = file.uncertainty.*e->interval;
      out << "    set " << e->interval_name() << " = " << interval_text(interval) << "\n";
    }
    out << "  end\n";
    if (file.collapse.given())
    {
      out << "  subsection Collapse\n";
      for (const CollapseEntry &e : collapse_entries())
        out << "    set " << e.name << " = " << material_file_number(file.collapse.*e.number) << "\n";
      if (!std::isnan(file.collapse.friction_coefficient))
        out << "    set " << friction_entry << " = " << material_file_number(file.collapse.friction_coefficient) << "\n";
      for (const CollapseIntervalEntry &e : collapse_interval_entries())
        out << "    set " << e.name << " = " << interval_text(file.collapse.*e.interval) << "\n";
      out << "  end\n";
    }
    out << "  subsection Provenance\n";
    for (const ProvenanceEntry &e : provenance_entries())
    {
      out << "    set " << e.name << " = ";
      if (e.integer)
        out << file.provenance.*e.integer;
      else if (e.number)
        out << material_file_number(file.provenance.*e.number);
      else
        out << file.provenance.*e.text;
      out << "\n";
    }
    out << "  end\n"
        << "end\n";
    return out.str();
  }
} // namespace anticrack::fem
