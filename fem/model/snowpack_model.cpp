// The discretised snowpack (see the header): mesh, dofs, cell caches, the constitutive loop,
// energies, fronts and field output. Explicitly instantiated for dim = 2 and 3.
#include "fem/model/snowpack_model.h"

#include "fem/model/checkpoint.h"
#include "fem/scene/crack_band.h"

#include <deal.II/base/mpi.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping_q1.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/petsc_sparse_matrix.h>
#include <deal.II/lac/petsc_vector.h>
#include <deal.II/numerics/data_out.h>
#include <deal.II/numerics/vector_tools.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>

namespace anticrack::fem
{
  using namespace dealii;

  namespace
  {
    /// Stiffness left to a cell that is cut through, relative to its material: keeps the nodes
    /// inside the cut in the system without carrying load (1e-6 of the weak layer's modulus moves
    /// G(a) by less than 1e-6 relative).
    constexpr double cut_stiffness_floor = 1e-6;

    std::vector<double> equal_steps(double length, unsigned int count)
    {
      return std::vector<double>(count, length / count);
    }

  } // namespace


  template <int dim>
  struct SnowpackModel<dim>::CellData
  {
    typename DoFHandler<dim>::active_cell_iterator cell;
    unsigned int layer = 0;
    unsigned int column = 0;     ///< index along the slope from x = 0
    double height = 0;           ///< extent normal to the slope [m]
    double inverse_h2 = 0;       ///< Σ_i (degree / h_i)², for the CFL estimate
    double density = 0;
    double intact = 1;           ///< intact fraction (saw)
    unsigned int first_qp = 0;   ///< into the state and geometry arrays
    std::vector<types::global_dof_index> dofs;
    std::vector<unsigned int> local_dofs; ///< local element indices of the ghosted vectors
    std::vector<double> nodal_mass;       ///< lumped mass of each cell dof [kg]
  };

  template <int dim>
  SnowpackModel<dim>::SnowpackModel(const SnowpackScene &scene, MPI_Comm communicator, PhaseTimer *timer)
    : scene_(scene)
    , communicator_(communicator)
    , timer_(timer ? *timer : own_timer_)
    , triangulation_(communicator)
    , fe_(FE_Q<dim>(scene.mesh.polynomial_degree), dim)
    , dof_handler_(triangulation_)
    , quadrature_(scene.mesh.polynomial_degree + 1)
  {
    const auto phase = timer_.scope("mesh and dofs");
    for (unsigned int id = 0; id < n_layers(scene.snowpack); ++id)
      layers_.push_back(layer_of(scene.snowpack, id));
    make_mesh();
    setup_dofs();
    setup_cells();
    assemble_gravity_and_mass();
  }

  template <int dim>
  SnowpackModel<dim>::~SnowpackModel()
  {
    cells_.clear(); // cell iterators before the DoFHandler
    dof_handler_.clear();
  }

  template <int dim>
  unsigned int SnowpackModel<dim>::n_cells() const
  {
    return triangulation_.n_global_active_cells();
  }

  template <int dim>
  void SnowpackModel<dim>::make_mesh()
  {
    const MeshParameters &m = scene_.mesh;
    const Snowpack &s = scene_.snowpack;
    const double length = scene_.pst.column_length;
    n_columns_ = column_count(scene_);

    // Through the thickness, layer by layer from the base (layer ids), element_rows() equal rows.
    std::vector<double> normal_steps;
    for (unsigned int id = 0; id < layers_.size(); ++id)
      if (layers_[id].thickness > 0)
      {
        const auto steps = equal_steps(layers_[id].thickness, element_rows(scene_, id));
        normal_steps.insert(normal_steps.end(), steps.begin(), steps.end());
      }

    std::vector<std::vector<double>> step_sizes;
    step_sizes.push_back(equal_steps(length, n_columns_));
    Point<dim> upper;
    upper[0] = length;
    if (dim == 3)
    {
      const double width = scene_.pst.column_width;
      step_sizes.push_back(equal_steps(width, std::max(1u, (unsigned int)std::lround(width / m.element_length))));
      upper[1] = width;
    }
    step_sizes.push_back(normal_steps);
    upper[dim - 1] = s.total_thickness();
    GridGenerator::subdivided_hyper_rectangle(triangulation_, step_sizes, Point<dim>(), upper);
    if (scene_.pst.column_ends == SawTest::ColumnEnds::periodic)
    {
      // Boundary ids 2k and 2k + 1 on the faces normal to lateral axis k (x; y in 3D), which repeat;
      // p4est then keeps the periodic neighbours in the ghost layer.
      std::vector<GridTools::PeriodicFacePair<typename Triangulation<dim>::cell_iterator>> pairs;
      for (unsigned int axis = 0; axis + 1 < dim; ++axis)
      {
        for (const auto &cell : triangulation_.active_cell_iterators())
          for (const unsigned int f : cell->face_indices())
            if (cell->face(f)->at_boundary())
            {
              const double x = cell->face(f)->center()[axis];
              if (std::abs(x) < 1e-12 * upper[axis])
                cell->face(f)->set_boundary_id(2 + 2 * axis);
              else if (std::abs(x - upper[axis]) < 1e-12 * upper[axis])
                cell->face(f)->set_boundary_id(3 + 2 * axis);
            }
        GridTools::collect_periodic_faces(triangulation_, 2 + 2 * axis, 3 + 2 * axis, axis, pairs);
      }
      triangulation_.add_periodicity(pairs);
    }

    // Layer ids from the cell centres; the base gets boundary id 1.
    const std::vector<double> tops = layer_tops(s);
    for (const auto &cell : triangulation_.active_cell_iterators())
    {
      cell->set_material_id(layer_id_at(tops, cell->center()[dim - 1]));
      for (const unsigned int f : cell->face_indices())
        if (cell->face(f)->at_boundary() && std::abs(cell->face(f)->center()[dim - 1]) < 1e-12)
          cell->face(f)->set_boundary_id(1);
    }
  }

  template <int dim>
  void SnowpackModel<dim>::setup_dofs()
  {
    dof_handler_.distribute_dofs(fe_);
    locally_owned_dofs_ = dof_handler_.locally_owned_dofs();
    DoFTools::extract_locally_relevant_dofs(dof_handler_, locally_relevant_dofs_);
    constraints_.clear();
    constraints_.reinit(locally_relevant_dofs_);
    // Periodic ends first: the base's own nodes at both ends are then fixed through their masters.
    if (scene_.pst.column_ends == SawTest::ColumnEnds::periodic)
      for (unsigned int axis = 0; axis + 1 < dim; ++axis)
        DoFTools::make_periodicity_constraints(dof_handler_, 2 + 2 * axis, 3 + 2 * axis, axis, constraints_);
    tie_weak_layer_nodes();
    VectorTools::interpolate_boundary_values(dof_handler_, 1, Functions::ZeroFunction<dim>(dim), constraints_);
    constraints_.close();
    partitioner_ = std::make_shared<Utilities::MPI::Partitioner>(locally_owned_dofs_, locally_relevant_dofs_,
                                                                 communicator_);
    // Fixed: lines without entries (the base, and periodic copies of base nodes); the others are
    // tied to their masters (periodic copies, nodes inside the weak layer; condense_constraints()).
    fixed_.assign(partitioner_->locally_owned_size() + partitioner_->n_ghost_indices(), false);
    tied_ = fixed_;
    ties_.clear();
    for (const auto &line : constraints_.get_lines())
      if (locally_relevant_dofs_.is_element(line.index))
      {
        const unsigned int local = partitioner_->global_to_local(line.index);
        if (line.entries.empty())
          fixed_[local] = true;
        else
        {
          tied_[local] = true;
          if (locally_owned_dofs_.is_element(line.index))
            for (const auto &[master, weight] : line.entries)
              ties_.push_back({local, partitioner_->global_to_local(master), weight});
        }
      }
    has_ties_ = Utilities::MPI::logical_or(!ties_.empty(), communicator_);
  }

  template <int dim>
  void SnowpackModel<dim>::tie_weak_layer_nodes()
  {
    const std::vector<double> tops = layer_tops(scene_.snowpack);
    const double bottom = layer_weak == 0 ? 0. : tops[layer_weak - 1], top = tops[layer_weak];
    const double thickness = top - bottom, tolerance = 1e-9 * scene_.snowpack.total_thickness();
    if (!(thickness > 0))
      return;
    // The dofs on the layer's two faces, by (position along the slope [and across], face, component),
    // from every rank: a column of weak-layer cells may span ranks.
    const std::vector<Point<dim>> &unit_points = fe_.get_unit_support_points();
    const MappingQ1<dim> mapping;
    std::vector<types::global_dof_index> dofs(fe_.n_dofs_per_cell());
    auto key_of = [&](const Point<dim> &p) {
      std::array<long long, 2> key{{std::llround(p[0] / tolerance), dim == 3 ? std::llround(p[1] / tolerance) : 0}};
      return key;
    };
    // f(position, component, dof) for every support point of the weak layer's cells that `take`.
    auto for_each_support_point = [&](auto take, auto f) {
      for (const auto &cell : dof_handler_.active_cell_iterators())
        if (take(cell) && cell->material_id() == layer_weak)
        {
          cell->get_dof_indices(dofs);
          for (unsigned int i = 0; i < dofs.size(); ++i)
            f(mapping.transform_unit_to_real_cell(cell, unit_points[i]),
              (long long)fe_.system_to_component_index(i).first, dofs[i]);
        }
    };
    std::vector<long long> face_dofs; // (key 0, key 1, face 0|1, component, dof) per entry
    for_each_support_point([](const auto &cell) { return cell->is_locally_owned(); },
                           [&](const Point<dim> &x, long long component, types::global_dof_index dof) {
                             const double n = x[dim - 1];
                             const int face = std::abs(n - bottom) < tolerance ? 0 : std::abs(n - top) < tolerance ? 1 : -1;
                             if (face < 0)
                               return;
                             const auto key = key_of(x);
                             face_dofs.insert(face_dofs.end(), {key[0], key[1], face, component, (long long)dof});
                           });
    std::map<std::array<long long, 4>, types::global_dof_index> on_face;
    for (const std::vector<long long> &from_rank : Utilities::MPI::all_gather(communicator_, face_dofs))
      for (std::size_t k = 0; k + 4 < from_rank.size(); k += 5)
        on_face[{{from_rank[k], from_rank[k + 1], from_rank[k + 2], from_rank[k + 3]}}] = from_rank[k + 4];

    // Every locally relevant dof strictly inside the layer: u = (1 − s) u_lower + s u_upper.
    for_each_support_point(
      [](const auto &cell) { return cell->is_locally_owned() || cell->is_ghost(); },
      [&](const Point<dim> &x, long long component, types::global_dof_index dof) {
        const double n = x[dim - 1];
        if (n < bottom + tolerance || n > top - tolerance || constraints_.is_constrained(dof))
          return;
        const auto key = key_of(x);
        const auto lower = on_face.find({{key[0], key[1], 0, component}}),
                   upper = on_face.find({{key[0], key[1], 1, component}});
        AssertThrow(lower != on_face.end() && upper != on_face.end(),
                    ExcMessage("the weak layer's faces have no node below or above an inner node"));
        const double s = (n - bottom) / thickness;
        constraints_.add_line(dof);
        constraints_.add_entry(dof, lower->second, 1 - s);
        constraints_.add_entry(dof, upper->second, s);
      });
  }

  template <int dim>
  void SnowpackModel<dim>::condense_constraints(VectorType &vector) const
  {
    if (!has_ties_)
      return;
    // A tied dof's force acts on its masters (its displacement is theirs, weighted): moved there,
    // across ranks through the ghost layer, and zeroed at the tied dof.
    VectorType moved;
    initialize_vector(moved);
    for (const Tie &t : ties_)
      moved.local_element(t.master) += t.weight * vector.local_element(t.tied);
    for (const Tie &t : ties_)
      vector.local_element(t.tied) = 0;
    moved.compress(VectorOperation::add);
    vector += moved;
  }

  template <int dim>
  void SnowpackModel<dim>::distribute_constraints(VectorType &vector) const
  {
    if (!has_ties_)
      return;
    vector.zero_out_ghost_values();
    constraints_.distribute(vector);
  }

  template <int dim>
  void SnowpackModel<dim>::initialize_vector(VectorType &vector) const
  {
    vector.reinit(partitioner_);
  }

  template <int dim>
  void SnowpackModel<dim>::zero_fixed(VectorType &vector) const
  {
    for (unsigned int i = 0; i < partitioner_->locally_owned_size(); ++i)
      if (fixed_[i])
        vector.local_element(i) = 0;
  }

  template <int dim>
  void SnowpackModel<dim>::setup_cells()
  {
    const unsigned int degree = scene_.mesh.polynomial_degree;
    // Parameters per layer, for its element height (crack band, cam_clay_parameters()).
    for (unsigned int id = 0; id < layers_.size(); ++id)
    {
      const Layer &layer = layers_[id];
      // A cohesive Cam-Clay layer with a friction coefficient takes the frictional law once it has
      // failed (fem/material/layer_point.h).
      layer_laws_.push_back(layer.model == Layer::Model::cohesive_cam_clay
                              ? LayerLaw::cohesive_cam_clay(cam_clay_parameters(layer, band_height(scene_, id)),
                                                            layer.friction_coefficient)
                              : LayerLaw::elastic(layer.material.youngs_modulus, layer.material.poisson_ratio));
    }

    FEValues<dim> fe_values(fe_, quadrature_, update_gradients | update_JxW_values | update_quadrature_points);
    const unsigned int n_q = quadrature_.size();
    const double column_length = scene_.pst.column_length / n_columns_;
    // Dof i of a cell is component component_[i] of the scalar shape function node_[i]; the
    // gradient of node k's shape function is that of the dof of component 0 at node k.
    const unsigned int n_nodes = fe_.base_element(0).n_dofs_per_cell();
    std::vector<unsigned int> node_dof(n_nodes);
    for (unsigned int i = 0; i < fe_.n_dofs_per_cell(); ++i)
    {
      const auto [component, node] = fe_.system_to_component_index(i);
      component_.push_back(component);
      node_.push_back(node);
      if (component == 0)
        node_dof[node] = i;
    }
    for (const auto &cell : dof_handler_.active_cell_iterators())
    {
      if (!cell->is_locally_owned())
        continue;
      CellData data;
      data.cell = cell;
      data.layer = cell->material_id();
      data.column = std::min(n_columns_ - 1, (unsigned int)std::floor(cell->center()[0] / column_length));
      const BoundingBox<dim> box = cell->bounding_box();
      data.height = box.side_length(dim - 1);
      // The weak layer's tied rows move as one element of the layer's thickness, linear through it
      // (tie_weak_layer_nodes()): its stiffness and condensed mass are those of that element.
      for (unsigned int d = 0; d < dim; ++d)
        data.inverse_h2 += d + 1 == dim && data.layer == layer_weak
                             ? std::pow(1 / layers_[layer_weak].thickness, 2)
                             : std::pow(degree / box.side_length(d), 2);
      data.density = layers_[data.layer].material.density;
      data.first_qp = committed_.size();
      data.dofs.resize(fe_.n_dofs_per_cell());
      cell->get_dof_indices(data.dofs);
      for (const auto g : data.dofs)
        data.local_dofs.push_back(partitioner_->global_to_local(g));
      fe_values.reinit(cell);
      for (unsigned int q = 0; q < n_q; ++q)
      {
        JxW_.push_back(fe_values.JxW(q));
        normal_coordinate_.push_back(fe_values.quadrature_point(q)[dim - 1]);
        for (unsigned int node = 0; node < n_nodes; ++node)
          gradients_.push_back(fe_values.shape_grad_component(node_dof[node], q, 0));
      }
      QuadraturePointState initial;
      if (layers_[data.layer].model == Layer::Model::cohesive_cam_clay)
        initial.material = CamClayState::initial(layer_laws_[data.layer].parameters);
      committed_.insert(committed_.end(), n_q, initial);
      cells_.push_back(std::move(data));
    }
    trial_ = committed_;
  }

  template <int dim>
  void SnowpackModel<dim>::assemble_gravity_and_mass()
  {
    // Gauss–Lobatto points coincide with the support points of FE_Q, so the mass integrated with
    // them is diagonal (step-48); the same rule integrates the body force. Each cell's nodal masses
    // are kept so that the saw can remove a cut cell's mass and weight with its stiffness.
    const QGaussLobatto<dim> lobatto(fe_.degree + 1);
    FEValues<dim> fe_values(fe_, lobatto, update_values | update_JxW_values);
    for (CellData &data : cells_)
    {
      fe_values.reinit(data.cell);
      data.nodal_mass.assign(fe_.n_dofs_per_cell(), 0.);
      for (unsigned int i = 0; i < fe_.n_dofs_per_cell(); ++i)
        for (unsigned int q = 0; q < lobatto.size(); ++q)
          data.nodal_mass[i] += data.density * fe_values.shape_value(i, q) * fe_values.JxW(q);
    }
    initialize_vector(gravity_force_);
    initialize_vector(lumped_mass_);
    sum_gravity_and_mass();
  }

  template <int dim>
  void SnowpackModel<dim>::sum_gravity_and_mass()
  {
    // Gravity in slope-parallel coordinates: g (sin ψ e_x − cos ψ e_n).
    const Snowpack &s = scene_.snowpack;
    Tensor<1, dim> g;
    g[0] = s.gravity * std::sin(s.slope_angle);
    g[dim - 1] = -s.gravity * std::cos(s.slope_angle);
    gravity_force_ = 0;
    lumped_mass_ = 0;
    for (const CellData &data : cells_)
    {
      // A cut cell weighs the fraction f of its weight (the sawn material is gone; its nodes would
      // otherwise sink under their own weight on the stiffness floor) but keeps its mass, so that
      // the lock-up's stiffness, which it keeps whole, does not shrink the stable time step.
      const double factor = std::max(data.intact, cut_stiffness_floor);
      for (unsigned int i = 0; i < fe_.n_dofs_per_cell(); ++i)
      {
        lumped_mass_.local_element(data.local_dofs[i]) += data.nodal_mass[i];
        gravity_force_.local_element(data.local_dofs[i]) += factor * data.nodal_mass[i] * g[component_[i]];
      }
    }
    gravity_force_.compress(VectorOperation::add);
    lumped_mass_.compress(VectorOperation::add);
    // The tied dofs' mass moves onto their masters with the constraint's weights: the row sums of
    // Cᵀ M C (the weights of a tie sum to 1), the lumped mass of the constrained system.
    condense_constraints(gravity_force_);
    condense_constraints(lumped_mass_);
    zero_fixed(gravity_force_);
    for (unsigned int i = 0; i < partitioner_->locally_owned_size(); ++i)
      if (fixed_[i] || tied_[i])
        lumped_mass_.local_element(i) = 1;
  }

  template <int dim>
  bool SnowpackModel<dim>::set_cut(double cut_length)
  {
    cut_length_ = cut_length;
    const double column_length = scene_.pst.column_length / n_columns_;
    bool changed = false;
    double removed = 0;
    for (CellData &data : cells_)
    {
      if (data.layer != layer_weak)
        continue;
      // Columns counted from the cut end; the part of this column's length the saw has passed.
      const unsigned int from_cut = scene_.pst.cut_side == SawTest::CutSide::upslope ? data.column
                                                                                      : n_columns_ - 1 - data.column;
      const double cut_part = std::clamp(cut_length / column_length - from_cut, 0., 1.);
      const double intact = 1 - cut_part;
      if (intact != data.intact)
      {
        removed += (std::max(data.intact, cut_stiffness_floor) - std::max(intact, cut_stiffness_floor)) *
                   cell_elastic_energy(data);
        data.intact = intact;
        changed = true;
      }
    }
    removed_by_saw_ += Utilities::MPI::sum(removed, communicator_);
    changed = Utilities::MPI::logical_or(changed, communicator_);
    if (changed)
      sum_gravity_and_mass();
    return changed;
  }

  template <int dim>
  double SnowpackModel<dim>::cell_elastic_energy(const CellData &data) const
  {
    double energy = 0;
    for (unsigned int q = 0; q < quadrature_.size(); ++q)
      energy += committed_[data.first_qp + q].cam_clay_energy_density() * JxW_[data.first_qp + q];
    return energy;
  }

  template <int dim>
  double SnowpackModel<dim>::evaluate(const VectorType &u, VectorType &internal_force, const Request &request)
  {
    const auto phase = timer_.scope("assembly");
    const unsigned int n_q = quadrature_.size();
    const unsigned int dofs_per_cell = fe_.n_dofs_per_cell();
    const Analysis &analysis = scene_.analysis;
    const unsigned int n_nodes = fe_.base_element(0).n_dofs_per_cell();
    FullMatrix<double> cell_matrix(dofs_per_cell, dofs_per_cell);
    std::vector<double> u_local(dofs_per_cell), v_local(dofs_per_cell), f_local(dofs_per_cell);
    internal_force = 0;
    double max_rate2 = 0; // max over cells of c_p² Σ (p/h_i)²
    double viscous_power = 0;
    Json failure; // the site of this rank's first failed return mapping (null: none)

    for (CellData &data : cells_)
    {
      const LayerLaw &law = layer_laws_[data.layer];
      const double stress_factor = std::max(data.intact, cut_stiffness_floor);
      for (unsigned int i = 0; i < dofs_per_cell; ++i)
      {
        u_local[i] = u.local_element(data.local_dofs[i]);
        if (request.velocity)
          v_local[i] = request.velocity->local_element(data.local_dofs[i]);
      }
      std::fill(f_local.begin(), f_local.end(), 0.);
      if (request.tangent)
        cell_matrix = 0;
      double cell_modulus = 0; // largest P-wave modulus of the cell's points, as they are loaded
      bool cell_failed = false;

      for (unsigned int q = 0; q < n_q; ++q)
      {
        const double JxW = JxW_[data.first_qp + q];
        const Tensor<1, dim> *gradients = &gradients_[(data.first_qp + q) * n_nodes];
        // Strain (3D; plane strain leaves the out-of-plane components zero) and velocity divergence.
        SymmetricTensor<2, 3> strain;
        double volumetric_rate = 0;
        for (unsigned int i = 0; i < dofs_per_cell; ++i)
        {
          const unsigned int c = component_[i];
          const Tensor<1, dim> &grad = gradients[node_[i]];
          for (unsigned int j = 0; j < dim; ++j)
            strain[c][j] += (c == j ? 1. : 0.5) * u_local[i] * grad[j];
          if (request.velocity)
            volumetric_rate += v_local[i] * grad[c];
        }
        // The loop above adds ½ (u_c,j) to [c][j] for c ≠ j from both (c, j) and (j, c) dofs,
        // which SymmetricTensor stores in one place: ε_cj = ½ (u_c,j + u_j,c).

        QuadraturePointState &state = trial_[data.first_qp + q];
        const QuadraturePointState &previous = committed_[data.first_qp + q];
        SymmetricTensor<4, 3> tangent;
        try
        {
          const LayerPointUpdate update = update_layer_point(law, previous, strain, stress_factor, data.intact < 1,
                                                             dim - 1, request.tangent != nullptr, state);
          if (request.tangent)
            tangent = update.tangent;
          cell_modulus = std::max(cell_modulus, update.p_wave_modulus);
        }
        catch (const ReturnMappingError &e)
        {
          // Finish the loop (and the collective compress below) on every rank, then throw on all.
          if (failure.is_null())
          {
            const Point<dim> centre = data.cell->center();
            std::ostringstream where;
            where << "in the " << layers_[data.layer].label << " at cell centre " << centre
                  << ", quadrature point " << q << ": " << e.what();
            failure = {{"description", where.str()},
                       {"layer", layers_[data.layer].label},
                       {"cell", data.cell->id().to_string()},
                       {"cell_centre_m", std::vector<double>(centre.begin_raw(), centre.end_raw())},
                       {"quadrature_point", q},
                       {"rank", Utilities::MPI::this_mpi_process(communicator_)},
                       {"material", e.what()}};
          }
          cell_failed = true;
          break;
        }
        SymmetricTensor<2, 3> stress = carried_stress(state, stress_factor);

        if (request.velocity && volumetric_rate < 0)
        {
          // Bulk viscosity (compression only), the von Neumann–Richtmyer quadratic term and a
          // linear term, over the cell's smallest length: p_v = ρ h (c_2² h |ε̇_v|² + c_1 c |ε̇_v|).
          const double h = 1 / std::sqrt(data.inverse_h2);
          const double c = std::sqrt(cell_modulus / data.density);
          const double rate = -volumetric_rate;
          const double p_v = data.density * h *
                             (analysis.quadratic_bulk_viscosity * analysis.quadratic_bulk_viscosity * h * rate +
                              analysis.linear_bulk_viscosity * c) *
                             rate;
          stress -= p_v * unit_symmetric_tensor<3>();
          viscous_power += p_v * rate * JxW;
        }

        for (unsigned int i = 0; i < dofs_per_cell; ++i)
        {
          const unsigned int c = component_[i];
          const Tensor<1, dim> &grad = gradients[node_[i]];
          double f = 0;
          for (unsigned int j = 0; j < dim; ++j)
            f += stress[c][j] * grad[j];
          f_local[i] += f * JxW;
        }
        if (request.tangent)
          for (unsigned int i = 0; i < dofs_per_cell; ++i)
          {
            const unsigned int ci = component_[i];
            const Tensor<1, dim> &grad_i = gradients[node_[i]];
            for (unsigned int k = 0; k < dofs_per_cell; ++k)
            {
              const unsigned int ck = component_[k];
              const Tensor<1, dim> &grad_k = gradients[node_[k]];
              double value = 0;
              for (unsigned int j = 0; j < dim; ++j)
                for (unsigned int l = 0; l < dim; ++l)
                  value += grad_i[j] * tangent[ci][j][ck][l] * grad_k[l];
              cell_matrix(i, k) += value * JxW;
            }
          }
      }
      if (cell_failed)
        continue;
      for (unsigned int i = 0; i < dofs_per_cell; ++i)
        internal_force.local_element(data.local_dofs[i]) += f_local[i];
      if (request.tangent)
        constraints_.distribute_local_to_global(cell_matrix, data.dofs, *request.tangent);
      max_rate2 = std::max(max_rate2, cell_modulus / data.density * data.inverse_h2);
    }
    internal_force.compress(VectorOperation::add);
    condense_constraints(internal_force);
    zero_fixed(internal_force);
    if (request.tangent)
      request.tangent->compress(VectorOperation::add);
    if (Utilities::MPI::logical_or(!failure.is_null(), communicator_))
      throw ModelReturnMappingError(first_failure_site_on_any_rank(failure, communicator_));
    viscous_power_ = Utilities::MPI::sum(viscous_power, communicator_);
    max_rate2 = Utilities::MPI::max(max_rate2, communicator_);
    // Central differences are stable for Δt ≤ 2/ω_max; ω_max ≤ c sqrt(Σ (2/h_i)²) for Q1 with a
    // lumped mass (the element eigenvalue bound), so Δt ≤ 1 / (c sqrt(Σ (1/h_i)²)).
    return 1 / std::sqrt(max_rate2);
  }

  template <int dim>
  void SnowpackModel<dim>::commit()
  {
    committed_ = trial_;
  }

  template <int dim>
  Energies SnowpackModel<dim>::energies() const
  {
    double elastic = 0, dissipated = 0;
    for (const CellData &data : cells_)
    {
      const double densification_modulus = layer_laws_[data.layer].parameters.densification_modulus;
      const CollapsedFrictionParameters &friction = layer_laws_[data.layer].friction;
      elastic += std::max(data.intact, cut_stiffness_floor) * cell_elastic_energy(data);
      for (unsigned int q = 0; q < quadrature_.size(); ++q)
      {
        const QuadraturePointState &state = committed_[data.first_qp + q];
        elastic += (state.lock_up_energy_density(densification_modulus) +
                    friction_energy_density(friction, state.friction_stress)) *
                   JxW_[data.first_qp + q];
      }
      for (unsigned int q = 0; q < quadrature_.size(); ++q)
        dissipated += committed_[data.first_qp + q].dissipation * JxW_[data.first_qp + q];
    }
    Energies energies;
    energies.elastic = Utilities::MPI::sum(elastic, communicator_);
    energies.dissipated = Utilities::MPI::sum(dissipated, communicator_);
    energies.removed_by_saw = removed_by_saw_;
    return energies;
  }

  template <int dim>
  double SnowpackModel<dim>::softening_of(const QuadraturePointState &state) const
  {
    const CamClayParameters &weak = layer_laws_[layer_weak].parameters;
    return (weak.p0_initial - state.material.p0) / std::max(weak.p0_initial - weak.p0_floor, 1e-300);
  }

  template <int dim>
  double SnowpackModel<dim>::weak_layer_softening() const
  {
    double sums[2] = {0, 0};
    for (const CellData &data : cells_)
      if (data.layer == layer_weak)
        for (unsigned int q = 0; q < quadrature_.size(); ++q)
        {
          sums[0] += softening_of(committed_[data.first_qp + q]);
          sums[1] += 1;
        }
    double total[2];
    Utilities::MPI::sum(ArrayView<const double>(sums, 2), communicator_, ArrayView<double>(total, 2));
    return total[0] / std::max(total[1], 1.);
  }

  template <int dim>
  Json SnowpackModel<dim>::locate_non_finite(const std::vector<const VectorType *> &vectors) const
  {
    Json found;
    for (unsigned int i = 0; i < partitioner_->locally_owned_size() && found.is_null(); ++i)
      for (const VectorType *vector : vectors)
        if (!std::isfinite(vector->local_element(i)))
        {
          std::map<types::global_dof_index, Point<dim>> points;
          DoFTools::map_dofs_to_support_points(MappingQ1<dim>(), dof_handler_, points);
          const types::global_dof_index dof = partitioner_->local_to_global(i);
          const Point<dim> &x = points.at(dof);
          unsigned int component = 0;
          for (unsigned int c = 0; c < dim; ++c)
          {
            ComponentMask mask(dim, false);
            mask.set(c, true);
            if (DoFTools::extract_dofs(dof_handler_, mask).is_element(dof))
              component = c;
          }
          const std::string &layer = layers_[layer_id_at(layer_tops(scene_.snowpack), x[dim - 1])].label;
          const unsigned int rank = Utilities::MPI::this_mpi_process(communicator_);
          std::ostringstream where;
          where << "node at (" << x << ") m (along the slope" << (dim == 3 ? ", across" : "")
                << ", normal), displacement component " << component << ", in the " << layer << " (rank " << rank
                << ")";
          found = {{"description", where.str()},
                   {"layer", layer},
                   {"node_m", std::vector<double>(x.begin_raw(), x.end_raw())},
                   {"component", component},
                   {"rank", rank}};
          break;
        }
    return first_failure_site_on_any_rank(found, communicator_);
  }

  template <int dim>
  CrackFronts SnowpackModel<dim>::crack_fronts(double failure_fraction) const
  {
    std::vector<int> failed(n_columns_, 0), locked(n_columns_, 0);
    // Per column: Σ h_e mean(−ε_nn) and Σ h_e / H over its weak-layer cells (the second counts the
    // cells across the width in 3D).
    std::vector<double> closure(n_columns_, 0.), across(n_columns_, 0.);
    const CamClayParameters &weak = layer_laws_[layer_weak].parameters;
    const double densification = weak.densification_strain, thickness = layers_[layer_weak].thickness;
    for (const CellData &data : cells_)
    {
      if (data.layer != layer_weak)
        continue;
      double softening = 0, compaction = 0;
      bool lock = false;
      for (unsigned int q = 0; q < quadrature_.size(); ++q)
      {
        const SymmetricTensor<2, 3> &strain = committed_[data.first_qp + q].material.strain;
        softening += softening_of(committed_[data.first_qp + q]);
        compaction -= strain[dim - 1][dim - 1];
        lock = lock || (densification > 0 && -trace(strain) > densification);
      }
      softening /= quadrature_.size();
      closure[data.column] += data.height * compaction / quadrature_.size();
      across[data.column] += data.height / thickness;
      if (data.intact < 0.5 || softening >= failure_fraction)
        failed[data.column] = 1;
      if (lock)
        locked[data.column] = 1;
    }
    Utilities::MPI::max(failed, communicator_, failed);
    Utilities::MPI::max(locked, communicator_, locked);
    Utilities::MPI::sum(closure, communicator_, closure);
    Utilities::MPI::sum(across, communicator_, across);
    const double column_length = scene_.pst.column_length / n_columns_;
    // Contiguous flagged columns counted from the cut end (or from the far end).
    auto front = [&](const std::vector<int> &flags, bool from_cut_end) {
      const bool upslope_first = (scene_.pst.cut_side == SawTest::CutSide::upslope) == from_cut_end;
      unsigned int k = 0;
      for (; k < n_columns_; ++k)
      {
        const unsigned int column = upslope_first ? k : n_columns_ - 1 - k;
        if (!flags[column])
          break;
      }
      return k * column_length;
    };
    CrackFronts fronts;
    fronts.crack_tip = front(failed, true);
    fronts.far_end_failed = front(failed, false);
    for (unsigned int k = 0; k < n_columns_; ++k)
    {
      const unsigned int column = scene_.pst.cut_side == SawTest::CutSide::upslope ? k : n_columns_ - 1 - k;
      if (locked[column])
        fronts.touchdown = (k + 1) * column_length;
    }
    fronts.failed_anywhere = std::any_of(failed.begin(), failed.end(), [](int f) { return f != 0; });
    double locked_sum = 0;
    unsigned int locked_count = 0;
    for (unsigned int column = 0; column < n_columns_; ++column)
    {
      const double c = across[column] > 0 ? closure[column] / across[column] : 0.;
      fronts.largest_closure = std::max(fronts.largest_closure, c);
      if (locked[column])
        locked_sum += c, ++locked_count;
    }
    fronts.locked_closure = locked_count > 0 ? locked_sum / locked_count : 0.;
    return fronts;
  }

  template <int dim>
  typename SnowpackModel<dim>::SlabTension SnowpackModel<dim>::slab_tension() const
  {
    // Per column and slab layer the sums Σ w, Σ w z, Σ w z², Σ w σ_xx, Σ w σ_xx z (w = JxW) of the
    // committed states; their least-squares line σ_xx ≈ a + b (z − z̄) gives the fibre stresses
    // a ± |b| h/2 at the layer's faces: the slab's stretching and bending, without the stress
    // concentrations at the column's corners that a pointwise σ_1 would pick up.
    constexpr unsigned int n_sums = 5;
    const unsigned int n_slab = layers_.size() - layer_first_slab;
    std::vector<double> sums(n_columns_ * n_slab * n_sums, 0.);
    for (const CellData &data : cells_)
    {
      if (data.layer < layer_first_slab)
        continue;
      double *column = &sums[(data.column * n_slab + data.layer - layer_first_slab) * n_sums];
      for (unsigned int q = 0; q < quadrature_.size(); ++q)
      {
        const double w = JxW_[data.first_qp + q], z = normal_coordinate_[data.first_qp + q],
                     sigma = committed_[data.first_qp + q].stress[0][0];
        column[0] += w, column[1] += w * z, column[2] += w * z * z, column[3] += w * sigma, column[4] += w * sigma * z;
      }
    }
    Utilities::MPI::sum(sums, communicator_, sums);
    SlabTension largest;
    const double column_length = scene_.pst.column_length / n_columns_;
    for (unsigned int c = 0; c < n_columns_; ++c)
      for (unsigned int l = 0; l < n_slab; ++l)
      {
        const double *m = &sums[(c * n_slab + l) * n_sums];
        const Layer &layer = layers_[layer_first_slab + l];
        if (!(m[0] > 0) || !(layer.tensile_strength > 0))
          continue;
        const double z_mean = m[1] / m[0], spread = m[2] - m[0] * z_mean * z_mean;
        const double mean = m[3] / m[0], slope = spread > 0 ? (m[4] - m[3] * z_mean) / spread : 0.;
        const double fibre = mean + std::abs(slope) * layer.thickness / 2;
        if (fibre / layer.tensile_strength > largest.ratio)
        {
          largest = {fibre / layer.tensile_strength, fibre, layer.tensile_strength, layer_first_slab + l, {}};
          largest.position[0] = (c + 0.5) * column_length;
          largest.position[dim - 1] = z_mean + (slope >= 0 ? 0.5 : -0.5) * layer.thickness;
        }
      }
    return largest;
  }

  template <int dim>
  void SnowpackModel<dim>::save(std::ostream &out) const
  {
    static_assert(std::is_trivially_copyable_v<QuadraturePointState>);
    checkpoint::write(out, cut_length_);
    checkpoint::write(out, removed_by_saw_);
    checkpoint::write_vector(out, committed_);
  }

  template <int dim>
  void SnowpackModel<dim>::load(std::istream &in)
  {
    double cut = 0, removed = 0;
    checkpoint::read(in, cut);
    checkpoint::read(in, removed);
    std::vector<QuadraturePointState> states;
    checkpoint::read_vector(in, states, committed_.size(), "quadrature-point states");
    committed_ = trial_ = states;
    set_cut(cut);
    removed_by_saw_ = removed;
  }

  template <int dim>
  std::vector<CellSummary<dim>> SnowpackModel<dim>::cell_summaries() const
  {
    std::vector<CellSummary<dim>> summaries;
    const unsigned int n_q = quadrature_.size();
    for (const CellData &data : cells_)
    {
      CellSummary<dim> summary;
      summary.center = data.cell->center();
      summary.layer = data.layer;
      summary.intact = data.intact;
      const double stress_factor = std::max(data.intact, cut_stiffness_floor);
      for (unsigned int q = 0; q < n_q; ++q)
      {
        const QuadraturePointState &state = committed_[data.first_qp + q];
        summary.stress += carried_stress(state, stress_factor) / n_q;
        summary.strain += state.strain / n_q;
        summary.p0 += state.material.p0 / n_q;
      }
      summaries.push_back(summary);
    }
    return summaries;
  }

  template <int dim>
  std::string SnowpackModel<dim>::write_fields(const VectorType &u, const std::string &directory,
                                               const std::string &stem, unsigned int index) const
  {
    const auto phase = timer_.scope("output");
    const unsigned int n_q = quadrature_.size();
    const unsigned int n_active = triangulation_.n_active_cells();
    enum Field
    {
      p, q, p0, plastic_volumetric, softening, intact, layer, sigma_xx, sigma_nn, sigma_xn, n_fields
    };
    const char *names[n_fields] = {"p",         "q",     "p0",       "plastic_volumetric_strain", "collapse_state",
                                   "intact",    "layer", "sigma_xx", "sigma_nn",                  "sigma_xn"};
    std::vector<Vector<double>> fields(n_fields, Vector<double>(n_active));
    for (const CellData &data : cells_)
    {
      const unsigned int c = data.cell->active_cell_index();
      const CamClayParameters &parameters = layer_laws_[data.layer].parameters;
      const bool plastic_model = layers_[data.layer].model == Layer::Model::cohesive_cam_clay;
      for (unsigned int k = 0; k < n_q; ++k)
      {
        const QuadraturePointState &state = committed_[data.first_qp + k];
        const SymmetricTensor<2, 3> stress = carried_stress(state, std::max(data.intact, cut_stiffness_floor));
        fields[p][c] += mean_pressure(stress) / n_q;
        fields[q][c] += von_mises(stress) / n_q;
        fields[p0][c] += (plastic_model ? state.material.p0 : 0) / n_q;
        fields[plastic_volumetric][c] += trace(state.material.plastic_strain) / n_q;
        if (plastic_model)
          fields[softening][c] += (parameters.p0_initial - state.material.p0) /
                                  std::max(parameters.p0_initial - parameters.p0_floor, 1e-300) / n_q;
        fields[sigma_xx][c] += stress[0][0] / n_q;
        fields[sigma_nn][c] += stress[dim - 1][dim - 1] / n_q;
        fields[sigma_xn][c] += stress[0][dim - 1] / n_q;
      }
      fields[intact][c] = data.intact;
      fields[layer][c] = data.layer;
    }

    DataOut<dim> data_out;
    data_out.attach_dof_handler(dof_handler_);
    const std::vector<DataComponentInterpretation::DataComponentInterpretation> vector_field(
      dim, DataComponentInterpretation::component_is_part_of_vector);
    data_out.add_data_vector(u, std::vector<std::string>(dim, "displacement"), DataOut<dim>::type_dof_data,
                             vector_field);
    for (unsigned int f = 0; f < n_fields; ++f)
      data_out.add_data_vector(fields[f], names[f], DataOut<dim>::type_cell_data);
    Vector<float> subdomain(n_active);
    subdomain = triangulation_.locally_owned_subdomain();
    data_out.add_data_vector(subdomain, "subdomain");
    data_out.build_patches(fe_.degree);
    return data_out.write_vtu_with_pvtu_record(directory + "/", stem, index, communicator_, 5);
  }

  template class SnowpackModel<2>;
  template class SnowpackModel<3>;
} // namespace anticrack::fem
