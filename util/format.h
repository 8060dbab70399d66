// The one number format of messages, log lines and reports: `value` with `significant_digits`
// significant digits, as a C++ stream writes it in the classic locale ("0.0095", "1e+06", "2.5").
#pragma once

#include <string>

namespace anticrack
{
  std::string format_number(double value, int significant_digits = 6);
} // namespace anticrack
