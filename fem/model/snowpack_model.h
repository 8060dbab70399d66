// The discretised snowpack: mesh, degrees of freedom, the history at quadrature points, and the one
// loop that evaluates the constitutive law over the cells (internal force, optionally the
// consistent tangent, energies). The quasi-static (fem/solver/quasi_static.h) and the explicit
// (fem/solver/explicit_dynamics.h) solvers drive it; neither has a cell loop of its own.
//
// Mesh: parallel::distributed::Triangulation (p4est) built as one structured, graded coarse mesh
// (GridGenerator::subdivided_hyper_rectangle with step sizes): uniform element length along the
// slope, `Weak layer elements` through the weak layer, slab and substratum elements of the target
// heights (fem/scene/layers.h). Cell material ids are layer ids (layer_substratum, layer_weak, then
// slab layers from the bottom). Displacements are FE_Q^dim; plane strain in 2D with the full 3D stress at every
// quadrature point (docs/physics.md §0); the base (normal coordinate 0) is fixed.
//
// The weak layer collapses as one band through its thickness (docs/fem.md "The weak layer, one
// band"): every node strictly inside it is tied to the nodes on its lower and upper faces at the same
// position along the slope, u = (1 − s) u_lower + s u_upper with s the fraction of the thickness
// (AffineConstraints, like the periodic copies). The displacement is therefore linear through the
// layer whatever the number of element rows, as in the beam-on-foundation models (Gaume et al.
// 2017; Rosendahl et al. 2025), and the rows only sample the layer's state more finely. So the
// layer's own parameters hold in every row: the lock-up strain h_c / H closes a collapsed column by
// its collapse height h_c, and ξ_H = ξ H / h_ref gives the softening the plastic closure
// H Δα of the calibrated specimen (h_ref Δα_ref), hence its dissipation per unit area
// (fem/scene/crack_band.h), whatever the rows and the element length.
// Other cohesive Cam-Clay layers (slab, substratum) soften in a crack band of one element row:
// ξ_e = ξ h_e / h_ref, so a band one element high dissipates per unit area h_e ∫ p0 dα over
// Δα = asinh(p0/K)/ξ_e, which does not depend on h_e (Bažant & Oh 1983).
//
// The saw: weak-layer cells are removed progressively as the saw passes them; a cell's intact
// fraction f ∈ [0, 1] is the part of its length not yet cut, and its Cam-Clay stress and weight are
// scaled by max(f, 1e-6) (the floor keeps the nodes inside the cut in the system). It keeps its
// mass and its lock-up: the sawn gap closes once the slab has fallen by the collapse height.
#pragma once

#include "fem/material/layer_point.h"
#include "fem/model/failure_site.h"
#include "fem/scene/layers.h"
#include "fem/scene/snowpack_scene.h"
#include "util/phase_timer.h"

#include <deal.II/base/index_set.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/la_parallel_vector.h>

#include <memory>
#include <vector>

namespace dealii::PETScWrappers::MPI
{
  class SparseMatrix;
  class Vector;
} // namespace dealii::PETScWrappers::MPI

namespace anticrack::fem
{
  /// Energies of the model [J per metre of column width in 2D, J in 3D].
  struct Energies
  {
    double elastic = 0;     ///< ∫ ½ σ:(ε − ε_p) of the committed states (cut cells included with f)
    double dissipated = 0;  ///< plastic work of the committed states
    double kinetic = 0;     ///< set by the explicit solver
    double viscous = 0;     ///< bulk viscosity and damping, set by the explicit solver
    double external_work = 0; ///< set by the solvers
    double removed_by_saw = 0; ///< elastic energy of the material the saw removed
  };

  /// Where the weak layer has failed, measured from the cut end along the column [m].
  struct CrackFronts
  {
    double crack_tip = 0;  ///< far end of the contiguous failed (or cut) columns
    /// Length of the contiguous failed columns from the other (far) end of the column, which a free
    /// end can reach by failing by itself [m].
    double far_end_failed = 0;
    double touchdown = 0;  ///< far end of the farthest column where the collapsed layer locked up
    bool failed_anywhere = false;
    /// Closure of the weak layer, ∫ −ε_nn dn through its thickness (mean over a column's width in
    /// 3D) [m]: the largest over the columns, and the mean over the locked-up columns (0 if none).
    double largest_closure = 0;
    double locked_closure = 0;
  };

  /// Average state of one locally owned cell (for tests and diagnostics).
  template <int dim>
  struct CellSummary
  {
    dealii::Point<dim> center;
    unsigned int layer = 0;
    double intact = 1;
    dealii::SymmetricTensor<2, 3> stress; ///< mean over the quadrature points, as carried (f σ_cc − p_d I)
    dealii::SymmetricTensor<2, 3> strain; ///< mean total strain over the quadrature points
    double p0 = 0;                        ///< mean p0 (Cam-Clay cells)
  };

  template <int dim>
  class SnowpackModel
  {
  public:
    using VectorType = dealii::LinearAlgebra::distributed::Vector<double>;

    /// `timer` (may be null: the model keeps its own) gets the phases "mesh and dofs", "assembly"
    /// (every evaluate(): the one cell loop, with or without the tangent) and "output" (fields).
    SnowpackModel(const SnowpackScene &scene, MPI_Comm communicator, PhaseTimer *timer = nullptr);
    ~SnowpackModel();

    /// Where the run's time goes (util/phase_timer.h); the solvers and analyses add their phases.
    PhaseTimer &timer() const { return timer_; }

    const SnowpackScene &scene() const { return scene_; }
    MPI_Comm communicator() const { return communicator_; }
    const dealii::DoFHandler<dim> &dof_handler() const { return dof_handler_; }
    const dealii::AffineConstraints<double> &constraints() const { return constraints_; }
    const dealii::IndexSet &locally_owned_dofs() const { return locally_owned_dofs_; }
    const dealii::IndexSet &locally_relevant_dofs() const { return locally_relevant_dofs_; }
    dealii::types::global_dof_index n_dofs() const { return dof_handler_.n_dofs(); }
    unsigned int n_cells() const;
    unsigned int n_columns() const { return n_columns_; }

    /// A vector with the ghost layer this model needs for displacements and forces.
    void initialize_vector(VectorType &vector) const;

    /// Gravity body force per unit load factor, with fixed dofs zero (cut cells weigh nothing).
    const VectorType &gravity_force() const { return gravity_force_; }

    /// The lumped (Gauss–Lobatto) mass, one entry per dof, with fixed dofs 1 (never used).
    const VectorType &lumped_mass() const { return lumped_mass_; }

    /// True for the dofs of the fixed base (locally owned or ghost), indexed by local element.
    bool is_fixed(unsigned int local_index) const { return fixed_[local_index]; }
    /// True for the dofs that follow others (locally owned or ghost): the periodic copies and the
    /// nodes inside the weak layer (the band, see above). Their force and mass are moved onto their
    /// masters (condense_constraints()) and their values follow (distribute_constraints()).
    bool is_tied(unsigned int local_index) const { return tied_[local_index]; }
    /// Sets the fixed dofs of a vector to zero.
    void zero_fixed(VectorType &vector) const;

    /// Moves the entries of the tied dofs (periodic copies, nodes inside the weak layer) onto their
    /// masters with the constraint's weights and zeroes them: Cᵀ of a force vector assembled cell by
    /// cell (internal_force, gravity_force and lumped_mass are so already). No-op without ties.
    void condense_constraints(VectorType &vector) const;
    /// Sets each tied dof's entry from its masters (a displacement, a velocity or an increment,
    /// after an update of the masters). No-op without ties.
    void distribute_constraints(VectorType &vector) const;

    /// Cuts the weak layer up to `cut_length` from the cut end (set_cut(0): intact). Returns true
    /// if any cell changed its intact fraction.
    bool set_cut(double cut_length);
    double cut_length() const { return cut_length_; }

    /// What evaluate() computes besides the internal force.
    struct Request
    {
      /// Assemble the consistent tangent and the residual `load_factor · f_gravity − f_int` into
      /// these PETSc objects (through the constraints; fixed rows get the identity).
      dealii::PETScWrappers::MPI::SparseMatrix *tangent = nullptr;
      dealii::PETScWrappers::MPI::Vector *residual = nullptr;
      double load_factor = 1;
      /// Velocity (ghosted) for the bulk viscosity pressure of explicit steps; nullptr: none.
      const VectorType *velocity = nullptr;
    };

    /// Evaluates every locally owned cell at displacement u (ghosted): trial states from the
    /// committed ones, internal force f_int (ghosted layout, compressed, fixed dofs zero), and what
    /// `request` asks for. Returns the largest stable explicit time step of the trial states
    /// (CFL estimate, before the safety factor) over all ranks. Throws ModelReturnMappingError with
    /// the site (layer, cell, quadrature point; the same on every rank) when a return mapping fails.
    double evaluate(const VectorType &u, VectorType &internal_force, const Request &request);

    /// The trial states of the last evaluate() become the committed history.
    void commit();

    /// Power of the bulk viscosity in the last evaluate() with a velocity [W], over all ranks.
    double last_viscous_power() const { return viscous_power_; }

    /// Elastic and dissipated energies of the committed states, over all ranks.
    Energies energies() const;

    /// Where the first non-finite entry of the given vectors (same layout, ghosted) lies, as a
    /// failure site (fem/model/failure_site.h): its node's position, component and layer, on the
    /// lowest rank that has one (null if none). Collective; for failure reports only (it maps every
    /// dof to its support point).
    Json locate_non_finite(const std::vector<const VectorType *> &vectors) const;

    /// Crack and touchdown fronts of the committed states, over all ranks.
    CrackFronts crack_fronts(double failure_fraction) const;

    /// The largest tension in the slab layers relative to their tensile strength.
    struct SlabTension
    {
      double ratio = 0;     ///< σ_f / σ_t (0: no tension anywhere)
      double stress = 0;    ///< σ_f, the largest fibre stress [Pa]
      double strength = 0;  ///< σ_t of its layer [Pa]
      unsigned int layer = 0;
      dealii::Point<dim> position; ///< its column's centre along the slope, and the face (top or bottom)
    };

    /// The largest fibre stress σ_f over the slab layers and the columns, relative to the layer's
    /// tensile strength, of the committed states: per column and layer the least-squares line of
    /// σ_xx through the layer's thickness (its stretching and bending, as a beam), at the face where
    /// it is largest. A quadrature point's σ_1 would instead grow without bound at the column's
    /// corners as the elements shrink. Collective.
    SlabTension slab_tension() const;

    /// How far the weak layer has softened, over all ranks: the mean over its quadrature points of
    /// (p0_initial − p0) / (p0_initial − p0_floor), the measure of crack_fronts() (0: intact, 1: at the
    /// residual strength everywhere; negative where a hardening law has hardened it).
    double weak_layer_softening() const;

    /// Writes the fields of displacement u (ghosted) as VTU/PVTU into `directory` with the given
    /// name stem and index; returns the .pvtu file name (relative to `directory`).
    std::string write_fields(const VectorType &u, const std::string &directory, const std::string &stem,
                             unsigned int index) const;

    /// Writes / reads the history of this rank (committed states, cut, saw energy). load() needs a
    /// model of the same scene on the same number of ranks; throws checkpoint::Mismatch otherwise.
    void save(std::ostream &out) const;
    void load(std::istream &in);

    /// The committed state of every locally owned cell.
    std::vector<CellSummary<dim>> cell_summaries() const;

  private:
    struct CellData;

    void make_mesh();
    void setup_dofs();
    /// The weak layer's band constraints (header): every node strictly inside the weak layer
    /// follows the nodes below and above it on the layer's faces, linearly in the normal coordinate.
    void tie_weak_layer_nodes();
    void setup_cells();
    void assemble_gravity_and_mass();
    void sum_gravity_and_mass();
    double cell_elastic_energy(const CellData &data) const;
    /// (p0_initial − p0) / (p0_initial − p0_floor) of a weak-layer quadrature point.
    double softening_of(const QuadraturePointState &state) const;

    const SnowpackScene &scene_;
    MPI_Comm communicator_;
    mutable PhaseTimer own_timer_; ///< when the caller gives none
    PhaseTimer &timer_;
    dealii::parallel::distributed::Triangulation<dim> triangulation_;
    dealii::FESystem<dim> fe_;
    dealii::DoFHandler<dim> dof_handler_;
    dealii::QGauss<dim> quadrature_;
    dealii::AffineConstraints<double> constraints_;
    dealii::IndexSet locally_owned_dofs_, locally_relevant_dofs_;
    std::shared_ptr<const dealii::Utilities::MPI::Partitioner> partitioner_;
    std::vector<bool> fixed_, tied_;
    struct Tie
    {
      unsigned int tied, master; ///< local indices (the tied dof locally owned, the master owned or ghost)
      double weight;
    };
    std::vector<Tie> ties_;  ///< locally owned tied dofs, one entry per master
    bool has_ties_ = false;  ///< on any rank

    std::vector<Layer> layers_;                    ///< by layer id
    /// Per layer id: its point law (fem/material/layer_point.h; crack band applied).
    std::vector<LayerLaw> layer_laws_;
    std::vector<CellData> cells_;                  ///< locally owned cells, by active cell index order
    std::vector<QuadraturePointState> committed_, trial_;
    // Geometry cache (a flat array is ~10× faster than FEValues::reinit per cell in explicit loops):
    // JxW per quadrature point and the gradients of the scalar shape functions per (point, node).
    std::vector<double> JxW_;
    std::vector<double> normal_coordinate_; ///< of each quadrature point (slope-normal) [m]
    std::vector<dealii::Tensor<1, dim>> gradients_;
    std::vector<unsigned int> component_, node_; ///< of each cell dof
    double removed_by_saw_ = 0;
    unsigned int n_columns_ = 0;
    double cut_length_ = 0;
    double viscous_power_ = 0;

    VectorType gravity_force_, lumped_mass_;
  };
} // namespace anticrack::fem
