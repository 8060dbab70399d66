// Reading a snow profile from a file: the table of formats (one row per format: its name, how a
// file is recognised, its reader) and the checks every profile passes whatever its format. A new
// format is one reader file (profile/NAME_reader.cpp) and its row in profile_formats()
// (profile/profile_reader.cpp).
#pragma once

#include "profile/snow_profile.h"
#include "util/input_error.h"

#include <functional>
#include <string>
#include <vector>

namespace anticrack::profile
{
  /// A profile that cannot be read: the message names the file, the layer (or test, or sample) and
  /// the field. Bad input: exit 2, nothing written.
  class ProfileError : public InputError
  {
  public:
    using InputError::InputError;
  };

  struct ProfileFormat
  {
    const char *name;        ///< "CAAML v6.0 SnowProfileIACS"
    const char *description; ///< one line for `anticrack params` and the docs
    /// Whether `file` (its name and first bytes) is of this format.
    std::function<bool(const std::string &file, const std::string &head)> recognises;
    std::function<SnowProfile(const std::string &file)> read;
  };

  /// Every format anticrack reads, in the order they are tried.
  const std::vector<ProfileFormat> &profile_formats();

  /// The largest profile file read [bytes]: a SnowPilot pit is 10-40 kB; anything near this is not a
  /// profile (and would be parsed whole into memory).
  constexpr std::size_t largest_profile_file = 4 << 20;

  /// Reads `file` in the format that recognises it, then checks what every profile must satisfy
  /// (check_profile). Throws ProfileError.
  SnowProfile read_profile(const std::string &file);

  /// Layers from the surface down, each with a positive finite thickness, contiguous (no gap, no
  /// overlap); every number finite; saw tests with a failed depth inside the profile, a cut within
  /// its column and an outcome End, Arr or SF; density samples inside the plausible range.
  void check_profile(const SnowProfile &profile);

  /// The plausible range of a snow density [kg/m^3]: from the lightest new snow to ice. A value
  /// outside it is in another unit or a typing error.
  constexpr double lightest_snow_density = 10.0, ice_density = 917.0;

  // The readers (one file each).
  SnowProfile read_caaml_profile(const std::string &file);
  SnowProfile read_layer_table(const std::string &file);
} // namespace anticrack::profile
