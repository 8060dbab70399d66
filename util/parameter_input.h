// Parsing a parameter file (a scene, a material file) into a deal.II ParameterHandler, with every
// refusal naming the file, the line and the entry's full path, and the input checks that deal.II's
// patterns cannot make. Part of the anticrack_parameter_files library.
//
// What is refused, before deal.II reads a value:
//  - a file that is not text: a NUL byte (binary data), bytes that are not UTF-8 (summaries and
//    provenance records are JSON, which is UTF-8);
//  - `include` lines: a scene is read as its own text (its kind, variants and the files it names
//    come from it; scan_parameter_settings), so an included file would be half-read; deal.II's own
//    include also recurses without end on a file that includes itself. Scenes are composed by a
//    pipeline's or a study's scene changes instead;
//  - a number that is not finite, or whose magnitude lies beyond every value of its unit that
//    anticrack models (physical_magnitude_limit): 1e308 Pa is not a snow, a rock or a grain;
// and by deal.II: an undeclared entry, a value that does not match its pattern, an unbalanced
// subsection, with the entry's full path added to deal.II's message.
#pragma once

#include <optional>
#include <string>

namespace dealii
{
  class ParameterHandler;
}

namespace anticrack
{
  /// Parses `text`, the contents of `file` (`what`: "scene file", "material file"), into `prm`;
  /// throws InputError. `skip_undefined`: entries `prm` does not declare are skipped (a first pass
  /// that reads only the entries that select the rest).
  void parse_parameter_text(dealii::ParameterHandler &prm, const std::string &text, const std::string &file,
                            const std::string &what = "scene file", bool skip_undefined = false);

  /// Throws InputError if `text` is not a parameter file anticrack reads: binary, not UTF-8,
  /// `include` lines, non-finite or unphysically large numbers (see the file's comment).
  void check_parameter_text(const std::string &text, const std::string &file, const std::string &what = "scene file");

  /// The largest magnitude a value given in `unit` (the bracketed unit of an entry's name, e.g. "Pa")
  /// may have, with the reason; none for units without a limit. Unitless numbers: 1e15.
  struct MagnitudeLimit
  {
    double largest;
    const char *why;
  };
  std::optional<MagnitudeLimit> physical_magnitude_limit(const std::string &unit);

  /// The value of an entry that may be left empty (an optional number, declared as text): nullopt for
  /// empty text; the number when the whole text is one finite number; throws std::invalid_argument
  /// otherwise (the caller names the file and the entry).
  std::optional<double> parse_optional_number(const std::string &text);
} // namespace anticrack
