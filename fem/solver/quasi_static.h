// Quasi-static equilibrium of the snowpack model: Newton's method with the consistent tangent and a
// backtracking line search (step-42's globalisation), PETSc linear solvers (MUMPS, or GMRES with
// BoomerAMG), and load steps that adapt (halve on failure, grow after easy convergence).
#pragma once

#include <stdexcept>

#include "fem/model/snowpack_model.h"

#include <functional>
#include <memory>
#include <string>

namespace anticrack::fem
{
  /// Outcome of one equilibrium solve.
  struct NewtonResult
  {
    bool converged = false;
    unsigned int iterations = 0;
    double relative_residual = 0; ///< |r| / (max(|λ|, 1) |f_gravity|) at the end
    std::string failure;          ///< why it did not converge (empty when it did)
    Json failure_site;            ///< where (fem/model/failure_site.h), null when it converged
  };

  /// The gravity ramp could not be continued: Newton failed at `load_factor` even with the
  /// smallest load step. The message names the load factor and Newton's reason.
  class GravityRampFailure : public std::runtime_error
  {
  public:
    GravityRampFailure(const std::string &message, double load_factor, Json site)
      : std::runtime_error(message)
      , load_factor(load_factor)
      , site(std::move(site))
    {}
    double load_factor;
    Json site; ///< where Newton failed (NewtonResult::failure_site)
  };

  template <int dim>
  class QuasiStaticSolver
  {
  public:
    using VectorType = typename SnowpackModel<dim>::VectorType;

    explicit QuasiStaticSolver(SnowpackModel<dim> &model);
    ~QuasiStaticSolver();

    /// Equilibrium at `load_factor` · gravity starting from u (ghosted, updated in place). On
    /// success the model's states are committed; on failure u and the committed states are left as
    /// they were (the trial states are discarded).
    NewtonResult solve(VectorType &u, double load_factor);

    /// Ramps gravity from 0 to 1 in adaptive steps (at least `initial_steps`); u starts at zero.
    /// Throws GravityRampFailure naming the load factor when a step cannot be made smaller than
    /// 1e-4 and still fails. `progress` is called after every converged step.
    void apply_gravity(VectorType &u, unsigned int initial_steps,
                       const std::function<void(double load_factor, const NewtonResult &)> &progress = {});

    /// Total Newton iterations and linear solves so far.
    unsigned int total_iterations() const { return total_iterations_; }

  private:
    struct LinearAlgebra;
    SnowpackModel<dim> &model_;
    std::unique_ptr<LinearAlgebra> linear_algebra_;
    unsigned int total_iterations_ = 0;
  };
} // namespace anticrack::fem
