// "Report every problem before writing anything": a scene, material or campaign reader collects
// each problem it finds, naming the entry (with its subsection path), the value and why it is
// refused, and throws them all at once as one InputError. Nothing is written before the reader
// returns, so a user fixes a file in one round.
#pragma once

#include "util/input_error.h"

#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace anticrack
{
  class Problems
  {
  public:
    /// `source`: what is being read, e.g. "scene file <pst.prm>".
    explicit Problems(std::string source = "input") : source_(std::move(source)) {}

    /// "entry = value: why"
    template <typename T>
    void add(const std::string &entry, const T &value, const std::string &why)
    {
      std::ostringstream s;
      s.precision(8);
      s << entry << " = " << value << ": " << why;
      list_.push_back(s.str());
    }
    /// "entry: why"
    void add(const std::string &entry, const std::string &why) { list_.push_back(entry + ": " + why); }
    /// A problem that names no single entry.
    void add(const std::string &text) { list_.push_back(text); }

    [[nodiscard]] bool empty() const { return list_.empty(); }
    [[nodiscard]] std::size_t count() const { return list_.size(); }

    /// "Invalid <source>: N problem(s)" and one line per problem.
    [[nodiscard]] std::string text() const
    {
      std::string out = "Invalid " + source_ + ": " + std::to_string(list_.size()) + " problem" +
                        (list_.size() == 1 ? "" : "s") + "\n";
      for (const auto &p : list_)
        out += "  - " + p + "\n";
      return out;
    }

    void throw_if_any() const
    {
      if (!list_.empty())
        throw InputError(text());
    }

  private:
    std::string source_;
    std::vector<std::string> list_;
  };
} // namespace anticrack
