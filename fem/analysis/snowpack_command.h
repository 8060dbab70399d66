// `anticrack run` and `anticrack check` for snowpack scenes (a top-level `subsection Snowpack`):
// the deal.II solver of fem/. The scene (and every material file it names) is read and checked
// before anything is written; MPI and PETSc are initialised here (deal.II's MPI_InitFinalize), so
// `mpirun -np N anticrack run SCENE.prm -o DIR` runs on N ranks.
#pragma once

#include "util/run_options.h"

#include <deal.II/base/mpi.h>

#include <optional>

#include <string>

namespace anticrack::fem
{
  /// Runs the snowpack scene of options.scene_file; returns the exit code (0 done, 1 numerical
  /// failure with summary.json "status": "failed"); throws InputError before writing anything.
  int run_snowpack_scene(const RunOptions &options);

  /// The same in a process whose MPI and PETSc are initialised already (one
  /// dealii::Utilities::MPI::MPI_InitFinalize for several analyses: MPI cannot be initialised twice
  /// in a process, so run_snowpack_scene() runs once per process).
  int run_snowpack_scene_in_mpi(const RunOptions &options);

  /// Reads and checks a snowpack scene, builds its mesh and prints what a run would do.
  void check_snowpack_scene(const std::string &scene_file);

  /// Initialises MPI and PETSc for FE analyses in `mpi` (one thread per rank) unless MPI is
  /// initialised already (under mpirun by the session, or by an earlier call): the one place that
  /// starts deal.II's MPI_InitFinalize; MPI finalizes when `mpi` goes out of scope.
  void start_fe_mpi(std::optional<dealii::Utilities::MPI::MPI_InitFinalize> &mpi);
} // namespace anticrack::fem
