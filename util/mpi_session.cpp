#include "util/mpi_session.h"

#include <mpi.h>

#include <cstdlib>

namespace anticrack
{
  bool launched_by_mpirun()
  {
    for (const char *variable : {"OMPI_COMM_WORLD_SIZE", "OMPI_COMM_WORLD_RANK", "PMI_SIZE", "PMI_RANK", "PMIX_RANK"})
      if (std::getenv(variable))
        return true;
    return false;
  }

  int launcher_rank()
  {
    for (const char *variable : {"OMPI_COMM_WORLD_RANK", "PMI_RANK", "PMIX_RANK"})
      if (const char *value = std::getenv(variable))
        return std::atoi(value);
    return 0;
  }

  MpiSession &MpiSession::get()
  {
    static MpiSession session; // destroyed at exit, after main returns
    return session;
  }

  MpiSession::MpiSession()
  {
    int initialised = 0;
    MPI_Initialized(&initialised);
    if (launched_by_mpirun() && !initialised)
    {
      int provided = 0;
      MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
      owns_ = true;
      initialised = 1;
    }
    if (initialised)
    {
      active_ = true;
      MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
      MPI_Comm_size(MPI_COMM_WORLD, &size_);
    }
  }

  MpiSession::~MpiSession()
  {
    int finalised = 0;
    MPI_Finalized(&finalised);
    if (owns_ && !finalised)
      MPI_Finalize();
  }

  void MpiSession::barrier() const
  {
    if (active_)
      MPI_Barrier(MPI_COMM_WORLD);
  }

  bool MpiSession::any(bool flag) const
  {
    int local = flag ? 1 : 0, global = local;
    if (active_)
      MPI_Allreduce(&local, &global, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
    return global != 0;
  }
} // namespace anticrack
