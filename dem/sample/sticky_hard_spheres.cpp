#include "dem/sample/sticky_hard_spheres.h"

#include "dem/common/types.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <random>
#include <sstream>
#include <string>
#include <tuple>
#include <type_traits>
#include <utility>
#include <vector>

namespace anticrack::dem::shs
{
  namespace
  {
    void require_volume_fraction(double phi)
    {
      if (!(phi > 0 && phi < 1))
        throw SetupError("sticky hard spheres: volume fraction phi = " + std::to_string(phi) +
                         " outside (0, 1)");
    }

    /// Coefficients of the PY quadratic a lambda^2 + b lambda + c = 0.
    struct Quadratic
    {
      double a, b, c;
    };
    Quadratic percus_yevick_quadratic(double phi, double tau)
    {
      return {phi / 12, -(tau + phi / (1 - phi)), (1 + phi / 2) / ((1 - phi) * (1 - phi))};
    }
  } // namespace

  double minimum_stickiness(double phi)
  {
    require_volume_fraction(phi);
    return (14 * phi * phi - 4 * phi - 1) / (12 * (2 * phi * phi - phi - 1));
  }

  double percus_yevick_lambda(double phi, double tau)
  {
    const double tau_min = minimum_stickiness(phi);
    const Quadratic q = percus_yevick_quadratic(phi, tau);
    const double discriminant = q.b * q.b - 4 * q.a * q.c;
    if (!(tau >= tau_min) || discriminant < 0)
    {
      std::ostringstream message;
      message << "sticky hard spheres: stickiness tau = " << tau << " at volume fraction phi = " << phi
              << " is below the admissible minimum tau_min(phi) = " << tau_min
              << " (docs/physics.md §1.4); use tau >= tau_min or a lower volume fraction";
      throw SetupError(message.str());
    }
    // Smaller root, written to avoid cancellation: lambda = 2c / (-b + sqrt(disc)).
    return 2 * q.c / (-q.b + std::sqrt(discriminant));
  }

  double percus_yevick_coordination(double phi, double tau)
  {
    return 2 * phi * percus_yevick_lambda(phi, tau);
  }

  double stickiness_for_coordination(double phi, double z)
  {
    require_volume_fraction(phi);
    if (!(z > 0))
      throw SetupError("sticky hard spheres: target coordination number z = " + std::to_string(z) +
                       " must be positive");
    const double lambda = z / (2 * phi);
    const Quadratic q = percus_yevick_quadratic(phi, 0.0);
    const double tau = (q.a * lambda * lambda + q.c) / lambda - phi / (1 - phi);
    const double tau_min = minimum_stickiness(phi);
    // lambda must be the smaller root: the vertex of the parabola lies at lambda* = (tau + phi/(1-phi))/(2a).
    const double vertex = (tau + phi / (1 - phi)) / (2 * q.a);
    if (!(tau >= tau_min) || lambda > vertex)
    {
      std::ostringstream message;
      message << "sticky hard spheres: coordination number z = " << z << " at volume fraction phi = " << phi
              << " needs tau = " << tau << ", outside the admissible range tau >= tau_min(phi) = " << tau_min
              << " (the largest reachable z is " << percus_yevick_coordination(phi, tau_min) << ")";
      throw SetupError(message.str());
    }
    return tau;
  }
} // namespace anticrack::dem::shs

// -------------------------------------------------------------------------------------------------
// Monte Carlo sampler

namespace anticrack::dem::shs
{
  namespace
  {
    /// Particles of a periodic box in a cell grid (cells at least one well-range wide), for the
    /// sampler's neighbour queries; particles move between cells as they are displaced.
    class PeriodicCells
    {
    public:
      PeriodicCells(const Vec3 &box, double range, const std::vector<Vec3> &x) : box_(box)
      {
        for (int a = 0; a < 3; ++a)
        {
          cells_[a] = std::max<Index>(1, static_cast<Index>(std::floor(box[a] / range)));
          if (cells_[a] < 3)
            cells_[a] = 1; // one cell across: every pair along it is a candidate (minimum image keeps it unique)
        }
        members_.resize(cells_[0] * cells_[1] * cells_[2]);
        // Each cell's neighbourhood, in the order the walk visits it (z, y, x from -1 to 1; the one
        // cell across an axis that has one), so that the walk needs no modulo.
        const auto reach = [&](int a) { return cells_[a] == 1 ? Index(0) : Index(1); };
        neighbourhood_size_ = (2 * reach(0) + 1) * (2 * reach(1) + 1) * (2 * reach(2) + 1);
        neighbourhoods_.reserve(members_.size() * neighbourhood_size_);
        for (Index cz0 = 0; cz0 < cells_[2]; ++cz0)
          for (Index cy0 = 0; cy0 < cells_[1]; ++cy0)
            for (Index cx0 = 0; cx0 < cells_[0]; ++cx0)
              for (Index dz = -reach(2); dz <= reach(2); ++dz)
                for (Index dy = -reach(1); dy <= reach(1); ++dy)
                  for (Index dx = -reach(0); dx <= reach(0); ++dx)
                  {
                    const Index cx = (cx0 + dx + cells_[0]) % cells_[0], cy = (cy0 + dy + cells_[1]) % cells_[1],
                                cz = (cz0 + dz + cells_[2]) % cells_[2];
                    neighbourhoods_.push_back(static_cast<std::int32_t>(cx + cells_[0] * (cy + cells_[1] * cz)));
                  }
        cell_of_.resize(x.size());
        slot_.resize(x.size());
        for (std::size_t p = 0; p < x.size(); ++p)
          insert(static_cast<Index>(p), cell(x[p]));
      }

      void move(Index p, const Vec3 &to)
      {
        const Index c = cell(to);
        if (c == cell_of_[p])
          return;
        // remove by swapping with the last member of the old cell
        auto &old_members = members_[cell_of_[p]];
        const Index last = old_members.back();
        old_members[slot_[p]] = last;
        slot_[last] = slot_[p];
        old_members.pop_back();
        insert(p, c);
      }

      /// Calls visit(j) for every particle in the cells around x; a visit that returns true stops
      /// the walk (a hard-core overlap decides a trial move at once).
      template <class Visit>
      void for_each_near(const Vec3 &x, Visit &&visit) const
      {
        const std::int32_t *near = neighbourhoods_.data() + cell(x) * neighbourhood_size_;
        for (Index k = 0; k < neighbourhood_size_; ++k)
          for (const Index j : members_[near[k]])
            if constexpr (std::is_same_v<decltype(visit(j)), bool>)
            {
              if (visit(j))
                return;
            }
            else
              visit(j);
      }

    private:
      std::array<Index, 3> coordinates(const Vec3 &x) const
      {
        std::array<Index, 3> c{};
        for (int a = 0; a < 3; ++a)
          c[a] = std::clamp<Index>(static_cast<Index>(std::floor(x[a] / box_[a] * cells_[a])), 0, cells_[a] - 1);
        return c;
      }
      Index cell(const Vec3 &x) const
      {
        const auto c = coordinates(x);
        return c[0] + cells_[0] * (c[1] + cells_[1] * c[2]);
      }
      void insert(Index p, Index c)
      {
        cell_of_[p] = c;
        slot_[p] = static_cast<Index>(members_[c].size());
        members_[c].push_back(p);
      }

      Vec3 box_;
      std::array<Index, 3> cells_{};
      std::vector<std::vector<Index>> members_;
      Index neighbourhood_size_ = 0;               ///< cells around a cell, itself included
      std::vector<std::int32_t> neighbourhoods_;   ///< per cell, its neighbourhood's cell indices
      std::vector<Index> cell_of_, slot_;
    };

    /// The nearest image of d, the difference of two positions inside the box (|d_a| < L_a): one
    /// shift by a whole edge at most, the same as d_a - L_a nearbyint(d_a / L_a) without its
    /// division and rounding call (the sampler's innermost operation).
    Vec3 minimum_image(Vec3 d, const Vec3 &box)
    {
      for (int a = 0; a < 3; ++a)
      {
        if (d[a] > 0.5 * box[a])
          d[a] -= box[a];
        else if (d[a] < -0.5 * box[a])
          d[a] += box[a];
      }
      return d;
    }

    Vec3 wrap(Vec3 x, const Vec3 &box)
    {
      for (int a = 0; a < 3; ++a)
      {
        x[a] -= box[a] * std::floor(x[a] / box[a]);
        if (x[a] >= box[a])
          x[a] = 0;
      }
      return x;
    }

    /// Face-centred cubic sites scaled into the box (a hard-core-free start up to phi = 0.74): n of
    /// the 4 m_x m_y m_z sites of the smallest lattice that has enough, its cell counts in the ratio
    /// of the box's edges (m_a = max(1, round(t L_a / L_min)), t = 1, 2, ...; a cube has m^3 cells),
    /// taken at an even stride through the whole lattice (every site when n = 4 m_x m_y m_z). Filling the first n sites instead left the top
    /// layers empty whenever n < 4 m^3, and with strong stickiness the Monte Carlo does not relax a
    /// density gradient across the box within its sweeps: at N = 4096 (4 m^3 = 5324) the top fifth
    /// of the box held a third of its share of spheres after 5000 sweeps, and the bonds of two
    /// realizations in three did not reach the actuator (docs/work_precision.md).
    /// The closest two sites of an FCC lattice of m[a] cubic cells along each edge of `box`
    /// (periodic): half a face diagonal of the cell, or a whole cell edge where one cell spans the box.
    double fcc_nearest_sites(const std::array<Index, 3> &m, const Vec3 &box)
    {
      const Vec3 s(box[0] / m[0], box[1] / m[1], box[2] / m[2]);
      return std::min({0.5 * std::hypot(s[0], s[1]), 0.5 * std::hypot(s[0], s[2]), 0.5 * std::hypot(s[1], s[2]), s[0], s[1],
                       s[2]});
    }

    /// The FCC lattice's cells along each edge of `box`: as many along each edge as the edge is
    /// long, t times the shortest, for the smallest t that gives n sites (cells about cubic); unless
    /// its closest two sites are nearer than `diameter` (a flat box at high phi: 2 : 2 : 1 jumps from
    /// 432 to 1024 sites, and 469 spheres at phi = 0.49 would overlap), then the cell counts with at
    /// least n sites whose closest two sites are furthest apart.
    std::array<Index, 3> fcc_cells(Index n, const Vec3 &box, double diameter)
    {
      std::array<Index, 3> m{};
      for (Index t = 1;; ++t)
      {
        for (int a = 0; a < 3; ++a)
          m[a] = std::max<Index>(1, std::llround(t * box[a] / box.minCoeff()));
        if (4 * m[0] * m[1] * m[2] >= n)
          break;
      }
      if (fcc_nearest_sites(m, box) >= diameter)
        return m;
      // Around the cubic cell of n/4 cells in the box, each count a few cells either side.
      const double cell = std::cbrt(4 * box.prod() / static_cast<double>(n));
      std::array<Index, 3> best = m, low{}, high{};
      for (int a = 0; a < 3; ++a)
      {
        low[a] = std::max<Index>(1, static_cast<Index>(std::floor(box[a] / cell)) - 2);
        high[a] = static_cast<Index>(std::ceil(box[a] / cell)) + 2;
      }
      for (m[0] = low[0]; m[0] <= high[0]; ++m[0])
        for (m[1] = low[1]; m[1] <= high[1]; ++m[1])
          for (m[2] = low[2]; m[2] <= high[2]; ++m[2])
            if (4 * m[0] * m[1] * m[2] >= n && fcc_nearest_sites(m, box) > fcc_nearest_sites(best, box))
              best = m;
      return best;
    }

    /// n sites spread over the FCC lattice of fcc_cells: any n of them are at least its closest two
    /// sites apart (the caller checks the start against the spheres' diameter).
    std::vector<Vec3> fcc_start(Index n, const Vec3 &box, double diameter)
    {
      const std::array<Index, 3> m = fcc_cells(n, box, diameter);
      const Vec3 spacing(box[0] / m[0], box[1] / m[1], box[2] / m[2]);
      const std::array<Vec3, 4> basis = {Vec3(0, 0, 0), Vec3(0.5, 0.5, 0), Vec3(0.5, 0, 0.5), Vec3(0, 0.5, 0.5)};
      std::vector<Vec3> sites;
      for (Index k = 0; k < m[2]; ++k)
        for (Index j = 0; j < m[1]; ++j)
          for (Index i = 0; i < m[0]; ++i)
            for (const Vec3 &b : basis)
              sites.push_back(spacing.cwiseProduct(Vec3(i, j, k) + b + Vec3::Constant(0.25)));
      const auto total = static_cast<Index>(sites.size());
      std::vector<Vec3> x(n);
      for (Index q = 0; q < n; ++q)
        x[q] = sites[q * total / n];
      return x;
    }

    /// The rise of a history from the mean of its third quarter to the mean of its last, relative
    /// to the last, and the scatter of that rise at equilibrium: the larger of the points' own
    /// standard error (taken as independent) and 0.54 / sqrt(n). The coordination drifts slowly
    /// at equilibrium (correlated over more than 10 000 sweeps), so the points' own error
    /// understates it fivefold; 0.54 / sqrt(n) is the scatter measured for quarters of 5000 sweeps
    /// at n = 1024 (1.2 % per quarter, 1.7 % for their difference; (phi, tau) = (0.3, 0.178), sweeps
    /// 20 000-100 000), scaled as a fluctuation of n spheres.
    std::pair<double, double> relative_rise(const std::vector<double> &history, Index n)
    {
      const std::size_t quarter = history.size() / 4;
      if (quarter < 1)
        return {0.0, 0.0};
      const auto mean_and_variance = [&](std::size_t first) {
        double mean = 0, square = 0;
        for (std::size_t k = first; k < first + quarter; ++k)
          mean += history[k] / quarter;
        for (std::size_t k = first; k < first + quarter; ++k)
          square += (history[k] - mean) * (history[k] - mean);
        return std::make_pair(mean, quarter > 1 ? square / (quarter - 1) / quarter : 0.0);
      };
      const auto [third, third_variance] = mean_and_variance(history.size() - 2 * quarter);
      const auto [last, last_variance] = mean_and_variance(history.size() - quarter);
      if (!(last > 0))
        return {0.0, 0.0};
      const double equilibrium_scatter = 0.54 / std::sqrt(static_cast<double>(n));
      return {(last - third) / last, std::max(std::sqrt(third_variance + last_variance) / last, equilibrium_scatter)};
    }

    /// The sample has levelled off: its coordination rose by no more than the tolerance plus 1.5
    /// times the rise's scatter at equilibrium (SamplerSpec::equilibration_tolerance).
    bool levelled_off(const SamplerSpec &spec, double rise, double rise_error)
    {
      return !(spec.equilibration_tolerance > 0 && rise > spec.equilibration_tolerance + 1.5 * rise_error);
    }
  } // namespace

  SamplerReport sample_sticky_hard_spheres(DemSystem &system, const SamplerSpec &spec)
  {
    const auto fail = [](const std::string &what) { throw SetupError("sticky hard spheres: " + what); };
    if (spec.particle_count < 8)
      fail("particle count " + std::to_string(spec.particle_count) + " must be at least 8");
    if (!(spec.volume_fraction > 0 && spec.volume_fraction <= 0.55))
      fail("volume fraction " + std::to_string(spec.volume_fraction) +
           " outside (0, 0.55] (above, hard spheres crystallise)");
    if (!(spec.radius > 0))
      fail("radius must be positive");
    if (!(spec.well_width > 0 && spec.well_width <= 0.1))
      fail("well width " + std::to_string(spec.well_width) + " outside (0, 0.1] diameters");
    if (spec.sweeps < 1)
      fail("at least one sweep is needed");
    if (!(spec.sweep_extension_limit >= 1 && spec.sweep_extension_limit <= max_sweep_extension_limit))
      fail("sweep extension limit " + std::to_string(spec.sweep_extension_limit) + " outside [1, " +
           std::to_string(max_sweep_extension_limit) + "]");
    if (spec.material < 0 || spec.material >= system.materials.size())
      fail("material " + std::to_string(spec.material) + " is not defined");
    if (!(spec.cluster_move_fraction >= 0 && spec.cluster_move_fraction < 1))
      fail("cluster move fraction " + std::to_string(spec.cluster_move_fraction) + " outside [0, 1)");
    if (!(spec.aspect_ratios.minCoeff() > 0) || !spec.aspect_ratios.allFinite())
      fail("box aspect ratios must be finite and positive");
    if (!(spec.equilibration_tolerance >= 0))
      fail("equilibration tolerance " + std::to_string(spec.equilibration_tolerance) + " must be at least 0");
    if (spec.equilibration_tolerance > 0 && spec.sweeps < minimum_sweeps_to_judge_equilibrium)
      fail(std::to_string(spec.sweeps) + " sweeps are too few to tell whether the sample has levelled off (the "
           "coordination is recorded every 100 sweeps and its last two quarters are compared): give at least " +
           std::to_string(minimum_sweeps_to_judge_equilibrium) + " (DEM/Sample/Sweeps)");

    SamplerReport report;
    const double phi = spec.volume_fraction;
    report.stickiness =
      spec.target_coordination > 0 ? stickiness_for_coordination(phi, spec.target_coordination) : spec.stickiness;
    report.percus_yevick_coordination = percus_yevick_coordination(phi, report.stickiness); // checks tau_min

    const Index n = spec.particle_count;
    const double sigma = 2 * spec.radius;
    const double range = sigma * (1 + spec.well_width);
    // Edges in the ratio of spec.aspect_ratios, their product the volume n v / phi.
    const Vec3 box = spec.aspect_ratios * std::cbrt(n * sphere_volume(spec.radius) / phi / spec.aspect_ratios.prod());
    report.box_lengths = box;
    // Boltzmann factor of one contact, from the matched second virial coefficient.
    const double contact_weight =
      1 + 1 / (4 * report.stickiness * (std::pow(1 + spec.well_width, 3) - 1));

    std::vector<Vec3> x = fcc_start(n, box, sigma);
    PeriodicCells cells(box, range, x);
    std::mt19937_64 rng(spec.seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::uniform_int_distribution<Index> pick(0, n - 1);

    // Number of partners in the well around position y, skipping particle `self`; -1 on overlap.
    const auto partners = [&](const Vec3 &y, Index self) {
      Index count = 0;
      bool overlap = false;
      cells.for_each_near(y, [&](Index j) {
        if (j == self)
          return false;
        const double d2 = minimum_image(x[j] - y, box).squaredNorm();
        if (d2 < sigma * sigma)
          overlap = true;
        else if (d2 < range * range)
          ++count;
        return overlap;
      });
      return overlap ? Index(-1) : count;
    };
    // Hard spheres never overlap: not at the start (the moves keep it so), whose lattice may be too
    // tight for n spheres in a flat box at high phi.
    for (Index i = 0; i < n; ++i)
      if (partners(x[i], i) < 0)
        fail("cannot start " + std::to_string(n) + " spheres at phi = " + std::to_string(phi) + " in a box of " +
             std::to_string(box[0]) + " x " + std::to_string(box[1]) + " x " + std::to_string(box[2]) +
             " m without overlaps (the start's FCC lattice is too tight in this box): lower the volume fraction or "
             "change the box's aspect ratios");

    // Two kinds of trial move, each in detailed balance on its own, mixed half and half:
    //  - a displacement by up to `step` in each direction (the step adapts towards 40 % acceptance in
    //    the first half of the sweeps and is frozen in the second half, where the statistics are);
    //  - an aggregation-volume-bias move (Chen & Siepmann 2000, AVBMC1), which makes and breaks
    //    contacts far faster in a narrow well: pick a partner j, then with probability 1/2 move i
    //    into j's well shell (volume V_in), otherwise out of it (anywhere else in the box, V_out);
    //    a move "in" when i is already in (or "out" when already out) is rejected, and acceptance
    //    carries the volume ratio V_in / V_out (in) or V_out / V_in (out). V_out is the region the
    //    "out" move draws from and an "in" move can start from: the box minus j's shell AND j's core
    //    (hard core: i is never there), V_out = L_x L_y L_z - 4/3 pi range^3.
    const double shell_volume = 4.0 / 3.0 * M_PI * (range * range * range - sigma * sigma * sigma);
    const double outside_volume = box.prod() - 4.0 / 3.0 * M_PI * range * range * range;
    const auto random_direction = [&]() {
      const double cos_theta = 2 * unit(rng) - 1, azimuth = 2 * M_PI * unit(rng);
      const double sin_theta = std::sqrt(1 - cos_theta * cos_theta);
      return Vec3(sin_theta * std::cos(azimuth), sin_theta * std::sin(azimuth), cos_theta);
    };
    const auto in_shell_of = [&](const Vec3 &y, Index j) {
      const double d2 = minimum_image(y - x[j], box).squaredNorm();
      return d2 >= sigma * sigma && d2 < range * range;
    };
    double step = 0.1 * sigma;
    Index accepted = 0, tried = 0;

    // Cluster moves (opt-in, a fraction `cluster_move_fraction` of the trials; the detailed-balance
    // argument is in the header): the spheres linked to a random sphere p, each pair in the well
    // linked with probability 1 - 1/contact_weight (drawn while the cluster grows, each pair at most
    // once), are translated rigidly by a vector uniform in a cube of half-width `cluster_step`; the
    // move is accepted unless a moved sphere overlaps a sphere that stays. Clusters that wrap around
    // the periodic box or have more than `largest_moved_cluster` spheres are not moved.
    const double cluster_fraction = spec.cluster_move_fraction;
    const double link_probability = 1 - 1 / contact_weight;
    const std::size_t largest_moved_cluster = 16;
    std::vector<char> member(cluster_fraction > 0 ? n : 0, 0);
    std::vector<Vec3> unwrapped(cluster_fraction > 0 ? n : 0);
    std::vector<Index> cluster;
    std::vector<Vec3> moved;
    double cluster_step = 0.1 * sigma;
    Index cluster_accepted = 0, cluster_tried = 0;
    // 0: the cluster wraps or is too large (not moved), 1: the translation overlaps, 2: accepted.
    const auto cluster_move = [&]() -> int {
      const Index p = pick(rng);
      cluster.assign(1, p);
      member[p] = 1;
      unwrapped[p] = x[p];
      bool reject = false;
      for (std::size_t q = 0; q < cluster.size() && !reject; ++q)
      {
        const Index i = cluster[q];
        cells.for_each_near(x[i], [&](Index j) {
          if (j == i || reject)
            return;
          const Vec3 d = minimum_image(x[j] - x[i], box);
          if (d.squaredNorm() >= range * range)
            return;
          if (member[j])
          {
            // the pair closes a loop: through another periodic image, the cluster wraps
            if ((unwrapped[i] + d - unwrapped[j]).squaredNorm() > 0.25 * box.minCoeff() * box.minCoeff())
              reject = true;
            return;
          }
          if (unit(rng) >= link_probability)
            return; // not linked: j stays, whatever the move does to the pair
          member[j] = 1;
          unwrapped[j] = unwrapped[i] + d;
          cluster.push_back(j);
          if (cluster.size() > largest_moved_cluster)
            reject = true; // too large to move: nearly always blocked, and costly to grow
        });
      }
      bool accept = !reject;
      if (accept)
      {
        Vec3 v;
        for (int a = 0; a < 3; ++a)
          v[a] = cluster_step * (2 * unit(rng) - 1);
        moved.resize(cluster.size());
        for (std::size_t k = 0; k < cluster.size() && accept; ++k)
        {
          moved[k] = wrap(x[cluster[k]] + v, box);
          cells.for_each_near(moved[k], [&](Index j) {
            if (accept && !member[j] && minimum_image(x[j] - moved[k], box).squaredNorm() < sigma * sigma)
              accept = false;
          });
        }
      }
      if (accept)
        for (std::size_t k = 0; k < cluster.size(); ++k)
        {
          cells.move(cluster[k], moved[k]);
          x[cluster[k]] = moved[k];
        }
      for (const Index i : cluster)
        member[i] = 0;
      return reject ? 0 : accept ? 2 : 1;
    };

    // The sweeps to run: `sweeps`, extended by as many again at a time while the sample has not
    // levelled off, up to the extension limit (SamplerSpec::sweep_extension_limit). Whole `sweeps`
    // at a time: the check compares quarters of the whole history, so each extension also lengthens
    // the windows it judges by, rather than re-judging a sample a few hundred sweeps later.
    Index planned_sweeps = spec.sweeps;
    const Index sweep_limit = static_cast<Index>(std::ceil(spec.sweep_extension_limit * static_cast<double>(spec.sweeps)));
    for (Index sweep = 0; sweep < planned_sweeps; ++sweep)
    {
      Index sweep_accepted = 0, sweep_displacements = 0, displacements_accepted = 0;
      Index sweep_cluster_tried = 0, sweep_cluster_accepted = 0, sweep_cluster_translations = 0;
      for (Index t = 0; t < n; ++t)
      {
        if (cluster_fraction > 0 && unit(rng) < cluster_fraction)
        {
          ++sweep_cluster_tried;
          const int outcome = cluster_move();
          sweep_cluster_translations += outcome > 0;
          if (outcome == 2)
          {
            ++sweep_cluster_accepted;
            ++sweep_accepted;
          }
          continue;
        }
        const Index p = pick(rng);
        Vec3 trial;
        double bias = 1; // proposal-volume ratio of the move
        const bool displacement = unit(rng) < 0.5;
        if (displacement)
        {
          ++sweep_displacements;
          trial = wrap(x[p] + step * Vec3(2 * unit(rng) - 1, 2 * unit(rng) - 1, 2 * unit(rng) - 1), box);
        }
        else
        {
          Index j = pick(rng);
          if (j == p)
            continue;
          const bool into = unit(rng) < 0.5;
          if (in_shell_of(x[p], j) == into)
            continue; // AVBMC1: "in" only from outside j's shell, "out" only from inside
          if (into)
          {
            const double r = std::cbrt(sigma * sigma * sigma + unit(rng) * (range * range * range - sigma * sigma * sigma));
            trial = wrap(x[j] + r * random_direction(), box);
            bias = shell_volume / outside_volume;
          }
          else
          {
            do
              trial = Vec3(unit(rng), unit(rng), unit(rng)).cwiseProduct(box);
            while (in_shell_of(trial, j) || minimum_image(trial - x[j], box).squaredNorm() < sigma * sigma);
            bias = outside_volume / shell_volume;
          }
        }
        const Index after = partners(trial, p);
        const double u = unit(rng);
        if (after < 0)
          continue;
        const Index before = partners(x[p], p);
        if (u < bias * std::pow(contact_weight, static_cast<double>(after - before)))
        {
          cells.move(p, trial);
          x[p] = trial;
          ++sweep_accepted;
          displacements_accepted += displacement;
        }
      }
      if ((sweep + 1) % 100 == 0)
      {
        Index pairs = 0;
        for (Index i = 0; i < n; ++i)
          pairs += partners(x[i], i);
        report.coordination_history.push_back(static_cast<double>(pairs) / n);
      }
      if (2 * sweep < spec.sweeps)
      {
        const double rate =
          sweep_displacements > 0 ? static_cast<double>(displacements_accepted) / sweep_displacements : 0.4;
        step = std::clamp(step * (rate > 0.4 ? 1.05 : 0.95), 1e-4 * sigma, 0.5 * sigma);
        if (sweep_cluster_translations > 0)
        {
          const double cluster_rate = static_cast<double>(sweep_cluster_accepted) / sweep_cluster_translations;
          cluster_step = std::clamp(cluster_step * (cluster_rate > 0.4 ? 1.05 : 0.95), 1e-4 * sigma, 0.5 * sigma);
        }
      }
      else
      {
        accepted += sweep_accepted;
        tried += n;
        cluster_accepted += sweep_cluster_accepted;
        cluster_tried += sweep_cluster_tried;
      }
      if (sweep + 1 == planned_sweeps && planned_sweeps < sweep_limit)
      {
        const auto [rise, rise_error] = relative_rise(report.coordination_history, n);
        if (!levelled_off(spec, rise, rise_error))
          planned_sweeps = std::min(sweep_limit, planned_sweeps + spec.sweeps);
      }
    }
    report.sweeps = planned_sweeps;
    report.acceptance = tried > 0 ? static_cast<double>(accepted) / tried : 0;
    report.cluster_acceptance = cluster_tried > 0 ? static_cast<double>(cluster_accepted) / cluster_tried : 0;

    const double bond_probability = 1 - 1 / contact_weight;
    // Contact graph with the image offset of each edge, clusters and percolation (a cluster that
    // reaches a particle through two different periodic images wraps around the box).
    std::vector<std::vector<std::pair<Index, std::array<int, 3>>>> adjacent(n);
    for (Index i = 0; i < n; ++i)
      cells.for_each_near(x[i], [&](Index j) {
        if (j <= i)
          return;
        const Vec3 d = x[j] - x[i];
        const Vec3 image = minimum_image(d, box);
        if (image.squaredNorm() < range * range)
        {
          ++report.well_pairs;
          if (unit(rng) >= bond_probability)
            return; // a hard-sphere pair that happens to be close, not an adhesive contact
          std::array<int, 3> k{};
          for (int a = 0; a < 3; ++a)
            k[a] = static_cast<int>(std::nearbyint((image[a] - d[a]) / box[a])); // j + k box is next to i
          adjacent[i].push_back({j, k});
          adjacent[j].push_back({i, {-k[0], -k[1], -k[2]}});
          report.bonded_pairs.emplace_back(i, j);
          ++report.contacts;
        }
      });
    report.coordination = 2.0 * report.contacts / n;
    std::vector<char> seen(n, 0);
    std::vector<std::array<int, 3>> offset(n);
    Index largest = 0;
    for (Index start = 0; start < n; ++start)
    {
      if (seen[start])
        continue;
      std::vector<Index> queue = {start};
      seen[start] = 1;
      offset[start] = {0, 0, 0};
      bool wraps = false;
      for (std::size_t q = 0; q < queue.size(); ++q)
      {
        const Index i = queue[q];
        for (const auto &[j, k] : adjacent[i])
        {
          const std::array<int, 3> o = {offset[i][0] + k[0], offset[i][1] + k[1], offset[i][2] + k[2]};
          if (!seen[j])
          {
            seen[j] = 1;
            offset[j] = o;
            queue.push_back(j);
          }
          else if (offset[j] != o)
            wraps = true;
        }
      }
      if (static_cast<Index>(queue.size()) > largest)
      {
        largest = static_cast<Index>(queue.size());
        report.percolating = wraps;
      }
    }
    report.largest_cluster_fraction = static_cast<double>(largest) / n;
    if (spec.require_percolation && !report.percolating)
    {
      std::ostringstream why;
      why << "sticky hard spheres: the sample does not percolate at phi = " << spec.volume_fraction
          << ", tau = " << report.stickiness << " (z = " << 2.0 * static_cast<double>(report.contacts) / n
          << " bonded partners per sphere; the largest cluster holds " << 100 * report.largest_cluster_fraction
          << " % of the spheres and does not wrap around the periodic box). A non-percolating sample carries "
             "no load (Ritter et al. 2020): raise the coordination number (lower tau) or the volume fraction";
      throw SetupError(why.str());
    }
    std::tie(report.coordination_rise, report.coordination_rise_error) = relative_rise(report.coordination_history, n);
    if (!levelled_off(spec, report.coordination_rise, report.coordination_rise_error))
    {
      std::ostringstream why;
      why << "sticky hard spheres: the sample has not levelled off after " << report.sweeps << " sweeps"
          << (report.sweeps > spec.sweeps ? " (DEM/Sample/Sweeps, extended up to DEM/Sample/Sweep extension limit)" : "")
          << ": its coordination (partners in the well per sphere) still rose by "
          << 100 * report.coordination_rise << " % (+- " << 100 * report.coordination_rise_error
          << " % at equilibrium) from the third to the last quarter of the sweeps, more than the tolerance of "
          << 100 * spec.equilibration_tolerance
          << " % (DEM/Sample/Equilibration tolerance) plus 1.5 times that scatter. The start is an unbonded lattice: such a sample is less "
             "bonded than the fluid at phi = "
          << spec.volume_fraction << ", tau = " << report.stickiness
          << ", and its strength is biased low (about 4 % per 1 % of z). Raise DEM/Sample/Sweeps or DEM/Sample/Sweep "
             "extension limit (at phi = 0.3, z = 2.9: 20 000 for up to 2048 spheres, more in larger boxes and looser "
             "samples; docs/work_precision.md)";
      throw SetupError(why.str());
    }

    system.domain.lower = Vec3::Zero();
    system.domain.upper = box;
    system.domain.periodic = {true, true, true};
    const double density = system.materials[spec.material].density;
    const Index first = system.particles.size();
    for (const Vec3 &y : x)
      system.particles.add_sphere(y, spec.radius, density, spec.material);
    for (auto &[i, j] : report.bonded_pairs)
    {
      i += first;
      j += first;
    }
    report.volume_fraction = n * sphere_volume(spec.radius) / box.prod();
    return report;
  }
} // namespace anticrack::dem::shs
