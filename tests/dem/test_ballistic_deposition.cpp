// Ballistic-deposition generators (docs/physics.md §1.4): solid fractions and coordination of sticky
// (Lubachevsky et al. 1992, ~0.15, 2 contacts) and rolling (Visscher & Bolsterli 1972, ~0.58)
// deposits, overlap-free geometry, reproducibility and input checks.
#include "dem/sample/ballistic_deposition.h"
#include "dem/core/system.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>
#include <vector>

namespace anticrack::dem
{
  namespace
  {
    constexpr double R0 = 1e-3;

    DemSystem make_system()
    {
      DemSystem s;
      Material m;
      m.density = 1000;
      m.bond.enabled = true;
      s.materials.add(m);
      return s;
    }

    BallisticDepositionSpec make_spec(DepositionRule rule, double lateral_diameters, Index n,
                                      std::uint64_t seed = 7)
    {
      BallisticDepositionSpec spec;
      spec.rule = rule;
      spec.box_lower = Vec3(0, 0, 0);
      spec.box_upper = Vec3(lateral_diameters * 2 * R0, lateral_diameters * 2 * R0, 0.01);
      spec.particle_count = n;
      spec.radius.mean = R0;
      spec.seed = seed;
      return spec;
    }

    /// Per-sphere contact counts and the largest relative overlap, by brute force over a cell
    /// grid independent of the generator's (periodic x, y via the domain's minimum image).
    struct Geometry
    {
      std::vector<int> contacts;
      double max_overlap = 0; ///< max over pairs of (R_i + R_j - |x_ij|) / min(R_i, R_j)
    };

    Geometry examine(const DemSystem &s, double tol = 1e-9)
    {
      const ParticleStore &p = s.particles;
      const Index n = p.size();
      Geometry g;
      g.contacts.assign(n, 0);
      double rmax = 0;
      for (Index i = 0; i < n; ++i)
        rmax = std::max(rmax, p.radius[i]);
      // sort by z and sweep: pairs with |dz| < 2 rmax
      std::vector<Index> order(n);
      for (Index i = 0; i < n; ++i)
        order[i] = i;
      std::sort(order.begin(), order.end(),
                [&](Index a, Index b) { return p.position[a].z() < p.position[b].z(); });
      for (Index a = 0; a < n; ++a)
        for (Index b = a + 1; b < n; ++b)
        {
          const Index i = order[a], j = order[b];
          if (p.position[j].z() - p.position[i].z() > 2 * rmax)
            break;
          const Vec3 shift = s.domain.minimum_image_shift(p.position[i], p.position[j]);
          const double dist = (p.position[j] + shift - p.position[i]).norm();
          const double rmin = std::min(p.radius[i], p.radius[j]);
          const double gap = (dist - p.radius[i] - p.radius[j]) / rmin;
          g.max_overlap = std::max(g.max_overlap, -gap);
          if (gap <= tol)
          {
            ++g.contacts[i];
            ++g.contacts[j];
          }
        }
      return g;
    }

    double seconds_since(std::chrono::steady_clock::time_point t0)
    {
      return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    }
  } // namespace

  TEST(BallisticDeposition, StickySolidFractionAndTwoContacts)
  {
    DemSystem s = make_system();
    const auto spec = make_spec(DepositionRule::sticky, 20, 6000);
    const auto t0 = std::chrono::steady_clock::now();
    const DepositionReport rep = add_ballistic_deposit(s, spec);
    const double t = seconds_since(t0);
    RecordProperty("seconds", std::to_string(t));
    std::printf("sticky: N=%lld phi_bulk=%.4f z_bulk=%.3f z_all=%.3f height=%.1f d, %.3f s\n",
                static_cast<long long>(rep.particles), rep.solid_fraction_bulk, rep.mean_contacts,
                rep.mean_contacts_all, rep.height / (2 * R0), t);
    ASSERT_EQ(rep.particles, 6000);
    ASSERT_EQ(s.particles.size(), 6000);
    EXPECT_EQ(rep.fallbacks, 0);
    EXPECT_GT(rep.bulk_upper, rep.bulk_lower + 10 * 2 * R0);
    EXPECT_GT(rep.solid_fraction_bulk, 0.13);
    EXPECT_LT(rep.solid_fraction_bulk, 0.22);
    EXPECT_GE(rep.mean_contacts, 1.9);
    EXPECT_LE(rep.mean_contacts, 2.3);
    // Each sphere touches exactly one earlier sphere or the base: pairs = N - on_base, checked
    // independently of the generator's own count.
    const Geometry g = examine(s);
    long long sum = 0;
    for (const int c : g.contacts)
      sum += c;
    EXPECT_EQ(sum / 2, rep.particles - rep.on_base);
    EXPECT_LT(g.max_overlap, 1e-9);
    // A small gap tolerance bonds exactly the deposited contacts.
    EXPECT_EQ(s.bond_touching_pairs({1e-9}), rep.particles - rep.on_base);
    // The domain was set periodic in x, y and contains the deposit.
    EXPECT_TRUE(s.domain.periodic[0] && s.domain.periodic[1] && !s.domain.periodic[2]);
    EXPECT_GE(s.domain.upper.z(), rep.height);
  }

  // A thin layer (Bobillier et al.'s (2020) weak layer is ~6 diameters thick) is thinner than the two default
  // margins of 4 diameters: its bulk slab must still exist (the middle half of the thickness) and
  // measure the sticky solid fraction, not report 0.
  TEST(BallisticDeposition, ThinLayerKeepsItsMiddleHalfAsBulk)
  {
    DemSystem s = make_system();
    const DepositionReport rep = add_ballistic_deposit(s, make_spec(DepositionRule::sticky, 20, 450));
    // The slab is the middle half: bulk_lower = thickness / 4 above the base (z = 0), and the mean
    // thickness, twice the slab, is below the 2 x 4 diameters of the default margins.
    ASSERT_GT(rep.bulk_upper, rep.bulk_lower);
    const double thickness = 2 * (rep.bulk_upper - rep.bulk_lower);
    EXPECT_LT(thickness, 16 * R0);
    EXPECT_NEAR(rep.bulk_lower, thickness / 4, 1e-12);
    EXPECT_GT(rep.solid_fraction_bulk, 0.1);
    EXPECT_LT(rep.solid_fraction_bulk, 0.25);
  }

  TEST(BallisticDeposition, RollingSolidFractionAndThreePointRest)
  {
    DemSystem s = make_system();
    const auto spec = make_spec(DepositionRule::rolling, 12, 4000);
    const auto t0 = std::chrono::steady_clock::now();
    const DepositionReport rep = add_ballistic_deposit(s, spec);
    const double t = seconds_since(t0);
    std::printf("rolling: N=%lld phi_bulk=%.4f z_bulk=%.3f z_all=%.3f height=%.1f d fallbacks=%lld "
                "on_base=%lld, %.3f s\n",
                static_cast<long long>(rep.particles), rep.solid_fraction_bulk, rep.mean_contacts,
                rep.mean_contacts_all, rep.height / (2 * R0), static_cast<long long>(rep.fallbacks),
                static_cast<long long>(rep.on_base), t);
    EXPECT_GT(rep.bulk_upper, rep.bulk_lower + 10 * 2 * R0);
    EXPECT_GT(rep.solid_fraction_bulk, 0.53);
    EXPECT_LT(rep.solid_fraction_bulk, 0.60);
    EXPECT_LT(rep.fallbacks, rep.particles / 100);
    const Geometry g = examine(s);
    EXPECT_LT(g.max_overlap, 1e-9);
    Index poorly_supported = 0;
    for (Index i = 0; i < s.particles.size(); ++i)
    {
      const bool on_base = s.particles.position[i].z() - s.particles.radius[i] <= 1e-9 * R0;
      if (!on_base && g.contacts[i] < 3)
        ++poorly_supported;
    }
    EXPECT_LE(poorly_supported, rep.fallbacks);
  }

  TEST(BallisticDeposition, NoOverlapReproduciblePolydisperse)
  {
    for (const DepositionRule rule : {DepositionRule::sticky, DepositionRule::rolling})
    {
      SCOPED_TRACE(rule == DepositionRule::sticky ? "sticky" : "rolling");
      auto spec = make_spec(rule, 8, 800, 11);
      spec.radius.half_width = 0.2 * R0;
      DemSystem a = make_system(), b = make_system(), c = make_system();
      const DepositionReport ra = add_ballistic_deposit(a, spec);
      add_ballistic_deposit(b, spec);
      spec.seed = 12;
      add_ballistic_deposit(c, spec);
      ASSERT_EQ(a.particles.size(), 800);
      EXPECT_EQ(a.particles.position, b.particles.position);
      EXPECT_EQ(a.particles.radius, b.particles.radius);
      EXPECT_NE(a.particles.position, c.particles.position);
      double rmin = 1, rmax = 0;
      for (Index i = 0; i < a.particles.size(); ++i)
      {
        rmin = std::min(rmin, a.particles.radius[i]);
        rmax = std::max(rmax, a.particles.radius[i]);
        const Vec3 &x = a.particles.position[i];
        EXPECT_TRUE(x.x() >= 0 && x.x() < spec.box_upper.x() && x.y() >= 0 && x.y() < spec.box_upper.y());
        EXPECT_GE(x.z() - a.particles.radius[i], -1e-12 * R0);
        EXPECT_NEAR(a.particles.mass[i], 1000 * 4.0 / 3.0 * M_PI * std::pow(a.particles.radius[i], 3),
                    1e-12 * a.particles.mass[i]);
      }
      EXPECT_GE(rmin, 0.8 * R0);
      EXPECT_LE(rmax, 1.2 * R0);
      EXPECT_GT(rmax - rmin, 0.3 * R0); // actually polydisperse
      const Geometry g = examine(a);
      EXPECT_LT(g.max_overlap, 1e-9);
      if (rule == DepositionRule::sticky)
      {
        long long sum = 0;
        for (const int k : g.contacts)
          sum += k;
        EXPECT_EQ(sum / 2, ra.particles - ra.on_base);
      }
      else
        EXPECT_LT(ra.fallbacks, 8);
    }
  }

  TEST(BallisticDeposition, BadInputNamesTheParameter)
  {
    auto expect_error = [](BallisticDepositionSpec spec, const std::string &name) {
      DemSystem s = make_system();
      try
      {
        add_ballistic_deposit(s, spec);
        ADD_FAILURE() << "no SetupError for " << name;
      }
      catch (const SetupError &e)
      {
        EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
      }
    };
    const auto good = make_spec(DepositionRule::sticky, 10, 10);
    auto spec = good;
    spec.radius.mean = 0;
    expect_error(spec, "radius.mean");
    spec = good;
    spec.radius.mean = -1e-3;
    expect_error(spec, "radius.mean");
    spec = good;
    spec.radius.half_width = R0;
    expect_error(spec, "radius.half_width");
    spec = good;
    spec.box_upper.x() = 3.9 * 2 * R0;
    expect_error(spec, "box_upper - box_lower");
    spec = good;
    spec.box_upper.y() = 3.9 * 2 * R0;
    expect_error(spec, "box_upper - box_lower");
    spec = good;
    spec.material = 3;
    expect_error(spec, "material");
    spec = good;
    spec.particle_count = -1;
    expect_error(spec, "particle_count");
    // A laterally periodic domain that does not match the box.
    DemSystem s = make_system();
    s.domain.periodic = {true, true, false};
    s.domain.upper = Vec3(1, 1, 1);
    EXPECT_THROW(add_ballistic_deposit(s, good), SetupError);
    // The good spec passes.
    DemSystem ok = make_system();
    EXPECT_EQ(add_ballistic_deposit(ok, good).particles, 10);
  }
} // namespace anticrack::dem
