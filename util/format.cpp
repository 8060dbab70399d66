#include "util/format.h"

#include <locale>
#include <sstream>

namespace anticrack
{
  std::string format_number(const double value, const int significant_digits)
  {
    std::ostringstream out;
    out.imbue(std::locale::classic()); // no digit grouping whatever the global locale
    out.precision(significant_digits);
    out << value;
    return out.str();
  }
} // namespace anticrack
