// Tests of the small-strain error of a collapsing column (fem/material/column_collapse.h):
//  * the finite-strain reference against the closed form of Hencky elasticity in uniaxial strain,
//    σ = (K + 4G/3) (−ln(1 − x)) / (1 − x), work (K + 4G/3) ln²(1 − x) / 2, and the small-strain
//    path against σ = (K + 4G/3) x;
//  * the error of the solver's kinematics for the shipped PST scenes' weak layer (h_c / H = 0.15)
//    lies within the bound the scene check enforces, and grows past it for thicker collapses;
//  * below the peak it vanishes as the strain does, to first order.
#include "fem/material/column_collapse.h"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

namespace
{
  using namespace anticrack::fem;

  /// The weak layer of scenes/pst_flat.prm (E = 0.2 MPa, ν = 0.2, p0 = 5 kPa, β = 0.5, M = 1,
  /// collapse law, ξ = 4 on its own thickness, residual 10 %, K_d = 1 MPa), locking up at h_c / H.
  CamClayParameters pst_weak_layer(double closure_ratio)
  {
    CamClayParameters m;
    m.set_elastic_moduli(2e5, 0.2);
    m.M = 1;
    m.beta = 0.5;
    m.p0_initial = 5000;
    m.hardening_factor = 4;
    m.p0_floor = residual_p0_floor(5000, 0.1);
    m.law = HardeningLaw::collapse;
    m.densification_strain = closure_ratio;
    m.densification_modulus = 1e6;
    return m;
  }

  TEST(ColumnCollapse, ElasticColumnMatchesTheClosedFormsOfBothKinematics)
  {
    // p0 so large that the path stays elastic: the two kinematics differ only by their strain
    // measure and the Cauchy/Kirchhoff stress. Trapezoid over 4000 steps: relative error ~1e-8.
    CamClayParameters m = pst_weak_layer(0.2);
    m.p0_initial = 1e9;
    m.p0_floor = 1e6;
    const double modulus = m.bulk_modulus + 4 * m.shear_modulus / 3, x = 0.2, ln = std::log(1 - x);
    const ColumnCollapseComparison c = compare_column_collapse(m);
    EXPECT_NEAR(c.peak_small_strain, modulus * x, 1e-10 * modulus);
    EXPECT_NEAR(c.work_small_strain, modulus * x * x / 2, 1e-8 * modulus * x * x);
    EXPECT_NEAR(c.peak_finite_strain, modulus * -ln / (1 - x), 1e-10 * modulus);
    EXPECT_NEAR(c.work_finite_strain, modulus * ln * ln / 2, 1e-7 * modulus * ln * ln);
  }

  TEST(ColumnCollapse, ShippedWeakLayerIsWithinTheBoundAndThickCollapsesAreNot)
  {
    const ColumnCollapseComparison shipped = compare_column_collapse(pst_weak_layer(0.15));
    std::cout << "h_c/H = 0.15: peak " << shipped.peak_small_strain << " vs " << shipped.peak_finite_strain
              << " Pa (error " << shipped.peak_error() << "), work " << shipped.work_small_strain << " vs "
              << shipped.work_finite_strain << " J/m^3 (error " << shipped.work_error() << ")\n";
    EXPECT_LT(shipped.work_error(), max_collapse_work_error);
    EXPECT_LT(shipped.peak_error(), max_collapse_peak_error);
    for (const double ratio : {0.05, 0.1, 0.2, 0.25, 0.3, 0.4, 0.5})
    {
      const ColumnCollapseComparison c = compare_column_collapse(pst_weak_layer(ratio));
      std::cout << "h_c/H = " << ratio << ": peak error " << c.peak_error() << ", work error " << c.work_error() << "\n";
    }
    EXPECT_GT(compare_column_collapse(pst_weak_layer(0.4)).work_error(), max_collapse_work_error);
  }

  TEST(ColumnCollapse, KinematicsAgreeToFirstOrderInTheStrain)
  {
    // Below the peak (x < 1.8 % here) the path is elastic, and the work error is that of the strain
    // measures: ln²(1 − x) / x² − 1 ≈ x to first order; halving x halves it.
    const double e1 = compare_column_collapse(pst_weak_layer(0.008)).work_error();
    const double e2 = compare_column_collapse(pst_weak_layer(0.004)).work_error();
    EXPECT_NEAR(e1 / e2, 2, 0.02);
    EXPECT_NEAR(e2, 0.004, 0.05 * 0.004);
  }
} // namespace
