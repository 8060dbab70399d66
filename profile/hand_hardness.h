// Hand hardness (the hand hardness test, Fierz et al. 2009, The International Classification for
// Seasonal Snow on the Ground, §2.3): the object that can be pushed into the layer, from a fist (F)
// to a knife (K) and ice (I), with a + or - for a little more or less. Its index is the scale on
// which the density regressions of Geldsetzer & Jamieson (2000) are written: F = 1, 4F = 2, 1F = 3,
// P = 4, K = 5, I = 6, a + adding and a - subtracting one third.
#pragma once

#include <optional>
#include <string>

namespace anticrack::profile
{
  struct HandHardness
  {
    std::string text; ///< as written: "4F+", "1F-", "P"
    double index = 0; ///< F = 1 ... I = 6, +- 1/3
  };

  /// "F", "4F", "1F", "P", "K" or "I" with an optional "+" or "-" (whitespace around ignored);
  /// nullopt for anything else (the caller names the file, layer and field).
  std::optional<HandHardness> parse_hand_hardness(const std::string &text);

  /// What parse_hand_hardness accepts, for messages.
  constexpr const char *hand_hardness_values = "F, 4F, 1F, P, K or I, optionally followed by + or -";
} // namespace anticrack::profile
