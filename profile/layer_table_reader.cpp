// A plain layer table: CSV, top layer first, one row per layer, after a header line that names the
// columns with their units. Lines starting with # are comments; an empty field is a missing value.
//
//   thickness_cm,density_kg_m3,grain_form,grain_size_mm,hand_hardness,role
//   12,,RG,0.5,1F,slab
//   2,,FC,2,4F-,weak
//
// A column named for a quantity in another unit (thickness_mm, density_g_cm3) is refused naming the
// unit the table takes, never converted: a mix-up of units is the error this format invites.
#include "profile/profile_reader.h"

#include "util/format.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace anticrack::profile
{
  namespace
  {
    /// The columns, with their units in their names.
    constexpr std::array<const char *, 6> layer_table_columns = {"thickness_cm", "density_kg_m3", "grain_form",
                                                                 "grain_size_mm", "hand_hardness", "role"};

    std::vector<std::string> split(const std::string &line)
    {
      std::vector<std::string> fields;
      std::string field;
      std::istringstream in(line);
      while (std::getline(in, field, ','))
      {
        const auto first = field.find_first_not_of(" \t\r");
        const auto last = field.find_last_not_of(" \t\r");
        fields.push_back(first == std::string::npos ? "" : field.substr(first, last - first + 1));
      }
      if (!line.empty() && line.back() == ',')
        fields.push_back("");
      return fields;
    }

    /// The quantity of a column name ("thickness" of "thickness_mm").
    std::string quantity(const std::string &column)
    {
      for (const char *known : {"thickness", "density", "grain_size", "grain_form", "hand_hardness", "role"})
        if (column.rfind(known, 0) == 0)
          return known;
      return "";
    }
  } // namespace

  SnowProfile read_layer_table(const std::string &file)
  {
    std::ifstream in(file);
    if (!in)
      throw ProfileError(file + ": cannot be read");
    SnowProfile p;
    std::vector<int> column_of; // field index -> index in layer_table_columns
    std::string line;
    int line_number = 0;
    double depth = 0;
    while (std::getline(in, line))
    {
      ++line_number;
      const std::string where = file + ": line " + std::to_string(line_number);
      if (line.find_first_not_of(" \t\r") == std::string::npos || line[line.find_first_not_of(" \t\r")] == '#')
        continue;
      const std::vector<std::string> fields = split(line);
      if (column_of.empty())
      {
        for (const std::string &name : fields)
        {
          int index = -1;
          for (std::size_t c = 0; c < layer_table_columns.size(); ++c)
            if (name == layer_table_columns[c])
              index = static_cast<int>(c);
          if (index < 0)
          {
            std::string known;
            for (const char *c : layer_table_columns)
              known += std::string(known.empty() ? "" : ", ") + c;
            const std::string q = quantity(name);
            for (const char *c : layer_table_columns)
              if (!q.empty() && quantity(c) == q)
                throw ProfileError(where + ": column `" + name + "`: the layer table gives " + q + " as `" + c +
                                   "` (its unit in its name); convert the column, do not rename it");
            throw ProfileError(where + ": unknown column `" + name + "` (the columns are " + known + ")");
          }
          for (int seen : column_of)
            if (seen == index)
              throw ProfileError(where + ": column `" + name + "` twice");
          column_of.push_back(index);
        }
        if (std::find(column_of.begin(), column_of.end(), 0) == column_of.end())
          throw ProfileError(where + ": the header has no thickness_cm column");
        continue;
      }
      if (fields.size() != column_of.size())
        throw ProfileError(where + ": " + std::to_string(fields.size()) + " fields, the header names " +
                           std::to_string(column_of.size()));
      ProfileLayer l;
      l.depth_top_m = depth;
      const std::string layer = "layer " + std::to_string(p.layers.size() + 1) + " (line " + std::to_string(line_number) + ")";
      const auto number = [&](const std::string &text, const char *column) {
        char *end = nullptr;
        const double value = std::strtod(text.c_str(), &end);
        if (end == text.c_str() || *end != '\0' || !std::isfinite(value))
          throw ProfileError(file + ": " + layer + ": " + column + " `" + text + "` is not a finite number");
        return value;
      };
      bool has_thickness = false;
      for (std::size_t f = 0; f < fields.size(); ++f)
      {
        const std::string &text = fields[f];
        if (text.empty())
          continue;
        const char *column = layer_table_columns[static_cast<std::size_t>(column_of[f])];
        switch (column_of[f])
        {
          case 0: l.thickness_m = number(text, column) * 0.01; has_thickness = true; break;
          case 1: l.density_kg_m3 = number(text, column); break;
          case 2: l.grain_form = text; break;
          case 3: l.grain_size_mm = number(text, column); break;
          case 4:
            l.hardness = parse_hand_hardness(text);
            if (!l.hardness)
              throw ProfileError(file + ": " + layer + ": hand_hardness `" + text + "` is not a hand hardness (" +
                                 hand_hardness_values + ")");
            break;
          case 5:
            if (text == "slab") l.role = LayerRole::slab;
            else if (text == "weak") l.role = LayerRole::weak;
            else if (text == "base") l.role = LayerRole::base;
            else
              throw ProfileError(file + ": " + layer + ": role `" + text + "` is not slab, weak or base");
            break;
        }
      }
      if (!has_thickness)
        throw ProfileError(file + ": " + layer + ": no thickness_cm");
      if (!(l.thickness_m > 0))
        throw ProfileError(file + ": " + layer + ": thickness_cm " + format_number(100 * l.thickness_m) + " must be positive");
      if (!l.density_kg_m3 && !(l.hardness && !l.grain_form.empty()))
        throw ProfileError(file + ": " + layer + ": neither density_kg_m3 nor both hand_hardness and grain_form "
                           "(a layer's density is measured, or inferred from its hardness and grain form)");
      depth += l.thickness_m;
      p.layers.push_back(l);
    }
    if (column_of.empty())
      throw ProfileError(file + ": no header line (the first line that is not a comment names the columns: thickness_cm, ...)");
    return p;
  }
} // namespace anticrack::profile
