// A value of a selection whose values declare their own entries (DEM/Sample/Type: SampleType in
// dem/scene/sample_types.h; DEM/Loading/Test: LabTest in dem/scene/lab_tests.h): its name, its
// paragraph of the selection's documentation, its entries. The selection is the table of its
// variants, read with util/named_rows.h.
#pragma once

#include "util/named_rows.h"

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

  // The table of a selection's variants is read with util/named_rows.h (names_pattern, row_named,
  // name_paragraphs); what is the variants' own:

  /// "`a`, `b`": the variants that have `entry`, for messages.
  template <class V>
  std::string variants_with_entry(const std::vector<V> &variants, const std::string &entry)
  {
    return quoted_names(variants, [&](const Variant &v) { return v.has_entry(entry); });
  }
} // namespace anticrack::dem
