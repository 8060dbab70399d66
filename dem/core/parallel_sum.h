// Sums over a range whose result does not depend on the number of threads. OpenMP's reduction
// clause adds per-thread partial sums, whose grouping (and so the round-off) changes with the
// thread count; here the range is cut into fixed blocks, each block is summed in order by one
// thread, and the block sums are added in order. Energies and dissipation then come out bit for
// bit the same with 1 or N threads, like the trajectories. Hot loops use FixedBlocks and
// add_in_order directly (their bodies stay in the calling function, where the compiler keeps the
// arrays' pointers in registers); others call thread_independent_sum.
#pragma once

#include "dem/common/types.h"

#include <algorithm>
#include <array>
#include <vector>

namespace anticrack::dem
{
  /// [0, n) cut into blocks of a fixed size.
  struct FixedBlocks
  {
    static constexpr Index size = 128; // small enough to balance two threads on ~1000 items
    Index n;
    explicit FixedBlocks(Index range) : n(range) {}
    [[nodiscard]] Index count() const { return (n + size - 1) / size; }
    [[nodiscard]] Index begin(Index block) const { return block * size; }
    [[nodiscard]] Index end(Index block) const { return std::min(n, (block + 1) * size); }
  };

  /// Adds per-block partial sums in block order.
  template <std::size_t K>
  std::array<double, K> add_in_order(const std::vector<std::array<double, K>> &partial)
  {
    std::array<double, K> total{};
    for (const auto &sums : partial)
      for (std::size_t k = 0; k < K; ++k)
        total[k] += sums[k];
    return total;
  }

  /// Calls body(i, sums) for every i in [0, n) (in parallel) and returns the K sums.
  template <std::size_t K, class Body>
  std::array<double, K> thread_independent_sum(Index n, Body &&body)
  {
    const FixedBlocks blocks(n);
    std::vector<std::array<double, K>> partial(blocks.count());
#pragma omp parallel for schedule(static)
    for (Index b = 0; b < blocks.count(); ++b)
    {
      std::array<double, K> sums{};
      for (Index i = blocks.begin(b); i < blocks.end(b); ++i)
        body(i, sums);
      partial[b] = sums;
    }
    return add_in_order(partial);
  }
} // namespace anticrack::dem
