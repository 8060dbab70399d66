// One table per selection: the names a parameter file uses for the values of an enum. The same
// table makes the deal.II Patterns::Selection string (`pattern()`), turns a parsed name into the
// value (`value()`, which refuses a name the table lacks instead of falling back to some default)
// and gives the name back for messages and summaries (`name()`).
#pragma once

#include <initializer_list>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace anticrack
{
  template <typename Enum>
  class EnumTable
  {
  public:
    EnumTable(std::initializer_list<std::pair<const char *, Enum>> rows) : rows_(rows) {}

    /// "a|b|c", for Patterns::Selection.
    [[nodiscard]] std::string pattern() const
    {
      std::string p;
      for (const auto &[name, value] : rows_)
        p += (p.empty() ? "" : "|") + std::string(name);
      return p;
    }

    [[nodiscard]] Enum value(const std::string &name) const
    {
      for (const auto &[n, value] : rows_)
        if (name == n)
          return value;
      throw std::invalid_argument("`" + name + "` is none of " + pattern());
    }

    [[nodiscard]] std::string name(const Enum value) const
    {
      for (const auto &[n, v] : rows_)
        if (v == value)
          return n;
      throw std::logic_error("EnumTable: a value without a name");
    }

    [[nodiscard]] const std::vector<std::pair<const char *, Enum>> &rows() const { return rows_; }

  private:
    std::vector<std::pair<const char *, Enum>> rows_;
  };
} // namespace anticrack
