// Printing what a scene kind declares: every entry of a deal.II ParameterHandler with its
// documentation, allowed values and default, as a complete scene (`prm`, itself a valid scene),
// in deal.II's Description style or as JSON. Part of the anticrack_parameter_files library, the
// only piece of util/ that links deal.II.
#pragma once

#include <iosfwd>
#include <set>
#include <string>
#include <vector>

namespace dealii
{
  class ParameterHandler;
}

namespace anticrack
{
  enum class ParameterFormat
  {
    prm,
    description,
    json
  };

  /// One `set` statement of a parameter file: the subsection path and the entry name, the value as
  /// written, and the line it starts on.
  struct ParameterSetting
  {
    std::vector<std::string> path; ///< subsections, then the entry name
    std::string value;
    unsigned int line = 0;

    /// "DEM/Sample/Radius [m]", for messages.
    [[nodiscard]] std::string path_text() const;
  };

  /// Every `set` statement of a parameter-file text in the order written, following deal.II's
  /// syntax (`subsection NAME` ... `end`, `set NAME = VALUE`, `#` comments, a trailing `\`
  /// continues a line). Neither checks names nor patterns: that is the ParameterHandler's job;
  /// this tells what a file sets, so that a reader can say which kind or variant an entry belongs
  /// to, and refuse a file that sets nothing.
  std::vector<ParameterSetting> scan_parameter_settings(const std::string &text);

  /// The bytes of a scene file; throws InputError naming the file if it cannot be read.
  std::string read_scene_file(const std::string &file);

  /// The value of a top-level `set Scene = KIND` of a parameter file, or "" if it has none;
  /// throws InputError if the file cannot be read.
  std::string scene_kind_in_file(const std::string &file);

  /// "Material/Density [kg/m^3]" of deal.II's "Material.Density_20_5bkg_2fm_5e3_5d": the paths
  /// ParameterHandler::get_entries_wrongly_not_set() returns are of mangled names (every character
  /// but letters and digits as "_" and two hex digits), their subsections joined by ".".
  std::string demangled_parameter_path(const std::string &mangled);

  /// The paths (subsections, then the entry name) of every entry declared in `prm`.
  std::set<std::vector<std::string>> declared_entries(const dealii::ParameterHandler &prm);

  /// Prints every entry declared in `prm`; `kind` names the scene kind in the header line, which
  /// says whether the listing is itself a valid scene (`valid_scene`: one variant of each selection).
  void print_parameter_documentation(std::ostream &out, ParameterFormat format, const dealii::ParameterHandler &prm,
                                     const std::string &kind, bool valid_scene = true);
} // namespace anticrack
