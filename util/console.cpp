#include "util/console.h"

#include "util/mpi_session.h"

#include <mpi.h>

namespace anticrack
{
  bool is_root_process()
  {
    int initialised = 0, finalised = 0;
    MPI_Initialized(&initialised);
    MPI_Finalized(&finalised);
    if (initialised && !finalised)
    {
      int rank = 0;
      MPI_Comm_rank(MPI_COMM_WORLD, &rank);
      return rank == 0;
    }
    return launcher_rank() == 0;
  }

  ConditionalStream root_console(std::ostream &out) { return ConditionalStream(&out, is_root_process()); }
} // namespace anticrack
