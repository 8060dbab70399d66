// Explicit dynamics of the snowpack model: central differences (leapfrog: velocities at half
// steps) with the lumped Gauss–Lobatto mass (step-48), the CFL step re-evaluated every step from
// the current moduli (the lock-up of a collapsed layer stiffens it), bulk viscosity (in the model's
// constitutive loop) and optional mass-proportional damping.
//
//   a_n = M⁻¹ (λ f_g − f_int(u_n, v_{n−½}) − α_M M v_{n−½})
//   v_{n+½} = v_{n−½} + ½ (Δt_{n−1} + Δt_n) a_n   (centred; the first step uses Δt_0/2 from v_0)
//   u_{n+1} = u_n + Δt_n v_{n+½}
//
// Energy bookkeeping: external work f_g · Δu; kinetic ½ v·M v at half steps; viscous work of the
// bulk viscosity and the damping; elastic, plastic and saw-removed energies from the model. The
// balance error |W_ext − (E_el + E_kin + D + D_visc + E_saw)| / max(W_ext, E_el) is reported.
#pragma once

#include "fem/model/snowpack_model.h"

#include <cmath>

namespace anticrack::fem
{
  template <int dim>
  class ExplicitDynamics
  {
  public:
    using VectorType = typename SnowpackModel<dim>::VectorType;

    /// Starts from displacement u0 (e.g. the gravity equilibrium, whose states the model holds
    /// committed) at rest. The energies start at the model's elastic and dissipated energies, and
    /// the external work at the work done to reach u0 (−Π bookkeeping: the quasi-static ramp's work
    /// f_g·u0 minus nothing dissipated dynamically), so that the balance holds from t = 0.
    ExplicitDynamics(SnowpackModel<dim> &model, const VectorType &u0, double initial_external_work);

    /// An integrator whose state load() sets (resuming from a checkpoint): nothing is evaluated.
    ExplicitDynamics(SnowpackModel<dim> &model, const VectorType &u0, double initial_external_work, bool for_load);

    /// One step. The model throws ReturnMappingError when a return mapping fails. A non-finite
    /// force, velocity or step makes the step's summed powers non-finite: step_finite() says so
    /// after every step at no extra communication; finite() checks the fields themselves.
    void step();

    /// Continues from displacement u at rest, at the current time and step count: the quasi-static
    /// saw hands back to the explicit integrator after static saw steps. The energy ledger restarts
    /// with `external_work` (the work done to reach u, as in the constructor); the viscous work so
    /// far is kept.
    void restart_at_rest(const VectorType &u, double external_work);

    /// Re-evaluates the internal force at the current state, after the model changed (a cut).
    void refresh_internal_force();

    double time() const { return time_; }
    unsigned long steps() const { return steps_; }
    double time_step() const { return dt_; }
    const VectorType &displacement() const { return u_; }
    const VectorType &velocity() const { return v_; }

    /// Energies: the model's plus kinetic, viscous (bulk viscosity and damping) and external work.
    Energies energies() const;

    /// Writes / reads the integrator of this rank (time, step, the vectors, the energy ledger); the
    /// model's history is saved separately (SnowpackModel::save). A resumed run continues the same
    /// steps bit for bit.
    void save(std::ostream &out) const;
    void load(std::istream &in);

    /// True when every displacement and velocity is finite (over all ranks).
    bool finite() const;
    /// Where the first non-finite displacement, velocity or force lies (SnowpackModel::
    /// locate_non_finite(); collective).
    Json non_finite_location() const { return model_.locate_non_finite({&u_, &v_, &internal_force_}); }
    /// True when the last step's force, velocity, kinetic energy, external work and next step are
    /// finite on every rank (from the step's own reductions).
    bool step_finite() const
    {
      return std::isfinite(kinetic_) && std::isfinite(external_work_) && std::isfinite(viscous_work_) &&
             std::isfinite(stable_dt_);
    }

    /// Largest displacement magnitude (over all ranks) [m].
    double max_displacement() const;

  private:
    SnowpackModel<dim> &model_;
    VectorType u_, v_, internal_force_;
    double time_ = 0, dt_ = 0, stable_dt_ = 0;
    unsigned long steps_ = 0;
    bool from_rest_ = true; ///< the next step starts from rest (a half step for the velocity)
    double external_work_ = 0, viscous_work_ = 0, kinetic_ = 0;
  };
} // namespace anticrack::fem
