// Scenes of kind `study` (`set Scene = study`): a base scene of any other kind run again with some
// of its entries set to other values, to see what a setting buys for how much run time, or how
// an answer moves with an input (a sensitivity study):
//
//   set Scene = study
//   subsection Study
//     set Base scene  = ../pst_flat.prm            # relative to this file
//     set Base scene changes = Output/Field interval [s] = 1   # optional, set in every variant
//     set Combination = one at a time              # or: product (every combination)
//     set Results     = /results/critical_cut_length_m, /results/propagation_speed_m_per_s
//     set Reference values = /results/propagation_speed_m_per_s = 28.7   # optional
//     subsection Entry 1
//       set Path   = Mesh/Element length [m]
//       set Values = 0.04; 0.02; 0.01
//       set Refinement = size                      # size | count | ordinal | none
//     end
//   end
//
// Results are JSON pointers into each variant's summary.json. What a run does and writes:
// coupling/study.h; the error and order measures: coupling/study_analysis.h.
#pragma once

#include "util/parameter_files.h"

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace dealii
{
  class ParameterHandler;
}

namespace anticrack::coupling
{
  /// How an entry's values refine the answer.
  enum class Refinement
  {
    size,    ///< a discretisation length, step or rate: smaller is finer, order in h = value
    count,   ///< elements or particles through a length: larger is finer, order in h = 1/value
    ordinal, ///< larger is finer without a length scale (polynomial degree): no order
    none     ///< not a discretisation (a sensitivity study): no finest value
  };

  struct StudyEntry
  {
    std::string path;                ///< "Mesh/Element length [m]"
    std::vector<std::string> values; ///< as written
    Refinement refinement = Refinement::none;
    std::vector<double> measures;    ///< Measures: the number each value stands for (empty: the values)
    std::optional<std::string> base_value; ///< the base scene's setting (with Base scene changes), if any

    /// Index of the finest value (none for Refinement::none).
    [[nodiscard]] std::optional<std::size_t> finest() const;
    /// The values as numbers, or their Measures (only for refinements other than none, checked on
    /// reading).
    [[nodiscard]] std::vector<double> numbers() const;
  };

  struct StudyResult
  {
    std::string pointer;              ///< JSON pointer into a variant's summary.json
    std::string label;                ///< its last component(s), as many as make it unique among the results
    std::optional<double> reference;  ///< given in Study/Reference values; else the finest variant's
  };

  struct StudyScene
  {
    std::string file;       ///< the study scene itself
    std::string base_scene; ///< absolute, normalised
    std::string base_kind;  ///< the base scene's `Scene`
    std::vector<EntryChange> base_changes; ///< Study/Base scene changes: set in every variant
    bool product = false;   ///< every combination; else one entry at a time
    std::vector<StudyEntry> entries;
    std::vector<StudyResult> results;
    int side_by_side = 1;   ///< variants run at the same time without mpirun
  };

  /// One run of a study: the base scene with `changes`.
  struct StudyVariant
  {
    std::string id;                      ///< "v000", ...
    std::vector<std::optional<std::size_t>> level; ///< per entry: index of its value, or none (base scene's)
    std::vector<EntryChange> changes;
  };

  /// The variants: one entry at a time (each entry's values, the others as the base scene sets
  /// them) or every combination of the entries' values.
  std::vector<StudyVariant> study_variants(const StudyScene &study);

  /// The variants of entry `e`'s line, coarsest first: one at a time, those of `e`; for a
  /// product, those whose other entries are at their finest value (their first for entries
  /// without refinement).
  std::vector<std::size_t> line_of_entry(const StudyScene &study, const std::vector<StudyVariant> &variants,
                                         std::size_t e);

  /// Declares the entries of a study scene (for `anticrack params`).
  void declare_study_scene(dealii::ParameterHandler &prm);

  /// The label of a result (a column of study.csv, a plot's title): the pointer's last component,
  /// with as many components before it as make it differ from every other pointer's and not a
  /// bare array index (/a/p0/value and /a/M/value: p0_value and M_value; /a/interval/0:
  /// interval_0).
  std::string result_label(const std::string &pointer, const std::vector<std::string> &all_pointers);

  /// Reads and checks a study scene (not yet its variants: coupling/study.h); throws InputError
  /// naming the file, the entry and the allowed values.
  StudyScene read_study_scene(const std::string &file);

  /// "size", "count", "ordinal", "none".
  std::string refinement_name(Refinement refinement);
} // namespace anticrack::coupling
