#include "dem/sample/ballistic_deposition.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <sstream>
#include <vector>

namespace anticrack::dem
{
  namespace
  {
    constexpr double pi = 3.14159265358979323846;
    constexpr double angle_tol = 1e-10; ///< [rad] roots this close to the start count as "now"

    struct Entry
    {
      Vec3 x;     ///< wrapped laterally into the box
      double r;
      Index id;   ///< index into the deposit arrays
    };

    struct Neighbour
    {
      Vec3 c;     ///< centre, lateral image nearest to the query point
      double r;
      Index id;
    };

    /// Periodic 2D column grid over (x, y) of the deposited spheres.
    class ColumnGrid
    {
    public:
      ColumnGrid(const Vec3 &lower, const Vec3 &upper, double cell) : lower_(lower)
      {
        L_ = upper - lower;
        n_[0] = std::max<Index>(1, static_cast<Index>(std::floor(L_[0] / cell)));
        n_[1] = std::max<Index>(1, static_cast<Index>(std::floor(L_[1] / cell)));
        w_[0] = L_[0] / n_[0];
        w_[1] = L_[1] / n_[1];
        cells_.resize(n_[0] * n_[1]);
      }

      Vec3 wrap(Vec3 x) const
      {
        for (int a = 0; a < 2; ++a)
        {
          x[a] -= L_[a] * std::floor((x[a] - lower_[a]) / L_[a]);
          if (x[a] >= lower_[a] + L_[a])
            x[a] = lower_[a];
        }
        return x;
      }

      void insert(const Vec3 &x, double r, Index id)
      {
        const Vec3 y = wrap(x);
        cells_[cell_of(y, 0) + n_[0] * cell_of(y, 1)].push_back({y, r, id});
      }

      /// Calls f(Neighbour) for every sphere whose centre is within `radius` horizontally of p
      /// (a superset is fine) and whose z lies in [zlo, zhi]; images nearest to p.
      template <class F>
      void for_each(const Vec3 &p, double radius, double zlo, double zhi, F &&f) const
      {
        Index lo[2], hi[2];
        for (int a = 0; a < 2; ++a)
        {
          lo[a] = static_cast<Index>(std::floor((p[a] - radius - lower_[a]) / w_[a]));
          hi[a] = static_cast<Index>(std::floor((p[a] + radius - lower_[a]) / w_[a]));
          if (hi[a] - lo[a] + 1 >= n_[a])
          {
            lo[a] = 0;
            hi[a] = n_[a] - 1;
          }
        }
        for (Index j = lo[1]; j <= hi[1]; ++j)
          for (Index i = lo[0]; i <= hi[0]; ++i)
          {
            const Index ci = ((i % n_[0]) + n_[0]) % n_[0], cj = ((j % n_[1]) + n_[1]) % n_[1];
            for (const Entry &e : cells_[ci + n_[0] * cj])
            {
              if (e.x[2] < zlo || e.x[2] > zhi)
                continue;
              Vec3 c = e.x;
              for (int a = 0; a < 2; ++a)
                c[a] -= L_[a] * std::nearbyint((c[a] - p[a]) / L_[a]);
              f(Neighbour{c, e.r, e.id});
            }
          }
      }

      const Vec3 &length() const { return L_; }

    private:
      Index cell_of(const Vec3 &y, int a) const
      {
        return std::min<Index>(n_[a] - 1, static_cast<Index>((y[a] - lower_[a]) / w_[a]));
      }
      Vec3 lower_, L_;
      Index n_[2];
      double w_[2];
      std::vector<std::vector<Entry>> cells_;
    };

    /// Circle of centre positions touching two supports a and b.
    struct Circle
    {
      bool valid = false;
      Vec3 M, u, e1, e2; ///< centre, axis (a -> b), lowest direction, e2 = u x e1 (horizontal)
      double rho = 0, t = 0, d = 0;
    };

    Circle make_circle(const Vec3 &ca, double Da, const Vec3 &cb, double Db)
    {
      Circle c;
      Vec3 u = cb - ca;
      c.d = u.norm();
      if (!(c.d > 0))
        return c;
      u /= c.d;
      c.t = (c.d * c.d + Da * Da - Db * Db) / (2 * c.d);
      const double rho2 = Da * Da - c.t * c.t;
      if (!(rho2 > 0))
        return c;
      c.rho = std::sqrt(rho2);
      c.u = u;
      c.M = ca + c.t * u;
      Vec3 e1 = -(Vec3::UnitZ() - u.z() * u);
      const double n1 = e1.norm();
      if (n1 < 1e-9)
        return c; // horizontal circle: no descent
      c.e1 = e1 / n1;
      c.e2 = u.cross(c.e1);
      c.valid = true;
      return c;
    }

    /// Normal forces (per unit weight) of two supports holding a sphere at p against gravity -z,
    /// the component along the circle's tangent left free. Positive = compressive.
    void pair_forces(const Vec3 &p, const Vec3 &ca, double Da, const Vec3 &cb, double Db, double &la,
                     double &lb)
    {
      const Vec3 na = (p - ca) / Da, nb = (p - cb) / Db;
      const double c = na.dot(nb), sa = na.z(), sb = nb.z();
      const double det = 1 - c * c;
      la = (sa - c * sb) / det;
      lb = (sb - c * sa) / det;
    }

    /// Smallest angle x in [x0 - tol, x1] with a sin x + b cos x = k where the left side is
    /// decreasing-distance (entering), i.e. f(x) = 2 (a sin x + b cos x - k) has f' < 0 along
    /// increasing x. Returns +inf if none.
    double first_entering_root(double a, double b, double k, double x0, double x1)
    {
      const double amp = std::hypot(a, b);
      if (!(amp > 0) || std::abs(k) > amp)
        return std::numeric_limits<double>::infinity();
      const double ph = std::atan2(a, b), dl = std::acos(std::clamp(k / amp, -1.0, 1.0));
      double best = std::numeric_limits<double>::infinity();
      for (const double r0 : {ph + dl, ph - dl})
      {
        const double base = x0 - angle_tol;
        const double r = r0 - 2 * pi * std::floor((r0 - base) / (2 * pi));
        if (r > x1)
          continue;
        const double deriv = a * std::cos(r) - b * std::sin(r);
        if (deriv < 0 && r < best)
          best = r;
      }
      return best;
    }

    double cap_volume(double h, double R)
    {
      h = std::clamp(h, 0.0, 2 * R);
      return pi * h * h * (3 * R - h) / 3;
    }

    std::string num(double x)
    {
      std::ostringstream s;
      s << x;
      return s.str();
    }

    class Depositor
    {
    public:
      Depositor(const BallisticDepositionSpec &spec, double r_max)
        : spec_(spec), grid_(spec.box_lower, spec.box_upper, 2 * r_max), r_max_(r_max),
          base_(spec.box_lower.z())
      {
      }

      void add_obstacle(const Vec3 &x, double r)
      {
        const Index id = static_cast<Index>(x_.size());
        x_.push_back(grid_.wrap(x));
        r_.push_back(r);
        grid_.insert(x, r, id);
      }

      /// Deposits one sphere of radius R at lateral (x, y); returns the id in the deposit arrays.
      Index deposit(double x, double y, double R, std::mt19937_64 &rng, bool &fallback)
      {
        fallback = false;
        Vec3 p(x, y, std::numeric_limits<double>::infinity());
        Index hit = fall(p, R, -1);
        if (spec_.rule == DepositionRule::rolling && hit >= 0)
        {
          const Vec3 sticky = p;
          if (!roll(p, R, hit, rng))
          {
            p = sticky;
            fallback = true;
          }
        }
        const Index id = static_cast<Index>(x_.size());
        x_.push_back(grid_.wrap(p));
        r_.push_back(R);
        grid_.insert(p, R, id);
        return id;
      }

      const std::vector<Vec3> &positions() const { return x_; }
      const ColumnGrid &grid() const { return grid_; }

    private:
      /// Vertical fall from p (p.z may be +inf). Sets p to the first contact; returns the id of the
      /// sphere touched or -1 for the base (or nothing: then p.z = base + R regardless).
      Index fall(Vec3 &p, double R, Index ignore) const
      {
        const double z0 = p.z();
        double best = spec_.base_layer ? base_ + R : -std::numeric_limits<double>::infinity();
        Index hit = -1;
        grid_.for_each(p, R + r_max_, -std::numeric_limits<double>::infinity(),
                       std::numeric_limits<double>::infinity(), [&](const Neighbour &n) {
                         if (n.id == ignore)
                           return;
                         const double D = R + n.r;
                         const double dx = n.c.x() - p.x(), dy = n.c.y() - p.y();
                         const double d2 = dx * dx + dy * dy;
                         if (d2 >= D * D * (1 - 2e-9)) // grazing side contacts do not stop a fall
                           return;
                         const double zc = n.c.z() + std::sqrt(D * D - d2);
                         if (zc > z0 + 1e-12 * D || zc <= best)
                           return;
                         best = zc;
                         hit = n.id;
                       });
        if (!std::isfinite(best))
          best = base_ + R; // no base and nothing below: cannot happen with base_layer
        p.z() = best;
        return hit;
      }

      std::vector<Neighbour> gather(const Vec3 &centre, double radius) const
      {
        std::vector<Neighbour> out;
        grid_.for_each(centre, radius, centre.z() - radius, centre.z() + radius,
                       [&](const Neighbour &n) { out.push_back(n); });
        return out;
      }

      Neighbour support(Index id, const Vec3 &p) const
      {
        Vec3 c = x_[id];
        const Vec3 &L = grid_.length();
        for (int a = 0; a < 2; ++a)
          c[a] -= L[a] * std::nearbyint((c[a] - p[a]) / L[a]);
        return {c, r_[id], id};
      }

      /// Rolling phases (see file comment). Returns false if no rest was found.
      bool roll(Vec3 &p, double R, Index first, std::mt19937_64 &rng) const
      {
        std::vector<Index> sup = {first};
        Index dropped = -1;
        for (Index event = 0; event < spec_.max_roll_events; ++event)
        {
          if (sup.empty())
          {
            const Index hit = fall(p, R, dropped);
            if (hit < 0)
              return true; // on the base
            sup = {hit};
            dropped = -1;
          }
          else if (sup.size() == 1)
          {
            const int r = roll_one(p, R, sup, dropped, rng);
            if (r == 1)
              return true;
          }
          else if (sup.size() == 2)
          {
            const int r = roll_two(p, R, sup, dropped);
            if (r == 1)
              return true;
            if (r < 0)
              return false;
          }
          else
          {
            const int r = three(p, R, sup, dropped);
            if (r == 1)
              return true;
            if (r < 0)
              return false;
          }
        }
        return false;
      }

      /// Descent direction and angle of a sphere at p on one support. Returns false if the
      /// support is at or above the equator (no support).
      static bool one_geometry(const Vec3 &p, const Neighbour &a, double D, Vec3 &h, double &theta,
                               std::mt19937_64 *rng)
      {
        const Vec3 v = p - a.c;
        const double hn = std::hypot(v.x(), v.y());
        theta = std::atan2(hn, v.z());
        if (hn < 1e-12 * D)
        {
          if (rng == nullptr)
            return false;
          std::uniform_real_distribution<double> angle(0, 2 * pi);
          const double phi = angle(*rng);
          h = Vec3(std::cos(phi), std::sin(phi), 0);
        }
        else
          h = Vec3(v.x() / hn, v.y() / hn, 0);
        return theta < pi / 2 - 1e-12;
      }

      /// 1: rest (base), 0: state changed.
      int roll_one(Vec3 &p, double R, std::vector<Index> &sup, Index &dropped,
                   std::mt19937_64 &rng) const
      {
        const Neighbour a = support(sup[0], p);
        const double D = R + a.r;
        Vec3 h;
        double th0;
        if (!one_geometry(p, a, D, h, th0, &rng))
        {
          // At or below the equator: falls off.
          dropped = a.id;
          sup.clear();
          return 0;
        }
        auto at = [&](double th) -> Vec3 { return a.c + D * (std::sin(th) * h + std::cos(th) * Vec3::UnitZ()); };
        double th_end = pi / 2;
        int kind = 0; // 0 none, 1 base, 2 sphere
        Index other = -1;
        if (spec_.base_layer)
        {
          const double cz = (base_ + R - a.c.z()) / D;
          if (cz >= 0 && cz <= 1)
          {
            const double tb = std::acos(cz);
            if (tb < th_end)
            {
              th_end = std::max(tb, th0);
              kind = 1;
            }
          }
        }
        for (const Neighbour &b : gather(a.c, D + R + r_max_))
        {
          if (b.id == a.id)
            continue;
          const Vec3 w = a.c - b.c;
          const double Db = R + b.r;
          const double k = (Db * Db - w.squaredNorm() - D * D) / (2 * D);
          double th = first_entering_root(w.dot(h), w.z(), k, th0, th_end);
          if (b.id == dropped && th < th0 + 1e-7)
            continue;
          if (th <= th_end)
          {
            th_end = std::max(th, th0);
            kind = 2;
            other = b.id;
          }
        }
        p = at(th_end);
        if (kind == 1)
          return 1;
        if (kind == 2)
        {
          sup.push_back(other);
          dropped = -1;
          return 0;
        }
        dropped = a.id; // rolled off the equator
        sup.clear();
        return 0;
      }

      /// 1: rest (base), 0: state changed, -1: failure.
      int roll_two(Vec3 &p, double R, std::vector<Index> &sup, Index &dropped) const
      {
        const Neighbour a = support(sup[0], p), b = support(sup[1], p);
        const double Da = R + a.r, Db = R + b.r;
        const Circle c = make_circle(a.c, Da, b.c, Db);
        if (!c.valid)
        {
          // Degenerate (vertical axis): keep the lower support.
          const bool drop_a = a.c.z() > b.c.z();
          dropped = drop_a ? a.id : b.id;
          sup = {drop_a ? b.id : a.id};
          return 0;
        }
        const Vec3 rr = p - c.M;
        const double phi0 = std::atan2(rr.dot(c.e2), rr.dot(c.e1));
        auto at = [&](double phi) -> Vec3 { return c.M + c.rho * (std::cos(phi) * c.e1 + std::sin(phi) * c.e2); };
        p = at(phi0);
        double la, lb;
        pair_forces(p, a.c, Da, b.c, Db, la, lb);
        if (la < 0 || lb < 0 || std::abs(phi0) < 1e-12)
        {
          const bool drop_a = la < lb;
          dropped = drop_a ? a.id : b.id;
          sup = {drop_a ? b.id : a.id};
          return 0;
        }
        const double sigma = phi0 > 0 ? 1 : -1;
        const double s0 = std::abs(phi0);
        // Path: phi = sigma * s, s from s0 down to 0. Best event = largest s.
        double s_best = -1;
        int kind = 0; // 1 base, 2 sphere, 3 lose a, 4 lose b
        Index other = -1;
        // Loss of a support: lambda linear in cos(phi).
        {
          const double e1z = c.e1.z(), uz = c.u.z();
          const Vec3 na0 = (at(0) - a.c) / Da, nb0 = (at(0) - b.c) / Db;
          const double cc = na0.dot(nb0); // constant along the circle
          const double alpha_a = c.rho * e1z * (1 / Da - cc / Db);
          const double beta_a = uz * (c.t / Da - cc * (c.t - c.d) / Db);
          const double alpha_b = c.rho * e1z * (1 / Db - cc / Da);
          const double beta_b = uz * ((c.t - c.d) / Db - cc * c.t / Da);
          const double cos0 = std::cos(s0);
          auto crossing = [&](double al, double be, int k) {
            // lambda(cos) = al cos + be (times a positive factor); >= 0 at cos0, negative at 1?
            if (al + be < 0 && std::abs(al) > 0)
            {
              const double cs = std::clamp(-be / al, cos0, 1.0);
              const double s = std::acos(cs);
              if (s > s_best)
              {
                s_best = s;
                kind = k;
              }
            }
          };
          crossing(alpha_a, beta_a, 3);
          crossing(alpha_b, beta_b, 4);
        }
        if (spec_.base_layer && c.e1.z() < 0)
        {
          const double cs = (base_ + R - c.M.z()) / (c.rho * c.e1.z());
          if (cs >= std::cos(s0) - 1e-15 && cs <= 1)
          {
            const double s = std::acos(std::min(cs, 1.0));
            if (s > s_best)
            {
              s_best = std::min(s, s0);
              kind = 1;
            }
          }
        }
        for (const Neighbour &n : gather(c.M, c.rho + R + r_max_))
        {
          if (n.id == a.id || n.id == b.id)
            continue;
          const Vec3 w = c.M - n.c;
          const double Dn = R + n.r;
          const double k = (Dn * Dn - w.squaredNorm() - c.rho * c.rho) / (2 * c.rho);
          // In s: phi = sigma s, moving with s decreasing. Let x = s0 - s increasing from 0.
          // A cos(phi) + B sin(phi) with phi = sigma (s0 - x):
          //   = A cos(sigma s0 - sigma x) + B sin(sigma s0 - sigma x) = a' sin x + b' cos x.
          const double A = w.dot(c.e1), B = w.dot(c.e2), ph0 = sigma * s0;
          const double cp = std::cos(ph0), sp = std::sin(ph0);
          // cos(ph0 - sigma x) = cp cos x + sp sigma sin x; sin(ph0 - sigma x) = sp cos x - cp sigma sin x
          const double ap = sigma * (A * sp - B * cp), bp = A * cp + B * sp;
          const double x = first_entering_root(ap, bp, k, 0, s0 - std::max(s_best, 0.0));
          if (n.id == dropped && x < 1e-7)
            continue;
          if (!std::isfinite(x))
            continue;
          const double s = s0 - std::max(x, 0.0);
          if (s >= s_best)
          {
            s_best = s;
            kind = 2;
            other = n.id;
          }
        }
        if (kind == 0)
        {
          // Reached the lowest point with both supports compressive: not expected geometrically.
          p = at(0);
          pair_forces(p, a.c, Da, b.c, Db, la, lb);
          const bool drop_a = la < lb;
          dropped = drop_a ? a.id : b.id;
          sup = {drop_a ? b.id : a.id};
          return 0;
        }
        p = at(sigma * s_best);
        if (kind == 1)
          return 1;
        if (kind == 2)
        {
          sup.push_back(other);
          dropped = -1;
          return 0;
        }
        const bool drop_a = kind == 3;
        dropped = drop_a ? a.id : b.id;
        sup = {drop_a ? b.id : a.id};
        return 0;
      }

      /// 1: rest, 0: state changed, -1: failure.
      int three(Vec3 &p, double R, std::vector<Index> &sup, Index &dropped) const
      {
        Neighbour s[3] = {support(sup[0], p), support(sup[1], p), support(sup[2], p)};
        Mat3 N;
        for (int k = 0; k < 3; ++k)
          N.col(k) = (p - s[k].c) / (R + s[k].r);
        const double det = N.determinant();
        Vec3 lambda = Vec3::Constant(-1);
        if (std::abs(det) > 1e-12)
        {
          lambda = N.partialPivLu().solve(Vec3::UnitZ());
          if (lambda.minCoeff() >= -1e-12)
            return 1;
        }
        // Unstable: continue on the pair whose motion leaves the third support, most tensile first.
        int order[3] = {0, 1, 2};
        std::sort(order, order + 3, [&](int i, int j) { return lambda[i] < lambda[j]; });
        for (const int k : order)
        {
          const Neighbour &a = s[(k + 1) % 3], &b = s[(k + 2) % 3];
          const double Da = R + a.r, Db = R + b.r;
          const Circle c = make_circle(a.c, Da, b.c, Db);
          if (!c.valid)
            continue;
          double la, lb;
          pair_forces(p, a.c, Da, b.c, Db, la, lb);
          const Vec3 rr = p - c.M;
          const double phi = std::atan2(rr.dot(c.e2), rr.dot(c.e1));
          if (la < 0 || lb < 0 || std::abs(phi) < 1e-12)
            continue;
          const double sigma = phi > 0 ? 1 : -1;
          const Vec3 T = -sigma * c.rho * (-std::sin(phi) * c.e1 + std::cos(phi) * c.e2);
          if (T.dot(p - s[k].c) <= 0)
            continue;
          dropped = s[k].id;
          sup = {a.id, b.id};
          return 0;
        }
        for (int j = 0; j < 3; ++j)
        {
          Vec3 h;
          double th;
          if (!one_geometry(p, s[j], R + s[j].r, h, th, nullptr))
            continue;
          const Vec3 T = std::cos(th) * h - std::sin(th) * Vec3::UnitZ();
          if (T.dot(p - s[(j + 1) % 3].c) <= 0 || T.dot(p - s[(j + 2) % 3].c) <= 0)
            continue;
          dropped = s[(j + 1) % 3].id; // the other may be touched again only by an entering root
          sup = {s[j].id};
          return 0;
        }
        return -1;
      }

      const BallisticDepositionSpec &spec_;
      ColumnGrid grid_;
      double r_max_;
      double base_;
      std::vector<Vec3> x_;
      std::vector<double> r_;
    };
  } // namespace

  DepositionReport add_ballistic_deposit(DemSystem &system, const BallisticDepositionSpec &spec)
  {
    const char *who = "ballistic deposition: ";
    const RadiusDistribution &rd = spec.radius;
    if (!(rd.mean > 0))
      throw SetupError(std::string(who) + "radius.mean must be > 0 (got " + num(rd.mean) + ")");
    if (!(rd.half_width >= 0) || !(rd.half_width < rd.mean))
      throw SetupError(std::string(who) + "radius.half_width must satisfy 0 <= half_width < mean (got " +
                       num(rd.half_width) + ")");
    if (spec.particle_count < 0)
      throw SetupError(std::string(who) + "particle_count must be >= 0");
    if (spec.material < 0 || spec.material >= system.materials.size())
      throw SetupError(std::string(who) + "material " + std::to_string(spec.material) +
                       " is not in system.materials");
    if (spec.max_roll_events < 1)
      throw SetupError(std::string(who) + "max_roll_events must be >= 1");
    if (!(spec.bulk_margin >= 0) || !(spec.contact_tolerance >= 0))
      throw SetupError(std::string(who) + "bulk_margin and contact_tolerance must be >= 0");
    const Vec3 L = spec.box_upper - spec.box_lower;
    const double min_lateral = 4 * 2 * rd.mean;
    if (!(L.x() >= min_lateral) || !(L.y() >= min_lateral))
      throw SetupError(std::string(who) + "box_upper - box_lower: lateral size (" + num(L.x()) + " x " +
                       num(L.y()) + ") must be at least 4 mean diameters (" + num(min_lateral) + ")");
    Domain &dom = system.domain;
    const bool lateral_periodic = dom.periodic[0] && dom.periodic[1];
    if (lateral_periodic)
    {
      for (int a = 0; a < 2; ++a)
        if (std::abs(dom.lower[a] - spec.box_lower[a]) > 1e-12 * L[a] ||
            std::abs(dom.upper[a] - spec.box_upper[a]) > 1e-12 * L[a])
          throw SetupError(std::string(who) +
                           "system.domain is periodic laterally but its x/y extent differs from "
                           "box_lower/box_upper");
    }
    else
    {
      dom.lower = spec.box_lower;
      dom.upper = spec.box_upper;
      dom.upper.z() = std::max(spec.box_upper.z(), spec.box_lower.z() + 2 * (rd.mean + rd.half_width));
      dom.periodic = {true, true, false};
    }

    const double r_min = rd.mean - rd.half_width, r_max_new = rd.mean + rd.half_width;
    double r_max = r_max_new;
    ParticleStore &ps = system.particles;
    for (Index i = 0; i < ps.size(); ++i)
      r_max = std::max(r_max, ps.radius[i]);

    Depositor dep(spec, r_max);
    for (Index i = 0; i < ps.size(); ++i)
      dep.add_obstacle(ps.position[i], ps.radius[i]);
    const Index obstacles = ps.size();

    DepositionReport rep;
    rep.first = ps.size();
    const double density = system.materials[spec.material].density;
    std::mt19937_64 rng(spec.seed);
    std::uniform_real_distribution<double> ux(spec.box_lower.x(), spec.box_upper.x());
    std::uniform_real_distribution<double> uy(spec.box_lower.y(), spec.box_upper.y());
    std::uniform_real_distribution<double> ur(r_min, r_max_new);
    std::vector<double> radii;
    radii.reserve(spec.particle_count);
    for (Index n = 0; n < spec.particle_count; ++n)
    {
      const double x = ux(rng), y = uy(rng);
      const double R = rd.half_width > 0 ? ur(rng) : rd.mean;
      bool fallback = false;
      const Index id = dep.deposit(x, y, R, rng, fallback);
      rep.fallbacks += fallback ? 1 : 0;
      radii.push_back(R);
      ps.add_sphere(dep.positions()[id], R, density, spec.material);
    }
    rep.particles = spec.particle_count;

    // --- report
    const double base = spec.box_lower.z();
    double top = base;
    for (Index n = 0; n < rep.particles; ++n)
      top = std::max(top, ps.position[rep.first + n].z() + radii[n]);
    rep.height = top - base;
    if (dom.upper.z() < top)
      dom.upper.z() = top + 1e-9 * rd.mean; // keep every centre strictly inside the domain
    // The top of the bulk: the mean surface height over lateral bins one mean diameter wide
    // (highest z + R of the spheres centred in each bin), so that the rough active zone of the
    // surface is excluded rather than measured from its highest peak.
    {
      const Index bx = std::max<Index>(1, static_cast<Index>(L.x() / (2 * rd.mean)));
      const Index by = std::max<Index>(1, static_cast<Index>(L.y() / (2 * rd.mean)));
      std::vector<double> surface(bx * by, base);
      for (Index n = 0; n < rep.particles; ++n)
      {
        const Vec3 &x = ps.position[rep.first + n];
        const Index i = std::clamp<Index>(static_cast<Index>((x.x() - spec.box_lower.x()) / L.x() * bx), 0, bx - 1);
        const Index j = std::clamp<Index>(static_cast<Index>((x.y() - spec.box_lower.y()) / L.y() * by), 0, by - 1);
        surface[i + bx * j] = std::max(surface[i + bx * j], x.z() + radii[n]);
      }
      double mean_surface = 0;
      for (const double h : surface)
        mean_surface += h;
      mean_surface /= static_cast<double>(surface.size());
      // A thin layer (a weak layer of a few diameters) keeps the middle half of its thickness.
      const double margin = std::min(spec.bulk_margin * 2 * rd.mean, 0.25 * (mean_surface - base));
      rep.bulk_lower = base + margin;
      rep.bulk_upper = mean_surface - margin;
    }
    double solid = 0;
    Index pairs = 0, bulk_spheres = 0, bulk_contacts = 0;
    const auto &pos = dep.positions();
    for (Index n = 0; n < rep.particles; ++n)
    {
      const Index id = obstacles + n;
      const Vec3 &x = pos[id];
      const double R = radii[n];
      if (spec.base_layer && x.z() - R - base <= spec.contact_tolerance * R)
        ++rep.on_base;
      if (rep.bulk_upper > rep.bulk_lower)
        solid += cap_volume(rep.bulk_upper - (x.z() - R), R) - cap_volume(rep.bulk_lower - (x.z() - R), R);
      const bool in_bulk = x.z() >= rep.bulk_lower && x.z() <= rep.bulk_upper;
      Index contacts = 0;
      dep.grid().for_each(x, R + r_max, x.z() - R - r_max, x.z() + R + r_max, [&](const Neighbour &m) {
        if (m.id == id)
          return;
        const double rj = m.id < obstacles ? ps.radius[m.id] : radii[m.id - obstacles];
        const double gap = (m.c - x).norm() - R - rj;
        if (gap > spec.contact_tolerance * std::min(R, rj))
          return;
        ++contacts;
        if (m.id >= obstacles && m.id > id)
          ++pairs;
        else if (m.id < obstacles)
          ++pairs; // contact with a pre-existing particle counts once
      });
      if (in_bulk)
      {
        ++bulk_spheres;
        bulk_contacts += contacts;
      }
    }
    if (rep.bulk_upper > rep.bulk_lower)
      rep.solid_fraction_bulk = solid / (L.x() * L.y() * (rep.bulk_upper - rep.bulk_lower));
    rep.mean_contacts = bulk_spheres > 0 ? static_cast<double>(bulk_contacts) / bulk_spheres : 0;
    rep.mean_contacts_all = rep.particles > 0 ? 2.0 * pairs / rep.particles : 0;
    return rep;
  }
} // namespace anticrack::dem
