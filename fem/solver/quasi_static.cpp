// Newton's method on the snowpack model (see the header). Explicitly instantiated for dim = 2, 3.
#include "fem/solver/quasi_static.h"

#include <deal.II/base/mpi.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/petsc_precondition.h>
#include <deal.II/lac/petsc_solver.h>
#include <deal.II/lac/petsc_sparse_matrix.h>
#include <deal.II/lac/petsc_vector.h>
#include <deal.II/lac/solver_control.h>
#include <deal.II/lac/sparsity_tools.h>

#include <cmath>
#include <sstream>

namespace anticrack::fem
{
  using namespace dealii;

  template <int dim>
  struct QuasiStaticSolver<dim>::LinearAlgebra
  {
    PETScWrappers::MPI::SparseMatrix matrix;
    PETScWrappers::MPI::Vector rhs, solution;
    std::vector<types::global_dof_index> owned_indices;
    std::vector<PetscScalar> values;

    void to_petsc(const VectorType &in, PETScWrappers::MPI::Vector &out)
    {
      for (unsigned int k = 0; k < owned_indices.size(); ++k)
        values[k] = in.local_element(k);
      out.set(owned_indices, values);
      out.compress(VectorOperation::insert);
    }
    void from_petsc(const PETScWrappers::MPI::Vector &in, VectorType &out)
    {
      in.extract_subvector_to(owned_indices, values);
      for (unsigned int k = 0; k < owned_indices.size(); ++k)
        out.local_element(k) = values[k];
    }
  };

  template <int dim>
  QuasiStaticSolver<dim>::QuasiStaticSolver(SnowpackModel<dim> &model)
    : model_(model)
    , linear_algebra_(std::make_unique<LinearAlgebra>())
  {
    const MPI_Comm comm = model.communicator();
    DynamicSparsityPattern pattern(model.locally_relevant_dofs());
    DoFTools::make_sparsity_pattern(model.dof_handler(), pattern, model.constraints(), false);
    SparsityTools::distribute_sparsity_pattern(pattern, model.locally_owned_dofs(), comm,
                                               model.locally_relevant_dofs());
    LinearAlgebra &la = *linear_algebra_;
    la.matrix.reinit(model.locally_owned_dofs(), model.locally_owned_dofs(), pattern, comm);
    la.rhs.reinit(model.locally_owned_dofs(), comm);
    la.solution.reinit(model.locally_owned_dofs(), comm);
    for (const auto i : model.locally_owned_dofs())
      la.owned_indices.push_back(i);
    la.values.resize(la.owned_indices.size());
  }

  template <int dim>
  QuasiStaticSolver<dim>::~QuasiStaticSolver() = default;

  template <int dim>
  NewtonResult QuasiStaticSolver<dim>::solve(VectorType &u, double load_factor)
  {
    const Analysis &analysis = model_.scene().analysis;
    LinearAlgebra &la = *linear_algebra_;
    // Relative to the applied load once it exceeds the weight (the load to failure ramps beyond 1);
    // the weight itself below (the gravity ramp, whose early steps are small).
    const double reference = std::max(std::abs(load_factor), 1.) * std::max(model_.gravity_force().l2_norm(), 1e-300);
    VectorType internal_force, residual, trial_u, increment;
    model_.initialize_vector(internal_force);
    model_.initialize_vector(residual);
    model_.initialize_vector(trial_u);
    model_.initialize_vector(increment);
    NewtonResult result;

    // r(u) = λ f_g − f_int(u) (fixed dofs zero); returns |r| / |f_g|.
    auto residual_at = [&](const VectorType &displacement, typename SnowpackModel<dim>::Request request) {
      model_.evaluate(displacement, internal_force, request);
      residual = model_.gravity_force();
      residual.sadd(load_factor, -1., internal_force);
      return residual.l2_norm() / reference;
    };

    VectorType start = u;
    try
    {
      u.update_ghost_values();
      typename SnowpackModel<dim>::Request with_tangent;
      with_tangent.tangent = &la.matrix;
      la.matrix = 0;
      double norm = residual_at(u, with_tangent);
      for (result.iterations = 0;; ++result.iterations)
      {
        result.relative_residual = norm;
        if (!std::isfinite(norm))
        {
          result.failure = "the residual is not finite";
          // Collective: the norm is the same on every rank.
          result.failure_site = model_.locate_non_finite({&residual});
          if (!result.failure_site.is_null())
            result.failure += ": " + result.failure_site["description"].get<std::string>();
          break;
        }
        if (norm < analysis.newton_tolerance)
        {
          result.converged = true;
          break;
        }
        if (result.iterations == analysis.newton_max_iterations)
        {
          std::ostringstream message;
          message << "no convergence in " << result.iterations << " Newton iterations (|r|/|f| = " << norm << ")";
          result.failure = message.str();
          break;
        }
        // K δu = r with δu = 0 on the fixed base (the constrained rows hold the identity).
        la.to_petsc(residual, la.rhs);
        la.solution = 0;
        SolverControl control(2000, 1e-10 * la.rhs.l2_norm());
        try
        {
          const auto phase = model_.timer().scope("linear solves");
          if (analysis.linear_solver == Analysis::LinearSolver::direct)
          {
            PETScWrappers::SparseDirectMUMPS direct(control, model_.communicator());
            direct.solve(la.matrix, la.solution, la.rhs);
          }
          else
          {
            PETScWrappers::PreconditionBoomerAMG::AdditionalData data;
            data.symmetric_operator = false;
            PETScWrappers::PreconditionBoomerAMG amg(la.matrix, data);
            PETScWrappers::SolverGMRES gmres(control, model_.communicator());
            gmres.solve(la.matrix, la.solution, la.rhs, amg);
          }
        }
        catch (const dealii::ExceptionBase &e)
        {
          // GMRES out of iterations (SolverControl::NoConvergence), a PETSc or MUMPS error (a
          // singular or indefinite tangent): the step fails like a Newton that does not converge,
          // and the caller halves its load or saw step. Every rank gets the same PETSc error.
          std::ostringstream message;
          message << "the linear solver failed in Newton iteration " << result.iterations << " (|r|/|f| = " << norm
                  << "): " << e.get_exc_name();
          result.failure = message.str();
          break;
        }
        la.from_petsc(la.solution, increment);
        model_.zero_fixed(increment);
        model_.distribute_constraints(increment);
        ++total_iterations_;

        // Backtracking line search on |r| (Armijo-like sufficient decrease, step-42).
        double step = 1, trial_norm = 0;
        bool accepted = false;
        typename SnowpackModel<dim>::Request force_only;
        for (unsigned int k = 0; k < 8 && !accepted; ++k, step /= 2)
        {
          trial_u = u;
          trial_u.add(step, increment);
          trial_u.update_ghost_values();
          try
          {
            trial_norm = residual_at(trial_u, force_only);
          }
          catch (const ReturnMappingError &)
          {
            trial_norm = std::numeric_limits<double>::infinity();
          }
          accepted = trial_norm < (1 - 1e-4 * step) * norm;
        }
        if (!accepted)
        {
          // No step down to 1/128 of Newton's decreases |r| enough: refused, not taken.
          std::ostringstream message;
          message << "the line search found no acceptable step in Newton iteration " << result.iterations
                  << " (|r|/|f| = " << norm << ", " << trial_norm << " at the smallest step " << 2 * step << ")";
          result.failure = message.str();
          break;
        }
        u = trial_u;
        u.update_ghost_values();
        la.matrix = 0;
        norm = residual_at(u, with_tangent);
      }
    }
    catch (const ReturnMappingError &e)
    {
      result.converged = false;
      result.failure = e.what();
      result.failure_site = failure_site_of(e);
    }
    if (!result.converged && result.failure_site.is_null())
      result.failure_site = failure_site(result.failure);
    else if (!result.converged)
      result.failure_site["description"] = result.failure;
    if (result.converged)
      model_.commit();
    else
    {
      u = start;
      u.update_ghost_values();
    }
    return result;
  }

  template <int dim>
  void QuasiStaticSolver<dim>::apply_gravity(VectorType &u, unsigned int initial_steps,
                                             const std::function<void(double, const NewtonResult &)> &progress)
  {
    double load = 0, step = 1. / initial_steps;
    constexpr double smallest_step = 1e-4;
    while (load < 1 - 1e-12)
    {
      step = std::min(step, 1 - load);
      const NewtonResult result = solve(u, load + step);
      if (!result.converged)
      {
        if (step <= smallest_step)
        {
          std::ostringstream message;
          message << "the gravity ramp failed at load factor " << load + step << " with the smallest step "
                  << step << ": " << result.failure;
          throw GravityRampFailure(message.str(), load + step, result.failure_site);
        }
        step /= 2;
        continue;
      }
      load += step;
      if (progress)
        progress(load, result);
      if (result.iterations <= 4)
        step *= 2;
    }
  }

  template class QuasiStaticSolver<2>;
  template class QuasiStaticSolver<3>;
} // namespace anticrack::fem
