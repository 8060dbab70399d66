#include "util/parameter_files.h"

#include "util/atomic_file.h"
#include "util/input_error.h"
#include "util/problems.h"

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/utilities.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <ostream>
#include <sstream>

namespace anticrack
{
  std::string demangled_parameter_path(const std::string &mangled)
  {
    std::string path;
    for (std::size_t k = 0; k < mangled.size(); ++k)
    {
      if (mangled[k] == '_' && k + 2 < mangled.size() && std::isxdigit(mangled[k + 1]) && std::isxdigit(mangled[k + 2]))
      {
        path += static_cast<char>(std::stoi(mangled.substr(k + 1, 2), nullptr, 16));
        k += 2;
      }
      else
        path += mangled[k] == '.' ? '/' : mangled[k];
    }
    return path;
  }

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

  std::string ParameterSetting::path_text() const
  {
    std::string text;
    for (const std::string &part : path)
      text += (text.empty() ? "" : "/") + part;
    return text;
  }

  std::vector<ParameterSetting> scan_parameter_settings(const std::string &text)
  {
    const auto trim = [](const std::string &s) {
      const auto first = s.find_first_not_of(" \t\r");
      if (first == std::string::npos)
        return std::string();
      return s.substr(first, s.find_last_not_of(" \t\r") - first + 1);
    };
    std::vector<ParameterSetting> settings;
    std::vector<std::string> subsections;
    std::istringstream in(text);
    std::string raw;
    unsigned int line_number = 0;
    while (std::getline(in, raw))
    {
      const unsigned int first_line = ++line_number;
      std::string line = raw.substr(0, raw.find('#'));
      // A trailing backslash joins the next line (deal.II does the same before parsing).
      while (!line.empty() && trim(line).size() && trim(line).back() == '\\' && std::getline(in, raw))
      {
        ++line_number;
        line = trim(line);
        line.pop_back();
        line = trim(line) + " " + trim(raw.substr(0, raw.find('#')));
      }
      line = trim(line);
      if (line.empty())
        continue;
      std::istringstream words(line);
      std::string keyword;
      words >> keyword;
      if (keyword == "subsection")
        subsections.push_back(trim(line.substr(keyword.size())));
      else if (keyword == "end" && !subsections.empty())
        subsections.pop_back();
      else if (keyword == "set")
      {
        const std::string rest = line.substr(keyword.size());
        const auto equal = rest.find('=');
        ParameterSetting setting;
        setting.path = subsections;
        setting.path.push_back(trim(rest.substr(0, equal)));
        setting.value = equal == std::string::npos ? "" : trim(rest.substr(equal + 1));
        setting.line = first_line;
        settings.push_back(std::move(setting));
      }
    }
    return settings;
  }

  std::string read_scene_file(const std::string &file)
  {
    try
    {
      return read_text_file(file);
    }
    catch (const std::runtime_error &)
    {
      throw InputError("Cannot read the scene file <" + file + ">.");
    }
  }

  std::vector<std::string> split_parameter_path(const std::string &path)
  {
    std::vector<std::string> parts(1);
    int bracket_depth = 0;
    for (const char c : path)
    {
      bracket_depth += c == '[' ? 1 : c == ']' ? -1 : 0;
      if (c == '/' && bracket_depth == 0)
        parts.emplace_back();
      else
        parts.back() += c;
    }
    for (std::string &part : parts)
      part = dealii::Utilities::trim(part);
    return parts;
  }

  std::string scene_text_with_changes(std::string text, const std::vector<EntryChange> &changes,
                                      const std::string &origin)
  {
    if (changes.empty())
      return text;
    if (!text.empty() && text.back() != '\n')
      text += '\n';
    text += "\n# Added " + origin + ".\n";
    for (const auto &[path, value] : changes)
    {
      const std::vector<std::string> parts = split_parameter_path(path);
      for (std::size_t k = 0; k + 1 < parts.size(); ++k)
        text += std::string(2 * k, ' ') + "subsection " + parts[k] + "\n";
      text += std::string(2 * (parts.size() - 1), ' ') + "set " + parts.back() + " = " + value + "\n";
      for (std::size_t k = parts.size() - 1; k-- > 0;)
        text += std::string(2 * k, ' ') + "end\n";
    }
    return text;
  }

  std::vector<EntryChange> entry_changes_in_list(const std::string &list, const std::string &entry, Problems &problems)
  {
    std::vector<EntryChange> changes;
    for (const std::string &item : dealii::Utilities::split_string_list(list, ','))
    {
      const auto equal = item.find('=');
      // An item without `=` after a change continues that change's value: a list value
      // (`Campaign/Loading angles [deg] = 0, 45, Campaign/Realizations = 1`).
      if (equal == std::string::npos && !changes.empty())
        changes.back().second += ", " + dealii::Utilities::trim(item);
      else if (equal == std::string::npos)
        problems.add(entry, "'" + item + "' is not of the form `path = value`");
      else
        changes.emplace_back(dealii::Utilities::trim(item.substr(0, equal)),
                             dealii::Utilities::trim(item.substr(equal + 1)));
    }
    return changes;
  }

  std::string entry_changes_text(const std::vector<EntryChange> &changes)
  {
    std::string text;
    for (const auto &[path, value] : changes)
      text += (text.empty() ? "" : ", ") + path + " = " + value;
    return text;
  }

  const std::vector<std::string> &scene_relative_file_entries()
  {
    static const std::vector<std::string> names{"Material file", "Profile file", "Weak layer scene", "Snowpack scenes",
                                                "Base scene"};
    return names;
  }

  std::string path_relative_to_scene(const std::string &path, const std::string &scene_file)
  {
    namespace fs = std::filesystem;
    const fs::path p(dealii::Utilities::trim(path));
    return (p.is_absolute() ? p : fs::absolute(fs::path(scene_file).parent_path() / p)).lexically_normal().string();
  }

  std::string relocatable_scene_text(const std::string &file)
  {
    namespace fs = std::filesystem;
    const std::string text = read_scene_file(file);
    const auto absolute = [&](const std::string &path) {
      return dealii::Utilities::trim(path).empty() ? std::string() : path_relative_to_scene(path, file);
    };
    std::vector<EntryChange> changes;
    for (const ParameterSetting &setting : scan_parameter_settings(text))
    {
      const auto &names = scene_relative_file_entries();
      if (std::find(names.begin(), names.end(), setting.path.back()) == names.end())
        continue;
      std::string value;
      for (const std::string &item : dealii::Utilities::split_string_list(setting.value, ','))
        value += (value.empty() ? "" : ", ") + absolute(item);
      if (value != setting.value)
      {
        std::string path;
        for (const std::string &part : setting.path)
          path += (path.empty() ? "" : "/") + part;
        changes.emplace_back(path, value);
      }
    }
    return scene_text_with_changes(text, changes, "so that this copy of " + fs::absolute(fs::path(file)).lexically_normal().string() +
                                                    " finds the files it names relative to its folder");
  }

  std::string scene_kind_in_file(const std::string &file)
  {
    for (const ParameterSetting &setting : scan_parameter_settings(read_scene_file(file)))
      if (setting.path.size() == 1 && setting.path.front() == "Scene")
        return setting.value;
    return "";
  }

  namespace
  {
    void collect_entries(const nlohmann::ordered_json &node, std::vector<std::string> &path,
                         std::set<std::vector<std::string>> &entries)
    {
      for (const auto &[name, child] : node.items())
      {
        path.push_back(name);
        if (child.contains("default_value"))
          entries.insert(path);
        else
          collect_entries(child, path, entries);
        path.pop_back();
      }
    }
  } // namespace

  std::set<std::vector<std::string>> declared_entries(const dealii::ParameterHandler &prm)
  {
    std::ostringstream json;
    prm.print_parameters(json, ParameterHandler::JSON);
    std::set<std::vector<std::string>> entries;
    std::vector<std::string> path;
    collect_entries(nlohmann::ordered_json::parse(json.str()), path, entries);
    return entries;
  }

  void print_parameter_documentation(std::ostream &out, const ParameterFormat format, const ParameterHandler &prm,
                                     const std::string &kind, const bool valid_scene)
  {
    switch (format)
    {
      case ParameterFormat::prm:
      {
        std::ostringstream json;
        prm.print_parameters(json, ParameterHandler::JSON | ParameterHandler::KeepDeclarationOrder);
        out << "# Every anticrack " << kind << " "
            << "scene parameter with its documentation, allowed values and default.\n"
            << "# SI units unless the name says otherwise. "
            << (valid_scene ? "This listing is itself a valid scene.\n\n" :
                              "Every variant is listed: a scene sets the entries of its own.\n\n");
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
