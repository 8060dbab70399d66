// Tables of named rows: the values of a parameter-file selection that describe themselves (the DEM's
// sample types and lab tests, dem/scene/variant.h; the FE's analyses, fem/scene/analysis_type.h).
// A row is any struct with `const char *name` (and, for the paragraphs, `documentation`); these
// functions read a table of them, so that each selection gets its pattern, its lookup, its
// documentation and its lists for messages the same way.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

namespace anticrack
{
  /// "a|b|c", for Patterns::Selection and messages.
  template <class Row>
  std::string names_pattern(const std::vector<Row> &rows)
  {
    std::string pattern;
    for (const Row &row : rows)
      pattern += (pattern.empty() ? "" : "|") + std::string(row.name);
    return pattern;
  }

  /// The row called `name`; throws std::invalid_argument naming the allowed ones.
  template <class Row>
  const Row &row_named(const std::vector<Row> &rows, const std::string &name)
  {
    for (const Row &row : rows)
      if (name == row.name)
        return row;
    throw std::invalid_argument("`" + name + "` is none of " + names_pattern(rows));
  }

  /// Every row's paragraph, "`a`: ... `b`: ...", for the selection's documentation.
  template <class Row>
  std::string name_paragraphs(const std::vector<Row> &rows)
  {
    std::string text;
    for (const Row &row : rows)
      text += (text.empty() ? "`" : " `") + std::string(row.name) + "`: " + row.documentation;
    return text;
  }

  /// "`a`, `b`": the names of the rows for which `selected(row)` holds, for messages.
  template <class Row, class Predicate>
  std::string quoted_names(const std::vector<Row> &rows, const Predicate &selected)
  {
    std::string list;
    for (const Row &row : rows)
      if (selected(row))
        list += (list.empty() ? "`" : ", `") + std::string(row.name) + "`";
    return list;
  }
} // namespace anticrack
