#include "coupling/study_scene.h"

#include "util/enum_table.h"
#include "util/input_error.h"
#include "util/parameter_input.h"
#include "util/problems.h"

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/utilities.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <sstream>

namespace anticrack::coupling
{
  namespace fs = std::filesystem;
  using dealii::Patterns::Anything;
  using dealii::Patterns::Integer;
  using dealii::Patterns::Selection;

  namespace
  {
    /// At most this many entries vary in one study (subsections Entry 1 .. Entry 4).
    constexpr int max_entries = 4;
    /// The largest number of variants a study runs (a product grows fast).
    constexpr std::size_t max_variants = 1000;

    const EnumTable<Refinement> &refinements()
    {
      static const EnumTable<Refinement> table{{"size", Refinement::size},
                                               {"count", Refinement::count},
                                               {"ordinal", Refinement::ordinal},
                                               {"none", Refinement::none}};
      return table;
    }

    std::string entry_subsection(int k) { return "Entry " + std::to_string(k); }

    /// `text` as a finite number, or nothing.
    std::optional<double> number_in(const std::string &text)
    {
      std::istringstream in(text);
      double value = 0;
      in >> value;
      if (in.fail() || !(in >> std::ws).eof() || !std::isfinite(value))
        return std::nullopt;
      return value;
    }

    /// The items of a `;`-separated list, trimmed (values may contain commas: lists of angles).
    std::vector<std::string> semicolon_list(const std::string &text)
    {
      std::vector<std::string> items;
      std::string item;
      std::istringstream in(text);
      while (std::getline(in, item, ';'))
        if (!dealii::Utilities::trim(item).empty())
          items.push_back(dealii::Utilities::trim(item));
      return items;
    }
  } // namespace

  std::string refinement_name(const Refinement refinement) { return refinements().name(refinement); }

  std::optional<std::size_t> StudyEntry::finest() const
  {
    if (refinement == Refinement::none)
      return std::nullopt;
    const std::vector<double> v = numbers();
    const auto it = refinement == Refinement::size ? std::min_element(v.begin(), v.end())
                                                   : std::max_element(v.begin(), v.end());
    return static_cast<std::size_t>(it - v.begin());
  }

  std::vector<double> StudyEntry::numbers() const
  {
    if (!measures.empty())
      return measures;
    std::vector<double> v;
    for (const std::string &value : values)
      v.push_back(number_in(value).value_or(std::nan("")));
    return v;
  }

  std::vector<StudyVariant> study_variants(const StudyScene &study)
  {
    std::vector<StudyVariant> variants;
    const std::size_t n = study.entries.size();
    const auto add = [&](const std::vector<std::optional<std::size_t>> &level) {
      StudyVariant v;
      v.level = level;
      for (std::size_t e = 0; e < n; ++e)
        if (level[e])
          v.changes.emplace_back(study.entries[e].path, study.entries[e].values[*level[e]]);
      std::ostringstream id;
      id << 'v' << std::string(variants.size() < 10 ? "00" : variants.size() < 100 ? "0" : "") << variants.size();
      v.id = id.str();
      variants.push_back(std::move(v));
    };
    if (!study.product)
    {
      for (std::size_t e = 0; e < n; ++e)
        for (std::size_t k = 0; k < study.entries[e].values.size(); ++k)
        {
          std::vector<std::optional<std::size_t>> level(n);
          level[e] = k;
          add(level);
        }
      return variants;
    }
    std::vector<std::optional<std::size_t>> level(n, std::size_t{0});
    while (true)
    {
      add(level);
      std::size_t e = n;
      while (e-- > 0)
      {
        if (++*level[e] < study.entries[e].values.size())
          break;
        level[e] = 0;
      }
      if (e == static_cast<std::size_t>(-1))
        return variants;
    }
  }

  std::vector<std::size_t> line_of_entry(const StudyScene &study, const std::vector<StudyVariant> &variants,
                                         const std::size_t e)
  {
    std::vector<std::size_t> line;
    for (std::size_t v = 0; v < variants.size(); ++v)
    {
      if (!variants[v].level[e])
        continue;
      bool on_line = true;
      for (std::size_t other = 0; other < study.entries.size(); ++other)
        if (other != e && study.product)
          on_line = on_line && variants[v].level[other] == study.entries[other].finest().value_or(0);
        else if (other != e)
          on_line = on_line && !variants[v].level[other];
      if (on_line)
        line.push_back(v);
    }
    // Coarsest first: the order of decreasing h (size), increasing value (count, ordinal); as
    // written for entries without refinement.
    const StudyEntry &entry = study.entries[e];
    if (entry.refinement != Refinement::none)
    {
      const std::vector<double> x = entry.numbers();
      std::stable_sort(line.begin(), line.end(), [&](std::size_t a, std::size_t b) {
        const double xa = x[*variants[a].level[e]], xb = x[*variants[b].level[e]];
        return entry.refinement == Refinement::size ? xa > xb : xa < xb;
      });
    }
    return line;
  }

  void declare_study_scene(dealii::ParameterHandler &prm)
  {
    prm.declare_entry("Scene", "study", Selection("study"),
                      "What this scene is: a base scene run again with some of its entries set to other values.");
    prm.enter_subsection("Study");
    prm.declare_entry("Base scene", "", Anything(),
                      "The scene to vary, of any other kind (dem, campaign, calibration, snowpack, pipeline), "
                      "relative to this file. Each variant runs a copy of it with the varied entries set at its "
                      "end (DIR/variants/vNNN/scene.prm).",
                      /*has_to_be_set=*/true);
    prm.declare_entry("Base scene changes", "", Anything(),
                      "Entries set in every variant, a comma-separated list of `path = value` (e.g. `PST/Cut length "
                      "[m] = 0.4` for a shorter run, or fewer outputs). Empty: the base scene as it is.");
    prm.declare_entry("Combination", "one at a time", Selection("one at a time|product"),
                      "one at a time: each entry's values with every other entry as the base scene sets it; "
                      "product: every combination of the entries' values (errors against the variant with every "
                      "entry at its finest value).");
    prm.declare_entry("Results", "", Anything(),
                      "The answers to compare, comma-separated JSON pointers into each variant's summary.json "
                      "(e.g. /results/critical_cut_length_m; `anticrack run` of the base scene shows what its "
                      "summary holds). A variant that has no number there (a crack that did not run) has none.",
                      /*has_to_be_set=*/true);
    prm.declare_entry("Reference values", "", Anything(),
                      "Known values of some results (a closed form, a measurement), a comma-separated list of "
                      "`pointer = value`: their errors are measured against it. The other results' errors are "
                      "measured against the finest variant (entries with a refinement), or not at all.");
    prm.declare_entry("Variants side by side", "1", Integer(1, 64),
                      "Without mpirun: how many variants run at the same time, each in a process of its own "
                      "with the cores shared among them (--threads). 1 gives each variant's wall time alone on "
                      "the machine, which an error-against-run-time study needs.");
    for (int k = 1; k <= max_entries; ++k)
    {
      prm.enter_subsection(entry_subsection(k));
      prm.declare_entry("Path", "", Anything(),
                        "The entry to vary, its subsections and name separated by `/` (e.g. `Mesh/Element length "
                        "[m]`), as the base scene's kind declares it (`anticrack params BASE.prm`). Empty: unused.");
      prm.declare_entry("Values", "", Anything(),
                        "Its values, separated by `;` (a value may itself be a comma-separated list).");
      prm.declare_entry("Refinement", "none", Selection(refinements().pattern()),
                        "How the values refine the answer: size (a length, step or rate; smaller is finer; the "
                        "observed order of convergence in h = value), count (elements or particles; larger is "
                        "finer; order in h = 1/value), ordinal (larger is finer, no order: a polynomial degree), "
                        "none (an input, not a discretisation: a sensitivity study).");
      prm.declare_entry("Measures", "", Anything(),
                        "The number each value stands for, separated by `;`, when the values are not numbers "
                        "themselves: e.g. 2048; 4096 for the values `DEM/Sample/Particle count = 2048; "
                        "DEM/Sample/Particle count = 4096` of a pipeline's Weak layer scene changes. The "
                        "refinement orders the values and measures the order by them. Empty: the values.");
      prm.leave_subsection();
    }
    prm.leave_subsection();
  }

  std::string result_label(const std::string &pointer, const std::vector<std::string> &all_pointers)
  {
    const auto components = [](const std::string &p) {
      return dealii::Utilities::split_string_list(p.empty() ? p : p.substr(1), '/');
    };
    const auto last = [&](const std::string &p, std::size_t n) {
      const std::vector<std::string> parts = components(p);
      std::string label;
      for (std::size_t k = parts.size() - std::min(n, parts.size()); k < parts.size(); ++k)
        label += (label.empty() ? "" : "_") + parts[k];
      return label;
    };
    const std::size_t depth = components(pointer).size();
    std::size_t n = 1;
    const auto shared = [&](const std::string &other) { return other != pointer && last(other, n) == last(pointer, n); };
    // an array index alone says nothing: it takes its array's name
    const auto index_only = [&] {
      const std::string label = last(pointer, n);
      return !label.empty() && std::isdigit(static_cast<unsigned char>(label.front()));
    };
    while (n < depth && (index_only() || std::any_of(all_pointers.begin(), all_pointers.end(), shared)))
      ++n;
    return last(pointer, n);
  }

  StudyScene read_study_scene(const std::string &file)
  {
    const std::string text = read_scene_file(file);
    dealii::ParameterHandler prm;
    declare_study_scene(prm);
    parse_parameter_text(prm, text, file);
    Problems problems("scene file <" + file + ">");
    for (const std::string &missing : prm.get_entries_wrongly_not_set())
      problems.add(demangled_parameter_path(missing), "must be set (a study has no default for it)");
    problems.throw_if_any();

    StudyScene study;
    study.file = fs::absolute(file).lexically_normal().string();
    prm.enter_subsection("Study");
    study.base_scene = path_relative_to_scene(prm.get("Base scene"), file);
    study.base_changes = entry_changes_in_list(prm.get("Base scene changes"), "Study/Base scene changes", problems);
    study.product = prm.get("Combination") == "product";
    study.side_by_side = prm.get_integer("Variants side by side");
    for (const std::string &pointer : dealii::Utilities::split_string_list(prm.get("Results"), ','))
    {
      StudyResult r;
      r.pointer = pointer;
      r.label = pointer.substr(pointer.find_last_of('/') + 1);
      if (pointer.empty() || pointer.front() != '/' || r.label.empty())
        problems.add("Study/Results", pointer, "is not a JSON pointer to a value (e.g. /results/critical_cut_length_m)");
      study.results.push_back(r);
    }
    std::vector<std::string> pointers;
    for (const StudyResult &r : study.results)
      pointers.push_back(r.pointer);
    for (StudyResult &r : study.results)
      if (!r.label.empty())
        r.label = result_label(r.pointer, pointers);
    for (const auto &[pointer, value] : entry_changes_in_list(prm.get("Reference values"), "Study/Reference values", problems))
    {
      const auto it = std::find_if(study.results.begin(), study.results.end(),
                                   [&](const StudyResult &r) { return r.pointer == pointer; });
      const std::optional<double> number = number_in(value);
      if (it == study.results.end())
        problems.add("Study/Reference values", pointer, "is not one of Study/Results");
      else if (!number)
        problems.add("Study/Reference values", pointer + " = " + value, "is not a finite number");
      else
        it->reference = number;
    }
    for (int k = 1; k <= max_entries; ++k)
    {
      prm.enter_subsection(entry_subsection(k));
      const std::string where = "Study/" + entry_subsection(k) + "/";
      StudyEntry entry;
      entry.path = dealii::Utilities::trim(prm.get("Path"));
      const std::string values_text = prm.get("Values");
      entry.values = semicolon_list(values_text);
      entry.refinement = refinements().value(prm.get("Refinement"));
      const std::string measures_text = prm.get("Measures");
      prm.leave_subsection();
      if (entry.path.empty())
      {
        if (!entry.values.empty())
          problems.add(where + "Values", "are given without a Path");
        continue;
      }
      if (entry.values.size() < 2)
        problems.add(where + "Values", values_text.empty() ? "(empty)" : values_text,
                     "give at least 2 values, separated by `;`");
      if (entry.path == "Scene")
        problems.add(where + "Path", "Scene", "the kind of the base scene cannot vary");
      const std::vector<std::string> measures = semicolon_list(measures_text);
      if (!measures.empty() && entry.refinement == Refinement::none)
        problems.add(where + "Measures", measures_text, "are given for Refinement = none (they order a refinement)");
      else if (!measures.empty() && measures.size() != entry.values.size())
        problems.add(where + "Measures", measures_text,
                     "give one number per value: " + std::to_string(entry.values.size()) + " values, " +
                       std::to_string(measures.size()) + " measures");
      else if (entry.refinement != Refinement::none)
        for (const std::string &value : measures.empty() ? entry.values : measures)
        {
          const std::optional<double> x = number_in(value);
          if (!x || !(*x > 0))
            problems.add(where + (measures.empty() ? "Values" : "Measures"), value,
                         "must be a number > 0 for Refinement = " + refinement_name(entry.refinement) +
                           (measures.empty() ? " (or give Measures: the number each value stands for)" : ""));
          else if (!measures.empty())
            entry.measures.push_back(*x);
        }
      for (const StudyEntry &other : study.entries)
        if (other.path == entry.path)
          problems.add(where + "Path", entry.path, "varies in an earlier Entry too");
      study.entries.push_back(std::move(entry));
    }
    prm.leave_subsection();
    if (study.entries.empty())
      problems.add("Study/Entry 1/Path", "(empty)", "a study varies at least one entry");

    if (!fs::exists(study.base_scene))
      problems.add("Study/Base scene", study.base_scene, "does not exist");
    else
    {
      study.base_kind = scene_kind_in_file(study.base_scene);
      if (study.base_kind.empty() || study.base_kind == "study")
        problems.add("Study/Base scene", study.base_scene,
                     study.base_kind.empty() ? "does not say its kind (set Scene = ...): a study's base scene must"
                                             : "is a study itself; the base scene of a study is a scene of another kind");
      for (const ParameterSetting &setting : scan_parameter_settings(read_scene_file(study.base_scene)))
        for (StudyEntry &entry : study.entries)
          if (split_parameter_path(entry.path) == setting.path)
            entry.base_value = setting.value;
      // Base scene changes come first in every variant: an entry that varies overrides its own, and
      // the others' lines sit at it (e.g. a coarser mesh for every line but the mesh's own).
      for (const auto &[path, value] : study.base_changes)
        for (StudyEntry &entry : study.entries)
          if (split_parameter_path(entry.path) == split_parameter_path(path))
            entry.base_value = value;
    }
    std::size_t count = study.product ? 1 : 0;
    for (const StudyEntry &entry : study.entries)
      count = study.product ? count * entry.values.size() : count + entry.values.size();
    if (count > max_variants)
      problems.add("Study/Combination", study.product ? "product" : "one at a time",
                   "gives " + std::to_string(count) + " variants; at most " + std::to_string(max_variants));
    problems.throw_if_any();
    return study;
  }
} // namespace anticrack::coupling
