// Tests of one weak-layer point in the DEM's simple shear at constant normal stress
// (fem/material/point_simple_shear.h), against closed forms:
//  * an elastic point: compaction σ_n / (K + 4G/3) and τ = G γ (Hooke's law in uniaxial strain);
//  * a cohesive Cam-Clay point with friction, sheared at 30 % of its layer-plane compressive
//    strength: it stays elastic (τ = G γ) up to the layer-plane shear strength of its surface,
//    τ_p of Eq. P2 (docs/physics.md §2) at the confined lateral ratio ν/(1 − ν), and once it has
//    failed and slides its shear is Coulomb's μ σ_n (collapsed_layer_friction.h, F1);
//  * a point consolidated beyond its compressive strength collapses onto its lock-up: the
//    normal strain passes ε_d and the normal stress is carried, as the DEM's consolidation does;
//  * against the DEM (data/dem_simple_shear/): the calibrated weak layer repeats the DEM's intact
//    simple shear at 2 and 5 kPa, its peak and how fast it loses its cohesion after it.
//
// Units: the weak layer of cam_clay_test_support.h (K = 0.5 MPa, G = 0.3 MPa, p0 = 1 kPa, collapse
// law, floor 0.2 p0, lock-up at ε_d = 0.2 with K_d = 1 MPa) with μ = 0.4.
#include "cam_clay_test_support.h"
#include "fem/material/material_file.h"
#include "fem/material/point_simple_shear.h"
#include "fem/scene/crack_band.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace
{
  using namespace anticrack::fem;
  using test_support::weak_layer;

  constexpr double mu = 0.4;

  /// ν/(1 − ν) of the layer: the lateral stress ratio of uniaxial strain.
  double confined_ratio(const CamClayParameters &m)
  {
    const double nu = (3 * m.bulk_modulus - 2 * m.shear_modulus) / (2 * (3 * m.bulk_modulus + m.shear_modulus));
    return nu / (1 - nu);
  }

  TEST(PointSimpleShear, ElasticPointFollowsHookesLawInUniaxialStrain)
  {
    const LayerLaw law = LayerLaw::elastic(1e6, 0.25);
    const double K = law.parameters.bulk_modulus, G = law.parameters.shear_modulus;
    const auto samples = point_simple_shear(law, {2e3, 0.01, 10, 100});
    ASSERT_EQ(samples.size(), 110u);
    for (std::size_t k = 10; k < samples.size(); ++k) // the shear stage
    {
      const PointSimpleShearSample &s = samples[k];
      EXPECT_NEAR(s.normal_stress, 2e3, 1e-9 * 2e3);
      EXPECT_NEAR(s.shear_stress, G * s.shear_strain, 1e-9 * G * 0.01);
      EXPECT_FALSE(s.failed);
    }
    EXPECT_NEAR(samples.back().normal_strain, 2e3 / (K + 4 * G / 3), 1e-9 * 2e3 / (K + 4 * G / 3));
  }

  TEST(PointSimpleShear, FailedPointSlidesAtCoulombsLimit)
  {
    const CamClayParameters m = weak_layer();
    const LayerLaw law = LayerLaw::cohesive_cam_clay(m, mu);
    const double strength = layer_plane_compressive_strength(confined_ratio(m), m.p0_initial, m);
    const double sigma_n = 0.3 * strength;
    const double peak = layer_plane_shear_strength(sigma_n, confined_ratio(m), m.p0_initial, m);
    ASSERT_GT(peak, mu * sigma_n); // the drop at failure is a real one
    const double gamma_peak = peak / m.shear_modulus;
    const unsigned int steps = 4000;
    const auto samples = point_simple_shear(law, {sigma_n, 40 * gamma_peak, 50, steps});

    // Elastic to the surface: τ = G γ while the point is intact, and the largest shear is τ_p
    // within one step's stress increment.
    double largest = 0;
    bool failed = false;
    for (std::size_t k = 50; k < samples.size(); ++k) // the shear stage
    {
      const PointSimpleShearSample &s = samples[k];
      EXPECT_NEAR(s.normal_stress, sigma_n, 1e-8 * sigma_n);
      largest = std::max(largest, s.shear_stress);
      if (!failed && !s.failed && s.shear_stress < peak * (1 - 1e-9) && s.p0 == m.p0_initial)
      {
        EXPECT_NEAR(s.shear_stress, m.shear_modulus * s.shear_strain, 1e-9 * peak);
      }
      failed = failed || s.failed;
    }
    EXPECT_TRUE(failed);
    const double step_stress = m.shear_modulus * 40 * gamma_peak / steps;
    EXPECT_NEAR(largest, peak, step_stress + 1e-9 * peak);
    // Sliding at the end: Coulomb's limit on the carried normal stress.
    EXPECT_NEAR(samples.back().shear_stress, mu * sigma_n, 1e-9 * sigma_n);
  }

  TEST(PointSimpleShear, ConsolidationBeyondTheStrengthCollapsesOntoTheLockUp)
  {
    const CamClayParameters m = weak_layer();
    const LayerLaw law = LayerLaw::cohesive_cam_clay(m, mu);
    const double strength = layer_plane_compressive_strength(confined_ratio(m), m.p0_initial, m);
    const auto samples = point_simple_shear(law, {3 * strength, 0.01, 200, 10});
    const PointSimpleShearSample &consolidated = samples[199];
    EXPECT_EQ(consolidated.shear_strain, 0);
    EXPECT_NEAR(consolidated.normal_stress, 3 * strength, 1e-8 * strength);
    EXPECT_GT(consolidated.normal_strain, m.densification_strain);
    EXPECT_LE(consolidated.p0, m.p0_floor * (1 + 1e-9));
  }

  TEST(PointSimpleShear, RefusesSettingsOutOfRange)
  {
    const LayerLaw law = LayerLaw::elastic(1e6, 0.25);
    EXPECT_THROW(point_simple_shear(law, {0, 0.1, 10, 10}), std::invalid_argument);
    EXPECT_THROW(point_simple_shear(law, {1e3, -0.1, 10, 10}), std::invalid_argument);
    EXPECT_THROW(point_simple_shear(law, {1e3, 0.1, 0, 10}), std::invalid_argument);
  }

  /// The shear curve of a simple shear: γ, τ, σ_n (compression positive), ε_n (compaction positive).
  struct ShearCurve
  {
    std::vector<double> shear_strain, shear_stress, normal_stress, normal_strain;
  };

  /// What the comparison reads off a curve in the shear stage.
  struct ShearCurveMeasures
  {
    double peak = 0;              ///< largest τ [Pa]
    double peak_strain = 0;       ///< γ there
    double steady_ratio = 0;      ///< mean τ over mean σ_n for γ in [0.2, 0.4]
    double half_drop_strain = 0;  ///< first γ after the peak where τ is half-way from the peak to its steady value
    double compaction = 0;        ///< ε_n at the end
  };

  ShearCurveMeasures measure(const ShearCurve &c)
  {
    ShearCurveMeasures m;
    std::size_t peak = 0;
    for (std::size_t i = 0; i < c.shear_stress.size(); ++i)
      if (c.shear_stress[i] > c.shear_stress[peak])
        peak = i;
    m.peak = c.shear_stress[peak];
    m.peak_strain = c.shear_strain[peak];
    double tau = 0, sigma = 0;
    int n = 0;
    for (std::size_t i = 0; i < c.shear_strain.size(); ++i)
      if (c.shear_strain[i] >= 0.2 && c.shear_strain[i] <= 0.4)
      {
        tau += c.shear_stress[i];
        sigma += c.normal_stress[i];
        ++n;
      }
    m.steady_ratio = tau / sigma;
    const double steady_tau = tau / n;
    m.half_drop_strain = std::nan("");
    for (std::size_t i = peak; i < c.shear_stress.size(); ++i)
      if (c.shear_stress[i] <= 0.5 * (m.peak + steady_tau))
      {
        m.half_drop_strain = c.shear_strain[i];
        break;
      }
    m.compaction = c.normal_strain.back();
    return m;
  }

  /// The DEM's curve from data/dem_simple_shear/ (shear stage only), its base reactions averaged
  /// over 5 rows (10 samples of the run, Δγ ≈ 0.001): they ring after the peak (the file's README).
  ShearCurve dem_curve(const std::string &file)
  {
    std::ifstream in(file);
    if (!in)
      throw std::runtime_error("cannot read " + file);
    std::string line;
    std::vector<std::vector<double>> rows;
    bool header = true;
    while (std::getline(in, line))
    {
      if (line.empty() || line[0] == '#')
        continue;
      if (header) // the column names
      {
        header = false;
        continue;
      }
      std::vector<double> row;
      std::stringstream fields(line);
      std::string field;
      while (std::getline(fields, field, ','))
        row.push_back(std::stod(field));
      rows.push_back(row);
    }
    ShearCurve c;
    const int half_window = 2;
    for (std::size_t i = 0; i < rows.size(); ++i)
    {
      if (!(rows[i][1] > 0))
        continue;
      double tau = 0, sigma = 0;
      int n = 0;
      for (int k = -half_window; k <= half_window; ++k)
        if (i + k < rows.size() && static_cast<long>(i) + k >= 0)
        {
          tau += rows[i + k][2];
          sigma += rows[i + k][3];
          ++n;
        }
      c.shear_strain.push_back(rows[i][1]);
      c.shear_stress.push_back(tau / n);
      c.normal_stress.push_back(sigma / n);
      c.normal_strain.push_back(rows[i][4]);
    }
    return c;
  }

  TEST(PointSimpleShear, RepeatsTheDemsIntactShear)
  {
    // The calibrated weak layer in DEM units, at the DEM specimen's own height (no crack-band
    // scaling of ξ) with its lock-up and μ, as the FE layer takes them (fem/scene/crack_band.h).
    const std::string data = std::string(ANTICRACK_SOURCE_DIR) + "/data/dem_simple_shear/";
    const MaterialFile file = read_whole_material_file(data + "material.prm");
    Layer layer;
    layer.material = file.material;
    const double height = file.material.reference_thickness;
    layer.collapse_height = file.collapse.lock_up_strain * height;
    layer.densification_modulus = file.collapse.lock_up_modulus;
    const LayerLaw law = LayerLaw::cohesive_cam_clay(cam_clay_parameters(layer, height), file.collapse.friction_coefficient);

    for (const auto &[name, sigma_n] : {std::pair<std::string, double>{"2kPa", 2e3}, {"5kPa", 5e3}})
    {
      SCOPED_TRACE(name);
      const ShearCurveMeasures dem = measure(dem_curve(data + "intact_shear_" + name + ".csv"));
      ShearCurve fe;
      for (const PointSimpleShearSample &s : point_simple_shear(law, {sigma_n, 0.4, 100, 20000}))
        if (s.shear_strain > 0)
        {
          fe.shear_strain.push_back(s.shear_strain);
          fe.shear_stress.push_back(s.shear_stress);
          fe.normal_stress.push_back(s.normal_stress);
          fe.normal_strain.push_back(s.normal_strain);
        }
      const ShearCurveMeasures point = measure(fe);
      // The peak: the surface was fitted to the load-controlled tests (fit RMSE 8.1 %), never to
      // this displacement-controlled one; 10 % is that scatter.
      EXPECT_NEAR(point.peak / dem.peak, 1, 0.10);
      // The cohesion goes at least as fast as in the DEM, whose shear stress is half-way down
      // Δγ = 0.0014-0.003 after its peak. (A failed point that keeps the layer-plane shear in its
      // skeleton until the softening is complete needs 0.010-0.015: docs/physics.md §2.)
      EXPECT_LE(point.half_drop_strain - point.peak_strain, dem.half_drop_strain - dem.peak_strain);
      // Known misses, printed: the DEM slides at 0.50-0.60 of σ_n in its band at these stresses,
      // the FE at μ (measured on the collapsed layer at 45 kPa); the DEM compacts by shear at 5 kPa.
      std::cout << name << ": peak DEM " << dem.peak << " Pa, FE " << point.peak << " Pa; half-drop after Δγ DEM "
                << dem.half_drop_strain - dem.peak_strain << ", FE " << point.half_drop_strain - point.peak_strain
                << "; steady τ/σ_n DEM " << dem.steady_ratio << ", FE " << point.steady_ratio << "; compaction DEM "
                << dem.compaction << ", FE " << point.compaction << "\n";
    }
  }
} // namespace
