#include "fem/material/material_file.h"

#include "util/input_error.h"

#include <deal.II/base/parameter_handler.h>

#include <fstream>
#include <limits>
#include <sstream>

namespace anticrack::fem
{
  using dealii::ParameterHandler;
  using dealii::Patterns::Anything;
  using dealii::Patterns::Double;
  using dealii::Patterns::Integer;
  using dealii::Patterns::Selection;

  void declare_material_entries(ParameterHandler &prm)
  {
    prm.declare_entry("Name", "", Anything(), "Label of the material (in messages and outputs).");
    prm.declare_entry("Density [kg/m^3]", "200", Double(1e-3),
                      "rho: bulk density, phi rho_particle (phi the solid volume fraction). Units: kg/m^3.");
    prm.declare_entry("Young's modulus [Pa]", "1e6", Double(0, std::numeric_limits<double>::max()),
                      "E: Young's modulus. Units: Pa.");
    prm.declare_entry("Poisson's ratio", "0.2", Double(-0.999, 0.4999), "nu: Poisson's ratio. Dimensionless.");
    prm.declare_entry("Compressive strength p0 [Pa]", "1e3", Double(0),
                      "p0: compressive tip of the yield surface. Units: Pa.");
    prm.declare_entry("Tensile strength ratio beta", "0.5", Double(0),
                      "beta: the tensile tip of the yield surface lies at -beta p0. Dimensionless.");
    prm.declare_entry("Critical state slope M", "1", Double(0),
                      "M: slope of the critical state line q = M p. Dimensionless.");
    prm.declare_entry("Hardening law", "collapse", Selection("collapse|signed"),
                      "collapse: every plastic volume change softens (weak layers); signed: compaction hardens, "
                      "dilation softens (docs/physics.md §2).");
    prm.declare_entry("Hardening factor xi", "10", Double(0),
                      "xi: hardening factor of p0 = K sinh(xi max(-alpha, 0)). Dimensionless.");
    prm.declare_entry("Residual strength ratio", "0.2", Double(0, 1),
                      "Residual strength over peak strength p0. Dimensionless.");
    prm.declare_entry("Reference thickness [m]", "0.03", Double(0),
                      "h_ref: thickness of the calibrated specimen, over which the softening strain was measured "
                      "(crack band, docs/physics.md §2). Units: m.");
  }

  ContinuumMaterial parse_material_entries(ParameterHandler &prm)
  {
    ContinuumMaterial m;
    m.name = prm.get("Name");
    m.density = prm.get_double("Density [kg/m^3]");
    m.youngs_modulus = prm.get_double("Young's modulus [Pa]");
    m.poisson_ratio = prm.get_double("Poisson's ratio");
    m.p0 = prm.get_double("Compressive strength p0 [Pa]");
    m.beta = prm.get_double("Tensile strength ratio beta");
    m.M = prm.get_double("Critical state slope M");
    m.hardening_law = prm.get("Hardening law");
    m.hardening_factor = prm.get_double("Hardening factor xi");
    m.residual_strength_ratio = prm.get_double("Residual strength ratio");
    m.reference_thickness = prm.get_double("Reference thickness [m]");
    return m;
  }

  namespace
  {
    void declare_material_file(ParameterHandler &prm)
    {
      prm.enter_subsection("Material");
      declare_material_entries(prm);
      prm.enter_subsection("Uncertainty");
      prm.declare_entry("Confidence", "0.95", Double(0, 1), "level of the intervals");
      for (const char *name : {"Compressive strength p0 interval [Pa]", "Tensile strength ratio beta interval",
                               "Critical state slope M interval", "Young's modulus interval [Pa]",
                               "Poisson's ratio interval", "Hardening factor xi interval"})
        prm.declare_entry(name, "", Anything(), "lower, upper");
      prm.leave_subsection();
      prm.enter_subsection("Provenance");
      for (const char *name : {"Campaign file", "Campaign sha256", "Scene file", "Scene sha256", "Fit plane"})
        prm.declare_entry(name, "", Anything(), "where the material comes from");
      prm.declare_entry("Microstructure", "0", Integer(0), "index in the campaign");
      prm.declare_entry("R squared", "0", Double(), "of the yield-surface fit");
      prm.leave_subsection();
      prm.leave_subsection();
    }
  } // namespace

  ContinuumMaterial read_material_file(const std::string &file)
  {
    std::ifstream in(file);
    if (!in)
      throw InputError("material file " + file + " cannot be read");
    std::ostringstream text;
    text << in.rdbuf();
    return read_material_text(text.str(), file);
  }

  ContinuumMaterial read_material_text(const std::string &text, const std::string &name)
  {
    ParameterHandler prm;
    declare_material_file(prm);
    try
    {
      std::istringstream input(text);
      prm.parse_input(input, name);
    }
    catch (const dealii::ExceptionBase &e)
    {
      std::ostringstream info; // deal.II's text names the line and the entry; no stack trace
      e.print_info(info);
      throw InputError("material file " + name + ":\n" + info.str());
    }
    catch (const std::exception &e)
    {
      throw InputError("material file " + name + ": " + e.what());
    }
    prm.enter_subsection("Material");
    ContinuumMaterial m = parse_material_entries(prm);
    prm.leave_subsection();
    return m;
  }
} // namespace anticrack::fem
