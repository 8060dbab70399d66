// MPI for the processes that need it, started once. A serial run does not initialise MPI at all
// (it stays free of launcher requirements); under mpirun the first caller of MpiSession::get()
// initialises it (MPI_THREAD_FUNNELED: OpenMP threads inside a rank, MPI calls from the main
// thread only) and it is finalized when the process exits.
//
// Compatible with deal.II's Utilities::MPI::MPI_InitFinalize (the FE analysis, fem/analysis/snowpack_command.cpp):
// the session never initialises MPI that is already initialised, and never finalizes MPI that it
// did not initialise or that is already finalized. (The converse does not hold: MPI_InitFinalize
// initialises unconditionally, so a process that has started the session cannot afterwards start
// an FE analysis through MPI_InitFinalize.)
#pragma once

namespace anticrack
{
  /// Whether the process was started by mpirun (Open MPI, MPICH/PMI or PMIx), read from the
  /// launcher's environment without initialising MPI.
  bool launched_by_mpirun();

  /// This process's rank as the launcher's environment gives it (0 when not launched by mpirun),
  /// without initialising MPI: for deciding before MPI starts which rank reports an error.
  int launcher_rank();

  class MpiSession
  {
  public:
    /// The process's session: initialises MPI on the first call if the process was launched by
    /// mpirun and MPI is not initialised yet; active whenever MPI is initialised.
    static MpiSession &get();

    MpiSession(const MpiSession &) = delete;
    MpiSession &operator=(const MpiSession &) = delete;

    [[nodiscard]] bool active() const { return active_; } ///< MPI is initialised (ranks can talk)
    [[nodiscard]] int rank() const { return rank_; }       ///< in MPI_COMM_WORLD; 0 when inactive
    [[nodiscard]] int size() const { return size_; }       ///< of MPI_COMM_WORLD; 1 when inactive
    void barrier() const;
    /// Logical OR of `flag` over the ranks.
    [[nodiscard]] bool any(bool flag) const;

  private:
    MpiSession();
    ~MpiSession();
    bool owns_ = false, active_ = false;
    int rank_ = 0, size_ = 1;
  };
} // namespace anticrack
