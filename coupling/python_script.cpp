#include "coupling/python_script.h"

#include <cstdlib>
#include <iostream>

#ifndef ANTICRACK_SCRIPTS_DIR
#  define ANTICRACK_SCRIPTS_DIR "scripts"
#endif
#ifndef ANTICRACK_PYTHON
#  define ANTICRACK_PYTHON "/usr/bin/python3"
#endif

namespace anticrack::coupling
{
  bool run_python_script(const std::string &script, const std::string &directory, const std::string &outputs)
  {
    const std::string command =
      std::string(ANTICRACK_PYTHON) + " \"" + ANTICRACK_SCRIPTS_DIR + "/" + script + "\" \"" + directory + "\"";
    if (std::system(command.c_str()) == 0)
      return true;
    std::cerr << "anticrack: " << script << " failed (" << command << "); " << outputs
              << " are complete without it. Install python3-matplotlib and python3-h5py, or check the message above.\n";
    return false;
  }
} // namespace anticrack::coupling
