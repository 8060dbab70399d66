// Errors of the calibration that the user fixes with other data or options: degenerate failure
// points (one loading angle, no tensile point, fewer points than parameters), a campaign file of
// another format, impossible fits. The message names the file or data set, the quantity and what
// would be accepted; nothing has been written when it is thrown.
#pragma once

#include <stdexcept>
#include <string>

namespace anticrack::params
{
  class CalibrationError : public std::runtime_error
  {
  public:
    using std::runtime_error::runtime_error;
  };
} // namespace anticrack::params
