// Central differences on the snowpack model (see the header). Explicitly instantiated for 2, 3.
#include "fem/solver/explicit_dynamics.h"

#include "fem/model/checkpoint.h"

#include <deal.II/base/mpi.h>

#include <cmath>
#include <limits>

namespace anticrack::fem
{
  using namespace dealii;

  template <int dim>
  ExplicitDynamics<dim>::ExplicitDynamics(SnowpackModel<dim> &model, const VectorType &u0,
                                          double initial_external_work)
    : ExplicitDynamics(model, u0, initial_external_work, true)
  {
    restart_at_rest(u0, initial_external_work);
  }

  template <int dim>
  void ExplicitDynamics<dim>::restart_at_rest(const VectorType &u, double external_work)
  {
    u_ = u;
    v_ = 0;
    kinetic_ = 0;
    external_work_ = external_work;
    from_rest_ = true;
    u_.update_ghost_values();
    v_.update_ghost_values();
    typename SnowpackModel<dim>::Request request;
    request.velocity = &v_;
    stable_dt_ = model_.evaluate(u_, internal_force_, request);
    dt_ = model_.scene().analysis.cfl_safety * stable_dt_; // the first step's, reported before it
    model_.commit();
  }

  template <int dim>
  ExplicitDynamics<dim>::ExplicitDynamics(SnowpackModel<dim> &model, const VectorType &u0,
                                          double initial_external_work, bool)
    : model_(model)
    , external_work_(initial_external_work)
  {
    model.initialize_vector(u_);
    model.initialize_vector(v_);
    model.initialize_vector(internal_force_);
    u_ = u0;
  }

  template <int dim>
  void ExplicitDynamics<dim>::step()
  {
    const Analysis &analysis = model_.scene().analysis;
    const VectorType &mass = model_.lumped_mass();
    const VectorType &gravity = model_.gravity_force();
    const bool first = from_rest_;
    from_rest_ = false;
    const double previous_dt = dt_;
    dt_ = analysis.cfl_safety * stable_dt_;
    // Central differences with a variable step: the velocity lives at the half steps, so the
    // acceleration at t_n moves it over ½ (Δt_{n−1} + Δt_n) (Belytschko et al. 2014, ch. 6);
    // from rest the first half step is Δt_0 / 2.
    const double velocity_step = first ? dt_ / 2 : (previous_dt + dt_) / 2;
    const unsigned int n = mass.locally_owned_size();

    // v_{n+½} = v_{n−½} + Δt M⁻¹ (f_g − f_int − α_M M v), then u_{n+1} = u_n + Δt v_{n+½}.
    double damping_power = 0, external_power = 0, kinetic = 0;
    for (unsigned int i = 0; i < n; ++i)
    {
      if (model_.is_fixed(i) || model_.is_tied(i))
        continue;
      const double m = mass.local_element(i);
      double &v = v_.local_element(i);
      // A non-finite force or velocity poisons the summed power below (and so external_work_),
      // which step_finite() checks on every rank after the step.
      if (!std::isfinite(internal_force_.local_element(i)) || !std::isfinite(v))
        external_power = std::numeric_limits<double>::quiet_NaN();
      const double damping = analysis.mass_damping * m * v;
      damping_power += damping * v;
      v += velocity_step * (gravity.local_element(i) - internal_force_.local_element(i) - damping) / m;
      u_.local_element(i) += dt_ * v;
      external_power += gravity.local_element(i) * v;
      kinetic += 0.5 * m * v * v;
    }
    model_.distribute_constraints(u_); // the tied dofs follow their masters
    model_.distribute_constraints(v_);
    u_.update_ghost_values();
    v_.update_ghost_values();
    external_work_ += dt_ * Utilities::MPI::sum(external_power, model_.communicator());
    viscous_work_ += velocity_step * Utilities::MPI::sum(damping_power, model_.communicator());
    kinetic_ = Utilities::MPI::sum(kinetic, model_.communicator());

    typename SnowpackModel<dim>::Request request;
    request.velocity = &v_;
    stable_dt_ = model_.evaluate(u_, internal_force_, request);
    viscous_work_ += dt_ * model_.last_viscous_power();
    model_.commit();
    time_ += dt_;
    ++steps_;
  }

  template <int dim>
  void ExplicitDynamics<dim>::refresh_internal_force()
  {
    typename SnowpackModel<dim>::Request request;
    request.velocity = &v_;
    stable_dt_ = model_.evaluate(u_, internal_force_, request);
    model_.commit();
  }

  template <int dim>
  Energies ExplicitDynamics<dim>::energies() const
  {
    Energies energies = model_.energies();
    energies.kinetic = kinetic_;
    energies.viscous = viscous_work_;
    energies.external_work = external_work_;
    return energies;
  }

  template <int dim>
  void ExplicitDynamics<dim>::save(std::ostream &out) const
  {
    for (const double value : {time_, dt_, stable_dt_, external_work_, viscous_work_, kinetic_})
      checkpoint::write(out, value);
    checkpoint::write(out, std::uint64_t(steps_));
    checkpoint::write(out, std::uint64_t(from_rest_));
    for (const VectorType *vector : {&u_, &v_, &internal_force_})
      checkpoint::write_vector(out, std::vector<double>(vector->begin(), vector->end()));
  }

  template <int dim>
  void ExplicitDynamics<dim>::load(std::istream &in)
  {
    for (double *value : {&time_, &dt_, &stable_dt_, &external_work_, &viscous_work_, &kinetic_})
      checkpoint::read(in, *value);
    std::uint64_t steps = 0;
    checkpoint::read(in, steps);
    steps_ = steps;
    checkpoint::read(in, steps);
    from_rest_ = steps != 0;
    std::vector<double> values;
    for (VectorType *vector : {&u_, &v_, &internal_force_})
    {
      checkpoint::read_vector(in, values, vector->locally_owned_size(), "displacement, velocity, force");
      std::copy(values.begin(), values.end(), vector->begin());
    }
    u_.update_ghost_values();
    v_.update_ghost_values();
  }

  template <int dim>
  bool ExplicitDynamics<dim>::finite() const
  {
    bool ok = true;
    for (unsigned int i = 0; i < u_.locally_owned_size() && ok; ++i)
      ok = std::isfinite(u_.local_element(i)) && std::isfinite(v_.local_element(i));
    return !Utilities::MPI::logical_or(!ok, model_.communicator());
  }

  template <int dim>
  double ExplicitDynamics<dim>::max_displacement() const
  {
    return u_.linfty_norm();
  }

  template class ExplicitDynamics<2>;
  template class ExplicitDynamics<3>;
} // namespace anticrack::fem
