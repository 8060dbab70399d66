// The continuum material as the FE solver reads it: `subsection Material` of a material file written
// by a calibration (coupling/material_handoff.h), or the same entries inline in a layer of a
// snowpack scene (fem/scene/snowpack_scene.h). One table of entries (material_entries(): name,
// unit, meaning, default, range) serves the declaration, the reader and the writer, so a layer can
// be given either way with the same names, units and ranges, and a calibration writes exactly what
// the solver reads. `anticrack calibrate` reads every material file back with read_material_text()
// before it keeps it (a file the solver could not read is never left behind).
#pragma once

#include <limits>
#include <string>
#include <vector>

namespace dealii
{
  class ParameterHandler;
}

namespace anticrack::fem
{
  /// A continuum material (SI units): elasticity, the cohesive Cam-Clay surface and its softening.
  struct ContinuumMaterial
  {
    std::string name;
    /// What p0, beta and M are: "invariants", the cohesive Cam-Clay surface in (p, q) of the stress
    /// tensor (the only surface the solver has). A file states it, so that parameters of another
    /// plane (the (σ, τ) base stresses of Ritter et al. 2020) are never read as these.
    std::string yield_surface_plane = "invariants";
    double density = 0;             ///< [kg/m³]
    double youngs_modulus = 0;      ///< E [Pa]
    double poisson_ratio = 0;       ///< ν
    double p0 = 0;                  ///< compressive tip of the cohesive Cam-Clay surface [Pa]
    double beta = 0;                ///< tensile tip at −β p0
    double M = 0;                   ///< critical-state slope
    std::string hardening_law;      ///< collapse | signed (docs/physics.md §2)
    double hardening_factor = 0;    ///< ξ of p0 = K sinh(ξ max(−α, 0))
    double residual_strength_ratio = 0; ///< floor of p0 over its initial value
    /// [m] thickness of the calibrated specimen: the length over which the measured softening
    /// strain acts (Bobillier et al.'s (2020) thickness scaling; the FE's crack band scales ξ with it).
    double reference_thickness = 0;
  };

  /// A confidence interval of a material entry (subsection Material/Uncertainty).
  struct MaterialInterval
  {
    double lower = std::numeric_limits<double>::quiet_NaN();
    double upper = std::numeric_limits<double>::quiet_NaN();
  };

  /// What a calibration knows of the uncertainty of its material (subsection Material/Uncertainty).
  struct MaterialUncertainty
  {
    double confidence = 0.95; ///< level of the intervals
    MaterialInterval youngs_modulus, poisson_ratio, p0, beta, M, hardening_factor;
  };

  /// Where a calibrated material comes from (subsection Material/Provenance).
  struct MaterialProvenance
  {
    std::string campaign_file, campaign_sha256, scene_file, scene_sha256;
    int microstructure = 0;     ///< index in the campaign
    /// How the surface was fitted: "p-q on the tests' paths, ..." (coupling/material_handoff.h). A
    /// file whose fit plane says otherwise (an older calibration's "p-q" of the Love–Weber stress
    /// or "sigma-tau") is refused by the readers.
    std::string fit_plane;
    double r_squared = 0;       ///< of the yield-surface fit
  };

  /// The collapse of a calibrated weak layer (subsection Material/Collapse), measured in the DEM's
  /// displacement-controlled compaction tests (dem/lab/compaction_curve.h). A strain, not a height:
  /// the collapse height of a layer that uses the file is lock_up_strain times its thickness
  /// (fem/scene/snowpack_scene.h). A file without it (lock_up_strain = 0) leaves the collapse height
  /// and densification modulus to the scene's layer.
  struct MaterialCollapse
  {
    double lock_up_strain = 0;          ///< ε_d: compaction at the onset of the lock-up, in [0, 1)
    MaterialInterval lock_up_strain_interval;
    double lock_up_modulus = 0;         ///< K_d [Pa]
    double fracture_energy_density = 0; ///< w_f [J/m³], dissipated by the strength drop beyond the residual
    MaterialInterval fracture_energy_density_interval;
    double collapse_energy_density = 0; ///< w_c [J/m³], dissipated up to the lock-up
    /// μ of the failed layer (fem/material/collapsed_layer_friction.h), the steady shear over normal
    /// stress of the collapsed layer's simple shear in the DEM; NaN: not measured (the scene's layer
    /// gives it).
    double friction_coefficient = std::numeric_limits<double>::quiet_NaN();
    MaterialInterval friction_coefficient_interval;

    [[nodiscard]] bool given() const { return lock_up_strain > 0; }
  };

  /// A whole material file: a comment block, the material, its uncertainty, its provenance and
  /// (optional) its collapse.
  struct MaterialFile
  {
    std::vector<std::string> comment; ///< lines of the header, written after "# "
    ContinuumMaterial material;
    MaterialUncertainty uncertainty;
    MaterialProvenance provenance;
    MaterialCollapse collapse;
  };

  /// One entry of `subsection Material`: its label and unit (the name in the file is
  /// "label [unit]", or the label alone for a ratio), what it means and the values it admits.
  struct MaterialEntry
  {
    const char *label;
    const char *unit;          ///< "" for dimensionless entries
    const char *meaning;       ///< the entry's documentation
    const char *default_value;
    /// Exactly one of the two members is set: a number of ContinuumMaterial, or a text.
    double ContinuumMaterial::*number = nullptr;
    std::string ContinuumMaterial::*text = nullptr;
    double lower = -std::numeric_limits<double>::max(); ///< range of a number
    double upper = std::numeric_limits<double>::max();
    const char *choices = nullptr;  ///< "a|b" of a text with a fixed set of values; nullptr: any text
    /// Its interval in subsection Uncertainty, if a calibration reports one.
    MaterialInterval MaterialUncertainty::*interval = nullptr;

    /// "label [unit]", the name in the file.
    [[nodiscard]] std::string name() const;
    /// "label interval [unit]", the name of its interval in subsection Uncertainty.
    [[nodiscard]] std::string interval_name() const;
  };

  /// Every entry of `subsection Material`, in the order of the files.
  const std::vector<MaterialEntry> &material_entries();

  /// The entries that have an interval in subsection Uncertainty, in the order of the files.
  const std::vector<const MaterialEntry *> &material_interval_entries();

  /// Declares the entries of a ContinuumMaterial in the current subsection of `prm`. With
  /// `required`, every entry but the name has to be set (a material file: no defaults for physics).
  void declare_material_entries(dealii::ParameterHandler &prm, bool required = false);

  /// The beginning of Provenance/Fit plane of a calibration whose surface the solver can use.
  inline constexpr const char *path_fit_plane = "p-q on the tests' paths";

  /// Reads what declare_material_entries() declared, from the current subsection.
  ContinuumMaterial parse_material_entries(dealii::ParameterHandler &prm);

  /// Parses `file` (a material file or a scene containing subsection Material); throws
  /// anticrack::InputError naming the file and the entry for unknown entries, bad values, values
  /// out of range, entries that are not set (every one but the name must be), and a surface fitted in
  /// another plane than the invariants on the tests' paths (Provenance/Fit plane).
  ContinuumMaterial read_material_file(const std::string &file);

  /// The same for the text of a material file; `name` is used in messages.
  ContinuumMaterial read_material_text(const std::string &text, const std::string &name);

  /// The whole file (material, uncertainty, provenance, collapse; not the comment) from its text;
  /// throws like read_material_text().
  MaterialFile read_material_file_text(const std::string &text, const std::string &name);

  /// The same from a file.
  MaterialFile read_whole_material_file(const std::string &file);

  /// The text of a material file: the comment, then subsection Material with every entry of
  /// material_entries(), Uncertainty and Provenance. Numbers are written with 6 significant digits.
  std::string material_file_text(const MaterialFile &file);

  /// A number as material files write it (6 significant digits), for comments that quote values.
  std::string material_file_number(double value);
} // namespace anticrack::fem
