// A table of parameter-file entries bound to the fields of the settings struct that holds them:
// the one table both declares the entries (name, default, range, documentation) and reads them,
// so that each entry's name is written once. For entries whose value is a number or a flag stored
// as is; an entry that is converted (degrees to radians, a name to an enum) keeps its own code.
// Part of the anticrack_parameter_files library, the only piece of util/ that links deal.II.
#pragma once

#include <deal.II/base/parameter_handler.h>

#include <limits>
#include <type_traits>
#include <variant>
#include <vector>

namespace anticrack
{
  template <class Settings>
  struct BoundEntry
  {
    const char *name;          ///< as in the file, with its unit: "Element length [m]"
    const char *default_value;
    /// The field it fills: a real number (Patterns::Double), a count (Patterns::Integer) or a
    /// flag (Patterns::Bool).
    std::variant<double Settings::*, unsigned int Settings::*, bool Settings::*> field;
    double lower;              ///< the range of a number or count, inclusive
    double upper;
    const char *documentation;
  };

  /// The least and largest values a number may take when its range is open on that side.
  inline constexpr double no_lower_bound = std::numeric_limits<double>::lowest();
  inline constexpr double no_upper_bound = std::numeric_limits<double>::max();

  /// Declares every entry of `table` in the current subsection of `prm`.
  template <class Settings>
  void declare_entries(dealii::ParameterHandler &prm, const std::vector<BoundEntry<Settings>> &table)
  {
    namespace Patterns = dealii::Patterns;
    for (const BoundEntry<Settings> &e : table)
      std::visit(
        [&](auto member) {
          using Field = std::remove_reference_t<decltype(std::declval<Settings &>().*member)>;
          if constexpr (std::is_same_v<Field, bool>)
            prm.declare_entry(e.name, e.default_value, Patterns::Bool(), e.documentation);
          else if constexpr (std::is_same_v<Field, unsigned int>)
            prm.declare_entry(e.name, e.default_value,
                              Patterns::Integer(e.lower == no_lower_bound ? Patterns::Integer::min_int_value
                                                                          : static_cast<int>(e.lower),
                                                e.upper == no_upper_bound ? Patterns::Integer::max_int_value
                                                                          : static_cast<int>(e.upper)),
                              e.documentation);
          else
            prm.declare_entry(e.name, e.default_value,
                              Patterns::Double(e.lower == no_lower_bound ? Patterns::Double::min_double_value : e.lower,
                                               e.upper == no_upper_bound ? Patterns::Double::max_double_value : e.upper),
                              e.documentation);
        },
        e.field);
  }

  /// Reads every entry of `table` from the current subsection of `prm` into `settings`.
  template <class Settings>
  void parse_entries(dealii::ParameterHandler &prm, const std::vector<BoundEntry<Settings>> &table, Settings &settings)
  {
    for (const BoundEntry<Settings> &e : table)
      std::visit(
        [&](auto member) {
          using Field = std::remove_reference_t<decltype(settings.*member)>;
          if constexpr (std::is_same_v<Field, bool>)
            settings.*member = prm.get_bool(e.name);
          else if constexpr (std::is_same_v<Field, unsigned int>)
            settings.*member = static_cast<unsigned int>(prm.get_integer(e.name));
          else
            settings.*member = prm.get_double(e.name);
        },
        e.field);
  }
} // namespace anticrack
