#include "dem/common/types.h"

#include <sstream>

namespace anticrack::dem
{
  std::string format_for_message(const double x)
  {
    std::ostringstream s;
    s.precision(6);
    s << x;
    return s.str();
  }
} // namespace anticrack::dem
