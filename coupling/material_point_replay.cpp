#include "coupling/material_point_replay.h"

#include "fem/material/cohesive_cam_clay.h"
#include "fem/scene/crack_band.h"

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <stdexcept>

namespace anticrack::coupling
{
  namespace
  {
    using Tensor = dealii::SymmetricTensor<2, 3>;

    /// The six independent components of a symmetric tensor, as (i, j).
    constexpr std::array<std::array<unsigned int, 2>, 6> components = {
      {{0, 0}, {1, 1}, {2, 2}, {0, 1}, {0, 2}, {1, 2}}};

    /// The FE material point of the calibrated specimen: the file's material as the solver builds it
    /// (crack band of the specimen's own thickness, so ξ is the file's; no lock-up).
    fem::CamClayParameters specimen_point(const fem::ContinuumMaterial &material)
    {
      fem::Layer layer;
      layer.model = fem::Layer::Model::cohesive_cam_clay;
      layer.material = material;
      layer.thickness = material.reference_thickness;
      return fem::cam_clay_parameters(layer, material.reference_thickness);
    }

    /// The strain that holds the layer-plane traction σ_zz = −σ̂, σ_xz = τ̂ (unit load) under the
    /// lateral condition, from the material's elastic tangent (the point is elastic until it yields,
    /// and its elasticity is linear, so the strain of load λ is λ times this).
    /// The mixed control of the path: the stress-controlled components (the layer-plane traction
    /// zz, xz, yz, and under open sides the lateral ones xx, yy, xy too; the others are
    /// strain-controlled at zero), their targets for the unit load (σ_zz = −σ̂, σ_xz = τ̂), and the
    /// Jacobian of those stresses in those strains from a tangent.
    struct PathControl
    {
      std::vector<unsigned int> controlled;
      Eigen::VectorXd unit_target;

      PathControl(bool confined, double sigma_hat, double tau_hat)
        : controlled(confined ? std::vector<unsigned int>{2, 4, 5} : std::vector<unsigned int>{0, 1, 2, 3, 4, 5})
        , unit_target(Eigen::VectorXd::Zero(static_cast<Eigen::Index>(controlled.size())))
      {
        for (std::size_t a = 0; a < controlled.size(); ++a)
        {
          const auto [i, j] = components[controlled[a]];
          if (i == 2 && j == 2)
            unit_target(static_cast<Eigen::Index>(a)) = -sigma_hat;
          else if (i == 0 && j == 2)
            unit_target(static_cast<Eigen::Index>(a)) = tau_hat;
        }
      }

      [[nodiscard]] Eigen::Index size() const { return static_cast<Eigen::Index>(controlled.size()); }

      [[nodiscard]] Eigen::MatrixXd jacobian(const dealii::SymmetricTensor<4, 3> &C) const
      {
        Eigen::MatrixXd J(size(), size());
        for (Eigen::Index a = 0; a < size(); ++a)
        {
          const auto [i, j] = components[controlled[static_cast<std::size_t>(a)]];
          for (Eigen::Index b = 0; b < size(); ++b)
          {
            const auto [k, l] = components[controlled[static_cast<std::size_t>(b)]];
            // ε_kl and ε_lk are one unknown: an off-diagonal strain enters twice.
            J(a, b) = C[i][j][k][l] * (k == l ? 1.0 : 2.0);
          }
        }
        return J;
      }

      [[nodiscard]] Eigen::VectorXd stresses(const Tensor &stress) const
      {
        Eigen::VectorXd s(size());
        for (Eigen::Index a = 0; a < size(); ++a)
        {
          const auto [i, j] = components[controlled[static_cast<std::size_t>(a)]];
          s(a) = stress[i][j];
        }
        return s;
      }

      void add_to_strain(const Eigen::VectorXd &x, Tensor &strain) const
      {
        for (Eigen::Index b = 0; b < size(); ++b)
        {
          const auto [k, l] = components[controlled[static_cast<std::size_t>(b)]];
          strain[k][l] += x(b);
        }
      }
    };

    Tensor unit_load_strain(const fem::CamClayParameters &parameters, bool confined, double sigma_hat, double tau_hat)
    {
      const fem::CamClayState initial = fem::CamClayState::initial(parameters);
      const PathControl control(confined, sigma_hat, tau_hat);
      const dealii::SymmetricTensor<4, 3> C = fem::update_stress_and_tangent(parameters, initial, Tensor()).tangent;
      Tensor strain;
      control.add_to_strain(control.jacobian(C).fullPivLu().solve(control.unit_target), strain);
      return strain;
    }

    struct Failure
    {
      double load = 0;           ///< λ_f [Pa]
      Tensor stress;             ///< at λ_f
    };

    /// The largest load factor at which the point is still elastic along `unit_strain`, searched
    /// from `dem_load` / 32 upwards (the DEM's failure load on this ray).
    Failure failure_load(const fem::CamClayParameters &parameters, const Tensor &unit_strain, double dem_load)
    {
      const fem::CamClayState initial = fem::CamClayState::initial(parameters);
      const auto yields = [&](double load) { return fem::update_stress(parameters, initial, load * unit_strain).plastic; };
      double low = 0, high = dem_load / 32;
      while (!yields(high))
      {
        if (high > 1e3 * dem_load)
          throw std::runtime_error("the FE material point does not yield below 1e3 times the DEM's failure stress");
        low = high, high *= 2;
      }
      while (high - low > 1e-12 * high)
      {
        const double mid = 0.5 * (low + high);
        (yields(mid) ? high : low) = mid;
      }
      return {low, fem::update_stress(parameters, initial, low * unit_strain).stress};
    }

    /// The peak of the load the point carries along the ray past its first yield `yield`: load
    /// steps of the controlled stresses, each solved by Newton on the controlled strains with the
    /// point's consistent tangent from the last converged state; steps of 1e-3 of the first yield's
    /// load (the same sequence for every surface, so that the peak is a smooth function of the
    /// parameters: the calibration iterates on it), halved from the first that does not converge;
    /// the peak is the last converged load once the step is below 1e-10 of it. Under the collapse law every plastic volume change softens, yet the
    /// stress point can slide along the shrinking surface to a larger load (confined compression of
    /// a low-M surface: coupling/material_point_replay.h).
    constexpr double largest_step = 1e-3;

    Failure peak_load(const fem::CamClayParameters &parameters, bool confined, double sigma_hat, double tau_hat,
                      const Failure &yield, const Tensor &unit_strain)
    {
      const PathControl control(confined, sigma_hat, tau_hat);
      Tensor strain = yield.load * unit_strain;
      fem::CamClayState state = fem::update_stress(parameters, fem::CamClayState::initial(parameters), strain).state;
      Failure peak = yield;
      double step = largest_step * yield.load;
      while (step > 1e-10 * peak.load)
      {
        if (peak.load > 100 * yield.load)
          throw std::runtime_error("the FE material point carries more than 100 times its first-yield load on a path");
        const double load = peak.load + step;
        Tensor trial = strain;
        bool converged = false;
        fem::CamClayUpdate update;
        try
        {
          for (unsigned int iteration = 0; iteration < 30 && !converged; ++iteration)
          {
            const fem::CamClayTangentUpdate u = fem::update_stress_and_tangent(parameters, state, trial);
            update = u.update;
            const Eigen::VectorXd residual = control.stresses(u.update.stress) - load * control.unit_target;
            converged = residual.norm() <= 1e-10 * load;
            if (!converged)
              control.add_to_strain(-control.jacobian(u.tangent).fullPivLu().solve(residual), trial);
          }
        }
        catch (const fem::ReturnMappingError &)
        {
          converged = false;
        }
        if (!converged || !std::isfinite(update.stress.norm()))
        {
          step /= 2;
          continue;
        }
        strain = trial;
        state = update.state;
        peak = {load, update.stress};
      }
      return peak;
    }

    /// A test's ray: its first yield and its peak (the FE point's failure).
    struct RayFailure
    {
      Failure first_yield, peak;
    };

    RayFailure replay_ray(const fem::CamClayParameters &parameters, bool confined, double sigma, double tau)
    {
      const double r = std::hypot(sigma, tau);
      const Tensor unit_strain = unit_load_strain(parameters, confined, sigma / r, tau / r);
      const Failure yield = failure_load(parameters, unit_strain, r);
      return {yield, peak_load(parameters, confined, sigma / r, tau / r, yield, unit_strain)};
    }
  } // namespace

  double MaterialPointReplay::largest_angle_error() const
  {
    double largest = 0;
    for (const ReplayedAngle &a : angles)
      largest = std::max(largest, std::abs(a.relative_error));
    return largest;
  }

  MaterialPointReplay replay_tests(const params::MicrostructureCalibration &c, const fem::ContinuumMaterial &material)
  {
    const fem::CamClayParameters parameters = specimen_point(material);
    MaterialPointReplay replay;
    replay.laterally_confined = c.path.laterally_confined;
    replay.fit_rmse = c.material_plane().cam_clay().rmse;

    std::map<double, std::vector<const params::CampaignTest *>> by_angle;
    for (const params::CampaignTest &t : c.tests)
    {
      by_angle[std::round(t.loading_angle_deg * 1e6) / 1e6].push_back(&t);
      const RayFailure f = replay_ray(parameters, replay.laterally_confined, t.sigma, std::abs(t.tau));
      replay.test_errors.push_back(std::log(f.peak.load / std::hypot(t.sigma, t.tau)));
      replay.peak_over_first_yield[t.id] = f.peak.load / f.first_yield.load;
    }
    for (const auto &[angle, tests] : by_angle)
    {
      ReplayedAngle a;
      a.loading_angle_deg = angle;
      a.tests = static_cast<int>(tests.size());
      for (const params::CampaignTest *t : tests)
        a.dem_sigma += t->sigma / a.tests, a.dem_tau += std::abs(t->tau) / a.tests;
      const RayFailure ray = replay_ray(parameters, replay.laterally_confined, a.dem_sigma, a.dem_tau);
      const Failure &f = ray.peak;
      a.peak_over_first_yield = ray.peak.load / ray.first_yield.load;
      const double r = std::hypot(a.dem_sigma, a.dem_tau);
      a.fe_sigma = -f.stress[2][2];
      a.fe_tau = f.stress[0][2];
      const auto lateral_ratio = [](const Failure &at) {
        return std::abs(at.stress[2][2]) > 1e-9 * at.load ? at.stress[0][0] / at.stress[2][2] : 0.0;
      };
      a.fe_lateral_stress_ratio = lateral_ratio(ray.first_yield);
      a.fe_lateral_stress_ratio_at_peak = lateral_ratio(ray.peak);
      a.relative_error = std::log(f.load / r);
      replay.angles.push_back(a);
    }
    replay.dem_normal_stiffness = c.elastic.axial_modulus.mean;
    replay.dem_shear_stiffness = c.elastic.shear_modulus.mean;
    replay.fe_normal_stiffness = 1.0 / -unit_load_strain(parameters, replay.laterally_confined, 1, 0)[2][2];
    replay.fe_shear_stiffness = 1.0 / (2.0 * unit_load_strain(parameters, replay.laterally_confined, 0, 1)[0][2]);
    return replay;
  }

  nlohmann::ordered_json replay_json(const MaterialPointReplay &replay)
  {
    using Json = nlohmann::ordered_json;
    Json angles = Json::array();
    for (const ReplayedAngle &a : replay.angles)
      angles.push_back(Json{{"loading_angle_deg", a.loading_angle_deg},
                            {"tests", a.tests},
                            {"dem_sigma_Pa", a.dem_sigma},
                            {"dem_tau_Pa", a.dem_tau},
                            {"fe_sigma_Pa", a.fe_sigma},
                            {"fe_tau_Pa", a.fe_tau},
                            {"fe_lateral_stress_ratio", a.fe_lateral_stress_ratio},
                            {"fe_lateral_stress_ratio_at_peak", a.fe_lateral_stress_ratio_at_peak},
                            {"fe_peak_over_first_yield", a.peak_over_first_yield},
                            {"relative_error", a.relative_error}});
    return Json{{"what", "the DEM tests repeated by the FE material point of the material file, along each "
                         "test's path to the peak of its load (coupling/material_point_replay.h); errors "
                         "ln(r_FE/r_DEM)"},
                {"laterally_confined", replay.laterally_confined},
                {"fit_relative_rmse", replay.fit_rmse},
                {"largest_angle_error", replay.largest_angle_error()},
                {"angles", angles},
                {"test_errors", replay.test_errors},
                {"normal_stiffness_Pa", Json{{"dem", replay.dem_normal_stiffness}, {"fe", replay.fe_normal_stiffness}}},
                {"shear_stiffness_Pa", Json{{"dem", replay.dem_shear_stiffness}, {"fe", replay.fe_shear_stiffness}}}};
  }
} // namespace anticrack::coupling
