// GoogleTest main for the FE solver tests: MPI and PETSc live for the whole run (deal.II's
// MPI_InitFinalize), which the solver's PETSc objects need.
#include <deal.II/base/mpi.h>

#include <gtest/gtest.h>

int main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
