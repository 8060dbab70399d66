#include "profile/profile_reader.h"

#include "util/format.h"

#include <cmath>
#include <filesystem>
#include <fstream>

namespace anticrack::profile
{
  const char *role_name(LayerRole role)
  {
    switch (role)
    {
      case LayerRole::slab: return "slab";
      case LayerRole::weak: return "weak";
      case LayerRole::base: return "base";
      default: return "unspecified";
    }
  }

  int SnowProfile::layer_at_depth(double depth_m) const
  {
    for (std::size_t k = 0; k < layers.size(); ++k)
      if (depth_m >= layers[k].depth_top_m &&
          (depth_m < layers[k].depth_bottom_m() || (k + 1 == layers.size() && depth_m <= layers[k].depth_bottom_m())))
        return static_cast<int>(k);
    return -1;
  }

  const std::vector<ProfileFormat> &profile_formats()
  {
    static const std::vector<ProfileFormat> formats = {
      {"CAAML v6.0 SnowProfileIACS",
       "an XML snow profile as SnowPilot and niViz export it (layers, density profile, slope, saw tests)",
       [](const std::string &file, const std::string &head) {
         return std::filesystem::path(file).extension() == ".xml" || std::filesystem::path(file).extension() == ".caaml" ||
                head.rfind("<?xml", 0) == 0 || head.rfind("<", 0) == 0;
       },
       read_caaml_profile},
      {"layer table",
       "CSV, top layer first, a header naming the columns with their units (thickness_cm, density_kg_m3, "
       "grain_form, grain_size_mm, hand_hardness, role)",
       [](const std::string &file, const std::string &) { return std::filesystem::path(file).extension() == ".csv"; },
       read_layer_table},
    };
    return formats;
  }

  SnowProfile read_profile(const std::string &file)
  {
    std::error_code error;
    if (!std::filesystem::is_regular_file(file, error))
      throw ProfileError(file + ": no such profile file");
    const auto size = std::filesystem::file_size(file, error);
    if (error || size > largest_profile_file)
      throw ProfileError(file + ": " + std::to_string(size) + " bytes, more than a snow profile (at most " +
                         std::to_string(largest_profile_file) + " bytes are read)");
    std::string head(64, '\0');
    std::ifstream in(file, std::ios::binary);
    in.read(head.data(), static_cast<std::streamsize>(head.size()));
    head.resize(static_cast<std::size_t>(in.gcount()));
    for (const ProfileFormat &format : profile_formats())
      if (format.recognises(file, head))
      {
        SnowProfile profile = format.read(file);
        profile.file = file;
        profile.format = format.name;
        check_profile(profile);
        return profile;
      }
    std::string names;
    for (const ProfileFormat &format : profile_formats())
      names += std::string(names.empty() ? "" : "; ") + format.name + " (" + format.description + ")";
    throw ProfileError(file + ": not a snow profile anticrack reads: " + names);
  }

  namespace
  {
    std::string centimetres(double metres) { return format_number(100 * metres, 4) + " cm"; }
  } // namespace

  void check_profile(const SnowProfile &p)
  {
    if (p.layers.empty())
      throw ProfileError(p.file + ": the profile has no layers");
    double expected_top = 0;
    for (std::size_t k = 0; k < p.layers.size(); ++k)
    {
      const ProfileLayer &l = p.layers[k];
      const std::string where = p.file + ": layer " + std::to_string(k + 1) + " (top at " + centimetres(l.depth_top_m) + ")";
      if (!std::isfinite(l.depth_top_m) || !std::isfinite(l.thickness_m) || !(l.thickness_m > 0))
        throw ProfileError(where + ": thickness " + centimetres(l.thickness_m) + " must be positive and finite");
      if (std::abs(l.depth_top_m - expected_top) > 1e-6)
        throw ProfileError(where + ": the layer " + (l.depth_top_m < expected_top ? "overlaps" : "leaves a gap below") +
                           " the one above, which ends at " + centimetres(expected_top) +
                           " (layers are read from the surface down, each starting where the one above ends)");
      expected_top = l.depth_bottom_m();
      if (l.grain_size_mm && !(*l.grain_size_mm > 0 && *l.grain_size_mm < 100))
        throw ProfileError(where + ": grain size " + format_number(*l.grain_size_mm) + " mm is outside (0, 100) mm");
      if (l.density_kg_m3 && !(*l.density_kg_m3 >= lightest_snow_density && *l.density_kg_m3 <= ice_density))
        throw ProfileError(where + ": density " + format_number(*l.density_kg_m3) + " kg/m^3 is outside [" +
                           format_number(lightest_snow_density) + ", " + format_number(ice_density) +
                           "] kg/m^3 (is it in another unit, g/cm^3?)");
    }
    for (std::size_t k = 0; k < p.density_samples.size(); ++k)
    {
      const DensitySample &s = p.density_samples[k];
      const std::string where = p.file + ": density sample " + std::to_string(k + 1) + " (top at " + centimetres(s.depth_top_m) + ")";
      if (!std::isfinite(s.depth_top_m) || !(s.thickness_m > 0) || !std::isfinite(s.thickness_m))
        throw ProfileError(where + ": its depth and a positive thickness are needed");
      if (!(s.density_kg_m3 >= lightest_snow_density && s.density_kg_m3 <= ice_density))
        throw ProfileError(where + ": density " + format_number(s.density_kg_m3) + " kg/m^3 is outside [" +
                           format_number(lightest_snow_density) + ", " + format_number(ice_density) +
                           "] kg/m^3 (is it in another unit, g/cm^3?)");
    }
    for (std::size_t k = 0; k < p.saw_tests.size(); ++k)
    {
      const SawTestObservation &t = p.saw_tests[k];
      const std::string where = p.file + ": propagation saw test " + std::to_string(k + 1);
      if (t.propagation != "End" && t.propagation != "Arr" && t.propagation != "SF")
        throw ProfileError(where + ": fracturePropagation `" + t.propagation + "` is not End, Arr or SF");
      if (!(t.column_length_m > 0) || !std::isfinite(t.column_length_m))
        throw ProfileError(where + ": column length " + centimetres(t.column_length_m) + " must be positive");
      if (!(t.cut_length_m >= 0) || t.cut_length_m > t.column_length_m + 1e-9)
        throw ProfileError(where + ": cut length " + centimetres(t.cut_length_m) + " is outside [0, the column's " +
                           centimetres(t.column_length_m) + "]");
      if (p.layer_at_depth(t.failed_depth_m) < 0)
        throw ProfileError(where + ": the failed layer's depth " + centimetres(t.failed_depth_m) +
                           " is not in the profile (0 to " + centimetres(p.height_m()) + ")");
    }
  }
} // namespace anticrack::profile
