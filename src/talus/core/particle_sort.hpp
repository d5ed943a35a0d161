// Particles sorted by cell within each body: the order that every process's share and the one
// process's solver share, so that one process's particle order is reproduced on any count.
#pragma once

#include "talus/core/grid.hpp"
#include "talus/core/particles.hpp"

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <vector>

namespace talus {

// The order (new place -> old index) that sorts the particles at x by cell index, stably,
// within each body's range [body_begin[b], body_begin[b + 1]).
template <int D>
std::vector<std::uint32_t> order_by_cell(const Grid<D>& G, const std::vector<Vec<D>>& x,
                                         const std::vector<std::size_t>& body_begin) {
  std::vector<std::int64_t> key(x.size());
  for (std::size_t p = 0; p < x.size(); ++p)
    key[p] = G.cell_index(G.cell_of(x[p]));
  std::vector<std::uint32_t> order(x.size());
  std::iota(order.begin(), order.end(), 0u);
  for (std::size_t b = 0; b + 1 < body_begin.size(); ++b)
    std::stable_sort(order.begin() + body_begin[b], order.begin() + body_begin[b + 1],
                     [&](std::uint32_t i, std::uint32_t j) { return key[i] < key[j]; });
  return order;
}

// a[i] <- a[order[i]] in place, one cycle of the permutation at a time: no copy of the array
// (a copy of the largest, the stress, would be the peak of the memory), one byte per element of
// marks in `done`.
template <class T>
void permute(std::vector<T>& a, const std::vector<std::uint32_t>& order, std::vector<char>& done) {
  done.assign(a.size(), 0);
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (done[i]) continue;
    T first = a[i];
    std::size_t j = i;
    while (true) {
      done[j] = 1;
      const std::size_t k = order[j];
      if (k == i) {
        a[j] = first;
        break;
      }
      a[j] = a[k];
      j = k;
    }
  }
}

// Every per-particle array of P put in `order` (order_by_cell); body_begin stays.
template <int D>
void apply_order(Particles<D>& P, const std::vector<std::uint32_t>& order) {
  std::vector<char> done;
  P.for_each_array([&](auto& a) { permute(a, order, done); });
  P.for_each_optional([&](auto& a) {
    if (!a.empty()) permute(a, order, done);
  });
}

} // namespace talus
