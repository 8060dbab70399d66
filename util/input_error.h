// Errors a user can fix by editing an input file or the command line: a scene, a material file, a
// campaign. They are raised before any output is written; the application turns them into exit
// code 2. Shared by the application and the FE library, which reads scene and material files.
#pragma once

#include <stdexcept>

namespace anticrack
{
  class InputError : public std::runtime_error
  {
  public:
    using std::runtime_error::runtime_error;
  };
} // namespace anticrack
