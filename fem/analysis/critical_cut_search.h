// The critical cut as PST practice reads it (docs/fem.md "The critical cut"): the shortest cut from
// which the test ends by itself, the saw stopped: the crack runs through the weak layer by itself,
// or the slab breaks. Found by fixed-cut trials (each cut made before the gravity ramp, then
// followed in time to its outcome) that bracket it to a resolution. No saw speed enters, and a
// trial's answer (ends the test or not) is read after the fact, not at a threshold of a moving saw.
//
// bracket_critical_cut() is the search alone (no FE): it asks `ends_test(cut)` and keeps what it
// learns. The trials of a PST (PST/Saw = bisection or practice) are run by
// run_critical_cut_search(), fem/analysis/critical_cut_search.cpp.
#pragma once

#include "fem/analysis/snowpack_run.h"

#include <functional>
#include <optional>
#include <vector>

namespace anticrack::fem
{
  /// One fixed-cut trial: its cut and whether the test ended from it (the crack ran, or the slab broke).
  struct CutTrial
  {
    double cut_length = 0;
    bool ends_test = false;
  };

  /// What the trials found: the longest cut that held (0 when none was tried: the intact column,
  /// which the gravity equilibrium holds), the shortest that ended the test (none when no cut up
  /// to the longest did), and every trial in the order run.
  struct CutBracket
  {
    double longest_holding = 0;
    std::optional<double> shortest_ending;
    std::vector<CutTrial> trials;
  };

  /// Brackets the critical cut to `resolution` by trials in (0, longest]. With a `seed` (a cut near
  /// the answer, e.g. where an advancing saw's crack ran), the first trial is there and the next
  /// ones step away from it by resolution, 2 resolution, 4 ... until the answer changes, then
  /// bisect: a few trials when the seed is close. Without, the first trial is `longest` (which must
  /// end the test) and the bracket (0, longest] is bisected. The answer is monotone in the cut (a
  /// longer cut loads the layer more), which the search assumes and does not test: a cut that ends
  /// the test above one that holds is the bracket, whatever the trials between them would say.
  /// Throws std::invalid_argument unless 0 < resolution and 0 < longest.
  CutBracket bracket_critical_cut(std::optional<double> seed, double longest, double resolution,
                                  const std::function<bool(double)> &ends_test);

  /// One run of the dynamic PST in time with the scene's saw, or, given a preloaded cut, a
  /// fixed-cut trial: the column cut by that much before the gravity ramp (fem/analysis/dynamic_pst.cpp).
  using PstInTime =
    std::function<Json(const SnowpackScene &, const SnowpackRunOptions &, std::optional<double> preloaded_cut)>;

  /// PST/Saw = bisection or practice: the trials (in DIR/fixed_cuts/cut_A/, each with its own
  /// series and fields, and its results.json once complete, from which a run with --resume skips
  /// it), seeded for practice by an advancing saw run (DIR/saw/). The results are the shortest
  /// ending trial's (outcome, speed, arrest, slab fracture), with the bracket, the trials and, for
  /// practice, the saw's onset of the tip's lead. Collective over `comm`.
  Json run_critical_cut_search(const SnowpackScene &scene, const SnowpackRunOptions &options, MPI_Comm comm,
                               const PstInTime &run_in_time);
} // namespace anticrack::fem
