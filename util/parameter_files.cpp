#include "util/parameter_files.h"

#include <deal.II/base/parameter_handler.h>

#include <nlohmann/json.hpp>

#include <ostream>
#include <sstream>

namespace anticrack
{
  using dealii::ParameterHandler;

  namespace
  {
    void print_wrapped(std::ostream &out, const std::string &indent, const std::string &text)
    {
      constexpr std::size_t width = 96;
      std::istringstream words(text);
      std::string word, line;
      while (words >> word)
      {
        if (!line.empty() && indent.size() + 2 + line.size() + 1 + word.size() > width)
        {
          out << indent << "# " << line << "\n";
          line.clear();
        }
        line += (line.empty() ? "" : " ") + word;
      }
      if (!line.empty())
        out << indent << "# " << line << "\n";
    }

    /// A complete scene with every entry at its default, each preceded by its documentation and
    /// its pattern (deal.II's PRM style has no patterns, its Description style no defaults).
    void print_documented_prm(std::ostream &out, const nlohmann::ordered_json &node, const std::string &indent)
    {
      for (const auto &[name, child] : node.items())
      {
        if (child.contains("default_value") && child.contains("pattern_description"))
        {
          print_wrapped(out, indent, child["documentation"].get<std::string>());
          out << indent << "#   allowed: " << child["pattern_description"].get<std::string>() << "\n"
              << indent << "set " << name << " = " << child["default_value"].get<std::string>() << "\n\n";
        }
        else
        {
          out << indent << "subsection " << name << "\n";
          print_documented_prm(out, child, indent + "  ");
          out << indent << "end\n\n";
        }
      }
    }
  } // namespace

  void print_parameter_documentation(std::ostream &out, const ParameterFormat format, const ParameterHandler &prm,
                                     const std::string &kind)
  {
    switch (format)
    {
      case ParameterFormat::prm:
      {
        std::ostringstream json;
        prm.print_parameters(json, ParameterHandler::JSON | ParameterHandler::KeepDeclarationOrder);
        out << "# Every anticrack " << kind << " "
            << "scene parameter with its documentation, allowed values and default.\n"
            << "# SI units unless the name says otherwise. This listing is itself a valid scene.\n\n";
        print_documented_prm(out, nlohmann::ordered_json::parse(json.str()), "");
        break;
      }
      case ParameterFormat::description:
        prm.print_parameters(out,
                             ParameterHandler::Description | ParameterHandler::KeepDeclarationOrder);
        break;
      case ParameterFormat::json:
        prm.print_parameters(out, ParameterHandler::JSON | ParameterHandler::KeepDeclarationOrder);
        break;
    }
  }
} // namespace anticrack
