#include "profile/hand_hardness.h"

#include <array>
#include <utility>

namespace anticrack::profile
{
  std::optional<HandHardness> parse_hand_hardness(const std::string &raw)
  {
    const auto first = raw.find_first_not_of(" \t");
    const auto last = raw.find_last_not_of(" \t");
    if (first == std::string::npos)
      return std::nullopt;
    std::string text = raw.substr(first, last - first + 1);
    double modifier = 0;
    if (text.size() > 1 && (text.back() == '+' || text.back() == '-'))
    {
      modifier = text.back() == '+' ? 1.0 / 3.0 : -1.0 / 3.0;
      text.pop_back();
    }
    static const std::array<std::pair<const char *, double>, 6> scale = {
      {{"F", 1}, {"4F", 2}, {"1F", 3}, {"P", 4}, {"K", 5}, {"I", 6}}};
    for (const auto &[name, index] : scale)
      if (text == name)
        return HandHardness{raw.substr(first, last - first + 1), index + modifier};
    return std::nullopt;
  }
} // namespace anticrack::profile
