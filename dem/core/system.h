// The DEM system: particles, interactions, boundaries and the time loop.
//
// One step (leapfrog, velocities at half steps, as in PFC and YADE):
//   1. rebuild the Verlet list if some particle moved more than skin/2;
//   2. one kernel per pair fills a per-pair load buffer (parallel over pairs): a bonded pair in the
//      Verlet list gets its bond and its contact from one evaluation of the pair kinematics; bonds
//      whose particles are too far apart to be listed are evaluated on their own;
//   3. every particle gathers its pair loads in a fixed order, adds gravity and wall contacts
//      (parallel over particles; the fixed order makes 1 and N threads agree bit for bit);
//   4. clumps sum their members' loads;
//   5. leapfrog update with Cundall local damping, F_w <- F_w - alpha |F_w| sign(v_w);
//   6. walls move (prescribed velocity or servo), energies are booked, stability is checked.
#pragma once

#include "dem/core/clumps.h"
#include "dem/core/domain.h"
#include "dem/core/energy.h"
#include "dem/common/interactions.h"
#include "dem/core/materials.h"
#include "dem/core/neighbor_list.h"
#include "dem/core/particles.h"
#include "dem/core/walls.h"

#include <functional>
#include <set>
#include <utility>
#include <string>
#include <vector>

namespace anticrack::dem
{
  struct IntegrationSettings
  {
    Vec3 gravity = Vec3::Zero();        ///< [m/s^2]
    double local_damping = 0.0;         ///< alpha of Cundall's local damping [-], 0 <= alpha < 1
    double time_step = 0.0;             ///< fixed step [s]; 0 selects the automatic critical step
    double time_step_safety = 0.5;      ///< dt = safety * dt_crit in automatic mode
    bool enforce_critical_step = true;  ///< refuse a fixed step above the critical estimate
    Index time_step_interval = 100;     ///< steps between re-evaluations of dt_crit
    double verlet_skin = 0.0;           ///< [m]; 0 selects 0.1 * mean radius
    Index stability_check_interval = 100; ///< steps between energy-balance checks
    double energy_drift_tolerance = 0.25; ///< abort when the balance drifts by more (relative)
  };

  /// What a bonding pass should bond.
  struct BondingRule
  {
    BondingRule(double tolerance = 0.0) : gap_tolerance(tolerance) {}
    double gap_tolerance;        ///< bond pairs with gap <= tolerance * min(R_i, R_j)
    /// If not empty, only these pairs (i < j) may be bonded (e.g. the bonds a sampler drew).
    std::set<std::pair<Index, Index>> only_pairs;
  };

  class DemSystem
  {
  public:
    // --- model (public: generators, tests and I/O fill and read these directly)
    ParticleStore particles;
    Domain domain;
    MaterialTable materials;
    ContactList contacts;
    BondList bonds;
    std::vector<Clump> clumps;
    std::vector<Wall> walls;
    IntegrationSettings settings;

    // --- run state (public for checkpoint I/O)
    double time = 0;
    Index step_count = 0;
    double dt = 0;
    EnergyLedger ledger;               ///< path functions accumulate here
    double initial_balance = 0;        ///< balance() at initialise()
    std::vector<Vec3> previous_velocity;          ///< v(n-1/2), for the kinetic energy
    std::vector<Vec3> previous_angular_velocity;
    std::vector<Vec3> wall_shear;      ///< tangential force of sphere-wall contacts, [wall * N + p]
    std::vector<Vec3> wall_dashpot;    ///< dashpot force of sphere-wall contacts (energy booking)

    /// Bonds every pair of particles whose materials allow bonding and whose gap is within the
    /// rule's tolerance; parameters from the material with the smaller id. Returns the count.
    Index bond_touching_pairs(const BondingRule &rule = {});

    /// Bonds particles i and j with the bond parameters of their materials (the one with the smaller
    /// id), across the minimum periodic image; `bond_radius` 0 selects lambda_bar min(R_i, R_j).
    /// Returns the bond's index. Throws SetupError for bad ids.
    Index add_bond(Index i, Index j, double bond_radius = 0);

    /// Adds a clump made of `members`; returns its index.
    Index add_clump(const std::vector<Index> &members);

    /// Validates the set-up, builds the neighbour list and chooses the time step. Call once before
    /// stepping (and again after changing particles, bonds or clumps by hand).
    void initialise();

    /// Re-establishes derived data after a checkpoint has been loaded (no change of state): the
    /// pair-to-bond map and the incidence lists are rebuilt from the loaded lists, the neighbour
    /// list is not (its reference positions come with the checkpoint), so the run continues bit for
    /// bit as if it had never stopped.
    void resume();

    /// Positions at the last neighbour-list build and the critical step of the last evaluation:
    /// run state that checkpoints carry (see resume()).
    [[nodiscard]] const std::vector<Vec3> &neighbor_reference_positions() const
    {
      return neighbor_list_.reference_positions();
    }
    void restore_neighbor_reference_positions(std::vector<Vec3> positions)
    {
      neighbor_list_.restore_reference_positions(std::move(positions));
    }
    [[nodiscard]] double critical_time_step_estimate() const { return dt_critical_; }
    void restore_critical_time_step_estimate(double dt_c) { dt_critical_ = dt_c; }

    /// The energy scale the stability check compares the balance drift with: the largest of the
    /// stored, exchanged and dissipated energies, floored by the energy of every particle moving by
    /// 1e-6 of its radius per critical step (below that the balance is round-off).
    [[nodiscard]] double energy_scale(const EnergyLedger &e) const;

    void step();
    /// Runs n steps; `observer(step_count)` is called after every step when given.
    void run(Index n, const std::function<void(const DemSystem &)> &observer = {});

    /// Critical time step estimate min(sqrt(m/K), sqrt(I/K_rot)) over free particles and clumps,
    /// with the summed stiffness of candidate contacts, bonds and wall contacts (docs/physics.md §1.3).
    /// `where` receives the limiting particle (or -1 - clump index).
    [[nodiscard]] double critical_time_step(Index *where = nullptr) const;

    /// Current energies: state functions computed now, path functions from the ledger.
    [[nodiscard]] EnergyLedger energy() const;

    /// Forces a neighbour-list rebuild now (positions get wrapped into the periodic box).
    void rebuild_neighbors();

    [[nodiscard]] Index neighbor_builds() const { return neighbor_list_.builds(); }

    /// Bonds whose pair is not in the Verlet list, and the load of such a bond at the last step
    /// (the loads of listed pairs, bond and contact together, are in contacts.load).
    [[nodiscard]] const std::vector<Index> &unlisted_bonds() const { return unlisted_bonds_; }
    [[nodiscard]] const PairLoad &unlisted_bond_load(Index bond) const { return bond_load_[bond]; }
    [[nodiscard]] double skin() const { return skin_; }

    /// Number of OpenMP threads used by the force and update loops.
    static void set_threads(int threads);
    static int threads();

  private:
    void compute_pair_loads();
    void compute_unlisted_bond_loads();
    void match_bonds_to_contacts();
    void gather_and_integrate();
    void integrate_clumps();
    void move_walls();
    void update_time_step();
    void build_incidence();
    void update_wall_overlaps();
    void choose_skin();
    void check_stability();

    NeighborList neighbor_list_;
    double skin_ = 0;
    bool incidence_valid_ = false;
    std::vector<Index> bond_of_contact_;  ///< bond of each listed pair, -1 if none
    std::vector<Index> unlisted_bonds_;   ///< bonds whose pair is not in the Verlet list
    std::vector<PairLoad> bond_load_;     ///< loads of the unlisted bonds, indexed by bond
    // Particle -> pair incidence in CSR form: entry = (index << 2) | (unlisted bond << 1) | (particle is j)
    std::vector<Index> incidence_offset_;
    std::vector<Index> incidence_;
    std::vector<Vec3> wall_load_;     ///< force on particle p from wall w, [w * N + p]
    std::vector<double> wall_overlap_;///< overlap of particle p with wall w at the last step
    Index dt_limiting_particle_ = -1;
    double dt_critical_ = 0;
  };
} // namespace anticrack::dem
