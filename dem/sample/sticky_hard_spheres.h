// Baxter's sticky hard spheres (SHS): the Percus-Yevick relations between volume fraction phi,
// stickiness tau (smaller = stickier) and mean coordination number z (docs/physics.md §1.4; Baxter 1968,
// J. Chem. Phys. 49:2770; Seaton & Glandt 1987, J. Chem. Phys. 86:4668). The sampler that builds
// SHS samples uses them to pick tau for a target z and to refuse unphysical requests.
//
//   lambda: smaller root of (phi/12) lambda^2 - (tau + phi/(1-phi)) lambda + (1 + phi/2)/(1-phi)^2 = 0
//   z = 2 phi lambda
//   tau_min(phi) = (14 phi^2 - 4 phi - 1) / (12 (2 phi^2 - phi - 1))
#pragma once

#include "dem/core/system.h"

#include <cstdint>
#include <utility>
#include <vector>

namespace anticrack::dem::shs
{
  /// Lower bound of the admissible stickiness at volume fraction phi (0 < phi < 1).
  double minimum_stickiness(double phi);

  /// Percus-Yevick lambda(phi, tau); throws SetupError (naming phi and tau and the admissible range)
  /// when tau < tau_min(phi) or the relation has no real root.
  double percus_yevick_lambda(double phi, double tau);

  /// Mean coordination number z = 2 phi lambda of the Percus-Yevick SHS fluid.
  double percus_yevick_coordination(double phi, double tau);

  /// The stickiness tau that gives the coordination number z at volume fraction phi (the PY relation
  /// solved for tau: tau = ((phi/12) lambda^2 + (1 + phi/2)/(1-phi)^2) / lambda - phi/(1-phi) with
  /// lambda = z/(2 phi), on the branch where lambda is the smaller root); throws SetupError when z is
  /// not reachable with tau >= tau_min(phi).
  double stickiness_for_coordination(double phi, double z);
} // namespace anticrack::dem::shs

namespace anticrack::dem::shs
{
  /// Monte Carlo sampling of adhesive hard spheres in a periodic box (a cube unless its aspect
  /// ratios say otherwise: a layer is wider than it is thick). Baxter's infinitely narrow
  /// and deep well is represented by its square-well limit: a well of width delta (relative to the
  /// diameter sigma) and depth eps with the same second virial coefficient,
  ///   ((1 + delta)^3 - 1) (exp(eps/kT) - 1) = 1 / (4 tau)     (B2 = B2_HS (1 - 1/(4 tau))),
  /// sampled by Metropolis single-particle moves that form and break contacts (acceptance
  /// min(1, exp(eps/kT)^(n_new - n_old)) for hard-core-free trials). A pair inside the well carries
  /// the weight exp(eps/kT) = 1 + (exp(eps/kT) - 1): the 1 is a hard-sphere pair that happens to be
  /// close, the rest Baxter's adhesion; each pair in the well is therefore bonded with probability
  /// 1 - exp(-eps/kT), and only bonded pairs count as contacts. (Counting every pair in the well
  /// would add 8 phi ((1+delta)^3 - 1) g(sigma) to z, which does not vanish with the stickiness;
  /// with the draw, dilute samples give z = 2 phi / tau, Baxter's low-density limit.) As delta -> 0 the model is Baxter's: at (phi, tau) = (0.3, 0.2) the
  /// coordination number is the same (2.81) for delta = 0.02 and 0.03 after 5000 sweeps, 3 % above
  /// Percus-Yevick (before levelling off: at tau = 0.178 the levelled chain is 4 % above PY).
  /// Aggregation-volume-bias moves help contacts form, but the bonded network still rearranges
  /// slowly: at (0.3, 0.178) z levels off after 15 000-20 000 sweeps, longer in larger boxes, and
  /// (0.4, 0.1) needs ~1e4 sweeps or more; `equilibration_tolerance` refuses a sample that has not.
  ///
  /// Cluster moves (opt-in: `cluster_move_fraction` > 0 of the trial moves; 0 leaves the random
  /// stream and every sample exactly as without them). Swendsen-Wang construction on Baxter's bond
  /// picture above: write the weight of a configuration as w^n_well = prod over well pairs of
  /// (1 + (w - 1)), w = exp(eps/kT), i.e. each pair in the well is linked with probability
  /// p = 1 - 1/w, independently. A cluster move
  ///   1. picks a sphere uniformly and grows its cluster C: from each member, every sphere in its well
  ///      that is not yet a member is linked with probability p (each pair drawn at most once), so
  ///      P(C | x) = f(C) (1 - p)^b(x), where b(x) counts the well pairs between C and the rest and
  ///      f depends only on the pairs inside C;
  ///   2. rejects (leaves x) when C wraps around the periodic box (a well pair inside C whose minimum
  ///      image disagrees with the unwrapped positions along the links) or has more than 16 spheres
  ///      (growth stops there; such clusters are nearly always blocked and costly to grow);
  ///   3. translates C rigidly by v uniform in [-s, s]^3 (s adapted in the first half of the sweeps
  ///      like the single-sphere step, frozen in the second) and accepts unless a moved sphere
  ///      overlaps one that stays. Well pairs between C and the rest may form and break freely.
  /// Detailed balance: a translation keeps every distance inside C, so the reverse move (any sphere
  /// of C picked, same link draws inside C, all b(x') boundary pairs unlinked, -v) grows the same C,
  /// with the same wrap/size verdict; the pick (|C|/N) and v are symmetric. Hence
  ///   pi(x) T(x -> x') / (pi(x') T(x' -> x)) = w^(n(x) - n(x')) (1 - p)^(b(x) - b(x')) = 1,
  /// because n(x) - n(x') = b(x) - b(x') (pairs inside C and among the rest do not change) and
  /// 1 - p = 1/w; the acceptance is 1 for every hard-core-free trial. Only translations: a rotation
  /// would need the cluster's minimum-image distances checked as well.
  /// Benefit (N = 500, fraction 0.2): early aggregation ~1.5-2x faster per sweep at (0.3, 0.2), about
  /// even per CPU second (cluster moves cost ~2.5x per sweep); none at (0.4, 0.1), where the bonded
  /// network spans the box within ~100 sweeps and a spanning cluster is never moved (cluster
  /// acceptance ~2e-4): the slow creep there is restructuring inside the network.
  /// Fewest sweeps whose coordination history (a point every 100 sweeps) has two quarters to
  /// compare: the equilibration check needs them (SamplerSpec::equilibration_tolerance).
  inline constexpr Index minimum_sweeps_to_judge_equilibrium = 400;
  /// The largest SamplerSpec::sweep_extension_limit: a sample still rising after 10 times its sweeps
  /// needs a better start or more sweeps, not a longer wait.
  inline constexpr double max_sweep_extension_limit = 10;

  struct SamplerSpec
  {
    Index particle_count = 2048;
    double volume_fraction = 0.3;     ///< phi
    double stickiness = 0.2;          ///< tau (ignored when target_coordination > 0)
    double target_coordination = 0;   ///< z; > 0 selects tau from the Percus-Yevick relation
    double radius = 1e-4;             ///< sphere radius [m]; the box's edges follow from phi
    /// The box's edges in x, y, z relative to each other (> 0); their size follows from N, phi and
    /// the radius. (1, 1, 1): a cube.
    Vec3 aspect_ratios = Vec3::Ones();
    double well_width = 0.03;         ///< delta / sigma
    Index sweeps = 20000;             ///< Monte Carlo sweeps (N trial moves each)
    /// A sample that has not levelled off after `sweeps` (`equilibration_tolerance`) runs on,
    /// `sweeps` more at a time, until it has or until it has run this many times `sweeps` in all;
    /// >= 1, 1: exactly `sweeps`. The criterion, not the count, decides when a sample is done: a
    /// looser sample (lower phi, fewer collisions per sweep) levels off later than the count that a
    /// denser one was measured to need. A sample that levels off within `sweeps` is the same bit for
    /// bit whatever the limit.
    double sweep_extension_limit = 1;
    int material = 0;
    std::uint64_t seed = 1;
    double cluster_move_fraction = 0; ///< fraction of trial moves that are cluster moves, in [0, 1)
    /// Refuse (SetupError) a sample whose largest bonded cluster does not wrap around the box: it
    /// would carry no load. false only for studies of the fluid itself (dilute-limit checks).
    bool require_percolation = true;
    /// Refuse (SetupError) a sample that has not levelled off: the well-pair coordination (the
    /// `coordination_history`) rose from the mean of the third quarter of the sweeps to the mean of
    /// the last by more than this fraction of it plus 1.5 times the rise's scatter at equilibrium
    /// (`coordination_rise_error`: 1.7 % at N = 1024, as 1/sqrt(N)). The start is an unbonded
    /// lattice, so an unequilibrated sample is always less bonded than the fluid it stands for, and
    /// the DEM strength rises by about 4 % per 1 % of z (docs/work_precision.md). A guard against
    /// gross cases, not a proof of equilibrium: one chain that fluctuates this slowly cannot tell a
    /// creep of a few percent from its own drift. At (phi, z) = (0.3, 2.9), N = 1024, it refuses
    /// 2000 sweeps (5.4 % rise) and passes 5000 (2.2 %, 7 % below equilibrium); the sweeps a
    /// sample needs are measured, not detected (20 000 up to 2048 spheres, 40 000 for 4096 in a
    /// 4 x 4 x 1 layer). Needs 400 sweeps or more. 0: not checked (studies of the sampler itself).
    double equilibration_tolerance = 0.015;
  };

  struct SamplerReport
  {
    double volume_fraction = 0;       ///< of the placed spheres (exact by construction)
    double stickiness = 0;            ///< tau used
    double percus_yevick_coordination = 0;
    double coordination = 0;          ///< mean number of bonded partners, z = 2 bonds / N
    Index contacts = 0;               ///< bonded pairs (Baxter contacts)
    Index well_pairs = 0;             ///< pairs inside the well, bonded or not
    std::vector<std::pair<Index, Index>> bonded_pairs; ///< particle ids (i < j) in the system
    double acceptance = 0;            ///< of the last sweeps' moves (cluster moves included)
    double cluster_acceptance = 0;    ///< of the last sweeps' cluster moves, wrapping/too-large
                                      ///< clusters included (0 without cluster moves)
    double largest_cluster_fraction = 0;
    bool percolating = false;         ///< the largest cluster wraps around the periodic box
    Vec3 box_lengths = Vec3::Zero();  ///< the periodic box's edges [m]
    std::vector<double> coordination_history; ///< partners in the well per sphere (2 well pairs / N,
                                              ///< not the bonded z) every 100 sweeps (equilibration check)
    /// Relative rise of the well-pair coordination from the third to the last quarter of the
    /// sweeps, (mean Q4 - mean Q3) / mean Q4, and its scatter at equilibrium (both 0 with fewer
    /// than 4 points).
    double coordination_rise = 0;
    double coordination_rise_error = 0;
    Index sweeps = 0;                 ///< run in all (`sweeps`, or more when extended)
  };

  /// Samples the fluid, appends the spheres to `system` (domain set to the periodic box) and
  /// returns the statistics; bonds are made by the caller: bond_touching_pairs with a gap tolerance
  /// of 2 delta (the well width in radii) restricted to report.bonded_pairs. Throws SetupError for
  /// tau < tau_min(phi) or bad input.
  SamplerReport sample_sticky_hard_spheres(DemSystem &system, const SamplerSpec &spec);
} // namespace anticrack::dem::shs
