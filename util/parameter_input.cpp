#include "util/parameter_input.h"

#include "util/format.h"
#include "util/input_error.h"
#include "util/parameter_files.h"

#include <deal.II/base/exceptions.h>
#include <deal.II/base/parameter_handler.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <regex>
#include <sstream>

namespace anticrack
{
  namespace
  {
    /// The byte offset of the first byte that is not part of well-formed UTF-8 (RFC 3629: no
    /// overlong forms, no surrogates, nothing above U+10FFFF), or npos.
    std::size_t first_invalid_utf8(const std::string &text)
    {
      std::size_t k = 0;
      while (k < text.size())
      {
        const auto byte = [&](std::size_t i) { return static_cast<unsigned char>(text[i]); };
        const unsigned char b = byte(k);
        std::size_t length = 0;
        unsigned int lowest = 0;
        if (b < 0x80)
          length = 1;
        else if ((b & 0xE0) == 0xC0)
          length = 2, lowest = 0x80;
        else if ((b & 0xF0) == 0xE0)
          length = 3, lowest = 0x800;
        else if ((b & 0xF8) == 0xF0)
          length = 4, lowest = 0x10000;
        else
          return k;
        if (k + length > text.size())
          return k;
        unsigned int code = length == 1 ? b : b & (0xFF >> (length + 1));
        for (std::size_t i = 1; i < length; ++i)
        {
          if ((byte(k + i) & 0xC0) != 0x80)
            return k;
          code = (code << 6) | (byte(k + i) & 0x3F);
        }
        if (code < lowest || code > 0x10FFFF || (code >= 0xD800 && code <= 0xDFFF))
          return k;
        k += length;
      }
      return std::string::npos;
    }

    unsigned int line_of_offset(const std::string &text, std::size_t offset)
    {
      return 1 + static_cast<unsigned int>(std::count(text.begin(), text.begin() + static_cast<long>(offset), '\n'));
    }

    /// The unit in an entry's name: "Pa" of "Young's modulus [Pa]", "" without brackets.
    std::string unit_of(const std::string &name)
    {
      const auto open = name.rfind('[');
      const auto close = name.rfind(']');
      return open == std::string::npos || close == std::string::npos || close < open ? ""
                                                                                     : name.substr(open + 1, close - open - 1);
    }

    /// The numbers of a value that is only numbers ("0.01", "0.008, 0.006, 0.010", "nan"), or none.
    std::optional<std::vector<double>> numbers_of(const std::string &value)
    {
      std::vector<double> numbers;
      std::string token;
      std::istringstream in(value);
      while (std::getline(in, token, ','))
      {
        std::istringstream words(token);
        std::string word;
        while (words >> word)
        {
          char *end = nullptr;
          const double x = std::strtod(word.c_str(), &end);
          if (end == word.c_str() || *end != '\0')
            return std::nullopt; // a word: a text value, not a number
          numbers.push_back(x);
        }
      }
      if (numbers.empty())
        return std::nullopt;
      return numbers;
    }

    /// deal.II's message without its stack trace, with the full path of the entry on the line it
    /// names ("Line <12> of file ..."), which deal.II gives by its bare name only.
    std::string deal_ii_message(const dealii::ExceptionBase &e, const std::string &text)
    {
      std::ostringstream info;
      e.print_info(info);
      std::string message = info.str();
      std::smatch match;
      if (std::regex_search(message, match, std::regex("Line <([0-9]+)>")))
      {
        const unsigned int line = static_cast<unsigned int>(std::stoul(match[1].str()));
        const ParameterSetting *setting = nullptr;
        std::vector<ParameterSetting> settings = scan_parameter_settings(text);
        for (const ParameterSetting &s : settings)
          if (s.line <= line)
            setting = &s;
        if (setting && setting->line == line)
          message += "  (the entry " + setting->path_text() + ", line " + std::to_string(line) + ")\n";
      }
      if (message.find("was declared") != std::string::npos || message.find("No entry with name") != std::string::npos)
        message += "  (`anticrack params FILE` lists every entry a scene of this kind and variant can set)\n";
      return message;
    }
  } // namespace

  std::optional<MagnitudeLimit> physical_magnitude_limit(const std::string &unit)
  {
    static const std::vector<std::pair<std::string, MagnitudeLimit>> limits{
      {"Pa", {1e13, "stresses and moduli: diamond's Young's modulus is 1.2e12 Pa"}},
      {"m", {1e4, "lengths and coordinates: 10 km is beyond any snowpack, slope or specimen"}},
      {"m/s", {1e5, "speeds: every elastic wave speed of a solid is below 2e4 m/s"}},
      {"m/s^2", {1e6, "accelerations"}},
      {"kg/m^3", {1e12, "densities: osmium, the densest element, has 2.26e4 kg/m^3; a load platen modelled as a heavy layer uses 1e8"}},
      {"deg", {720, "angles"}},
      {"s", {1e9, "times: 30 years"}},
      {"1/s", {1e9, "rates"}},
      {"J/m^2", {1e6, "fracture energies: ice's is below 1 J/m^2, rock's below 1e3 J/m^2"}},
      {"N/s", {1e15, "force rates"}},
      {"m/(s N)", {1e12, "servo gains"}},
      {"mean radii", {1e6, "distances in mean radii"}},
    };
    for (const auto &[name, limit] : limits)
      if (name == unit)
        return limit;
    return MagnitudeLimit{1e15, "counts and ratios"};
  }

  void check_parameter_text(const std::string &text, const std::string &file, const std::string &what)
  {
    const std::string source = what + " <" + file + ">";
    if (const auto nul = text.find('\0'); nul != std::string::npos)
      throw InputError("The " + source + " is not a text file (a NUL byte at line " +
                       std::to_string(line_of_offset(text, nul)) + "): a " + what +
                       " is a deal.II parameter file (`anticrack params` prints one).");
    if (const auto bad = first_invalid_utf8(text); bad != std::string::npos)
    {
      std::ostringstream byte;
      byte << std::hex << std::uppercase << static_cast<unsigned int>(static_cast<unsigned char>(text[bad]));
      const unsigned int line = line_of_offset(text, bad);
      std::string entry;
      for (const ParameterSetting &setting : scan_parameter_settings(text))
        if (setting.line == line)
          entry = " (the value of " + setting.path_text() + ")";
      throw InputError("The " + source + " is not UTF-8: line " + std::to_string(line) + entry + " holds the byte 0x" +
                       byte.str() +
                       " (Latin-1 or another 8-bit encoding?). Save the file as UTF-8 (e.g. `iconv -f latin1 -t utf-8`).");
    }
    std::istringstream lines(text);
    std::string line;
    for (unsigned int number = 1; std::getline(lines, line); ++number)
    {
      std::istringstream words(line.substr(0, line.find('#')));
      std::string keyword;
      words >> keyword;
      if (keyword == "include" || keyword == "INCLUDE")
        throw InputError("The " + source + ", line " + std::to_string(number) + ", `" + line +
                         "`: anticrack does not follow `include` (a scene is read as its own text: its kind, "
                         "variants and the files it names come from it, and a file that includes itself would "
                         "never end). Copy the entries, or vary a scene with a study's `Base scene changes` or a "
                         "pipeline's scene changes.");
    }
    std::string problems;
    for (const ParameterSetting &setting : scan_parameter_settings(text))
    {
      const std::optional<std::vector<double>> numbers = numbers_of(setting.value);
      if (!numbers)
        continue;
      const std::string unit = unit_of(setting.path.back());
      const MagnitudeLimit limit = *physical_magnitude_limit(unit);
      for (const double x : *numbers)
      {
        const std::string where = "  - line " + std::to_string(setting.line) + ", " + setting.path_text() + " = " +
                                  setting.value + ": ";
        if (!std::isfinite(x))
          problems += where + "not a finite number\n";
        else if (std::abs(x) > limit.largest)
          problems += where + "beyond the magnitude anticrack accepts " + (unit.empty() ? "" : "in " + unit + " ") +
                      "(|value| <= " + format_number(limit.largest) + "; " + limit.why + ")\n";
        else
          continue;
        break;
      }
    }
    if (!problems.empty())
      throw InputError("Invalid " + source + ":\n" + problems);
  }

  void parse_parameter_text(dealii::ParameterHandler &prm, const std::string &text, const std::string &file,
                            const std::string &what, const bool skip_undefined)
  {
    check_parameter_text(text, file, what);
    try
    {
      std::istringstream input(text);
      prm.parse_input(input, file, "", skip_undefined);
    }
    catch (const dealii::ExceptionBase &e)
    {
      throw InputError("Invalid " + what + " <" + file + ">:\n" + deal_ii_message(e, text));
    }
  }
  std::optional<double> parse_optional_number(const std::string &text)
  {
    if (text.empty())
      return std::nullopt;
    std::size_t used = 0;
    double value = 0;
    try
    {
      value = std::stod(text, &used);
    }
    catch (const std::exception &)
    {
      used = 0;
    }
    if (used != text.size() || !std::isfinite(value))
      throw std::invalid_argument("\"" + text + "\" is not a number");
    return value;
  }
} // namespace anticrack
