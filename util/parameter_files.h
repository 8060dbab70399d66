// Printing what a scene kind declares: every entry of a deal.II ParameterHandler with its
// documentation, allowed values and default, as a complete scene (`prm`, itself a valid scene),
// in deal.II's Description style or as JSON. Part of the anticrack_parameter_files library, the
// only piece of util/ that links deal.II.
#pragma once

#include <iosfwd>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace dealii
{
  class ParameterHandler;
}

namespace anticrack
{
  class Problems;

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

  /// "DEM/Boundary particles/Clump force rate [N/s]" -> {"DEM", "Boundary particles", "Clump force
  /// rate [N/s]"}: subsections are separated by '/', except inside a unit's brackets.
  std::vector<std::string> split_parameter_path(const std::string &path);

  /// A change of one entry of a scene: its path ("Mesh/Element length [m]") and the value to set.
  using EntryChange = std::pair<std::string, std::string>;

  /// `text` with a block at its end that sets each of `changes` (in deal.II's syntax the last
  /// setting of an entry wins), under a comment saying where they come from (`origin`).
  std::string scene_text_with_changes(std::string text, const std::vector<EntryChange> &changes,
                                      const std::string &origin);

  /// The `path = value` items of a comma-separated list entry (e.g. Pipeline/Snowpack scene
  /// changes). An item without `=` continues the value of the change before it (a list value:
  /// `A/List = 0, 45, B/Count = 1` sets A/List to "0, 45"); without a change before it, it is a
  /// problem of `entry`.
  std::vector<EntryChange> entry_changes_in_list(const std::string &list, const std::string &entry,
                                                 Problems &problems);

  /// The list entry_changes_in_list reads back: `path = value, path = value` (a list value keeps its
  /// commas, which the reader joins back to the change before them).
  std::string entry_changes_text(const std::vector<EntryChange> &changes);

  /// The text of scene `file` as it must read when run from another folder: the entries that name
  /// files relative to the scene's own folder (scene_relative_file_entries) set again at its end
  /// with absolute paths. A study's variants and a pipeline's stages run such copies.
  std::string relocatable_scene_text(const std::string &file);

  /// `path` as the reader of scene `scene_file` resolves a file it names: as it is if absolute, else
  /// relative to the scene's folder; absolute and normalised.
  std::string path_relative_to_scene(const std::string &path, const std::string &scene_file);

  /// The entry names (last path component) whose values name files relative to the folder of the
  /// scene that sets them, as their readers resolve them: a layer's `Material file`, a pipeline's
  /// `Weak layer scene` and `Snowpack scenes` (a comma-separated list), a study's `Base scene`, a
  /// snowpack's `Profile file`.
  const std::vector<std::string> &scene_relative_file_entries();

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
