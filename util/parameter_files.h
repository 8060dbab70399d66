// Printing what a scene kind declares: every entry of a deal.II ParameterHandler with its
// documentation, allowed values and default, as a complete scene (`prm`, itself a valid scene),
// in deal.II's Description style or as JSON. Part of the anticrack_parameter_files library, the
// only piece of util/ that links deal.II.
#pragma once

#include <iosfwd>
#include <string>

namespace dealii
{
  class ParameterHandler;
}

namespace anticrack
{
  enum class ParameterFormat
  {
    prm,
    description,
    json
  };

  /// Prints every entry declared in `prm`; `kind` names the scene kind in the header line.
  void print_parameter_documentation(std::ostream &out, ParameterFormat format, const dealii::ParameterHandler &prm,
                                     const std::string &kind);
} // namespace anticrack
