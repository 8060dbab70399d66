// A value of a selection whose values declare their own entries (DEM/Sample/Type: SampleType in
// dem/scene/sample_types.h; DEM/Loading/Test: LabTest in dem/scene/lab_tests.h): its name, its
// paragraph of the selection's documentation, its entries. The selection is the table of its
// variants; the functions below read such a table.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

namespace dealii
{
  class ParameterHandler;
}

namespace anticrack
{
  class Problems;
}

namespace anticrack::dem
{
  // What the variants' functions are given (dem/scene/parameters.h, dem/scene/model.h).
  class VariantEntries;
  struct SharedEntry;
  struct SceneParameters;
  struct DemModel;
  namespace parameters
  {
    struct Dem;
  }

  struct Variant
  {
    const char *name;          ///< the selection's value
    const char *documentation; ///< its paragraph of the selection's documentation (after "`name`: ")
    /// Names its entries of the subsection, in the order `anticrack params` lists them: its own and
    /// those it shares with other variants (dem/scene/scene_entries.h).
    void (*declare_parameters)(VariantEntries &entries);

    /// Whether `entry` of the subsection belongs to this variant.
    [[nodiscard]] bool has_entry(const std::string &entry) const;
  };

  /// "a|b|c", for Patterns::Selection.
  template <class V>
  std::string variant_pattern(const std::vector<V> &variants)
  {
    std::string pattern;
    for (const Variant &v : variants)
      pattern += (pattern.empty() ? "" : "|") + std::string(v.name);
    return pattern;
  }

  /// The variant called `name`; throws std::invalid_argument naming the allowed ones.
  template <class V>
  const V &variant_named(const std::vector<V> &variants, const std::string &name)
  {
    for (const V &v : variants)
      if (name == v.name)
        return v;
    throw std::invalid_argument("`" + name + "` is none of " + variant_pattern(variants));
  }

  /// Every variant's paragraph, "`a`: ... `b`: ...".
  template <class V>
  std::string variant_paragraphs(const std::vector<V> &variants)
  {
    std::string text;
    for (const Variant &v : variants)
      text += (text.empty() ? "`" : " `") + std::string(v.name) + "`: " + v.documentation;
    return text;
  }

  /// "`a`, `b`": the variants that have `entry`, for messages.
  template <class V>
  std::string variants_with_entry(const std::vector<V> &variants, const std::string &entry)
  {
    std::string list;
    for (const Variant &v : variants)
      if (v.has_entry(entry))
        list += (list.empty() ? "`" : ", `") + std::string(v.name) + "`";
    return list;
  }
} // namespace anticrack::dem
