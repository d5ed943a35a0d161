// Exchange: the points of a time step where a process that holds one slab of the particles (and
// ghost copies of its neighbours' particles within reach, parallel/distributed.hpp) agrees with
// the other processes. Simulation calls it when it has one (set_exchange); on one process it has
// none and every sum is local. Each call gives every process the same bits, whatever the number
// of processes: a min or max, or a sum in which each entry has exactly one contributor.
#pragma once

#include "talus/core/exact_sum.hpp"

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace talus {

class Exchange {
public:
  virtual ~Exchange() = default;
  // Whether particle p of the share is this process's own (not a ghost copy of another's).
  virtual bool is_own(std::size_t p) const = 0;
  // Particle p's index in one process's particle order (its global index).
  virtual std::size_t global_index(std::size_t p) const = 0;
  // The largest of every process's value.
  virtual double max(double local) = 0;
  // Elementwise: lo[i] <- min over the processes, hi[i] <- max.
  virtual void min_max(double* lo, double* hi, int n) = 0;
  // Whether this process owns node plane i (x index): its rows of the contact record count.
  virtual bool owns_plane(std::int64_t i) const = 0;
  // The node planes [lo, hi) whose sums this process's particles can complete: beyond them a
  // node lacks particles that only other processes hold, so node passes may skip it.
  virtual void plane_reach(std::int64_t& lo, std::int64_t& hi) const = 0;
  // data[i] <- the sum over the processes, where at most one process holds a nonzero entry i
  // (so the sum is that entry, exactly).
  virtual void sum_disjoint(double* data, std::size_t n) = 0;
  // sums[i] <- the sum over the processes of every process's sums[i]: exact, so in any order.
  virtual void sum_exact(ExactSum* sums, std::size_t n) = 0;
  // data[i] <- the sum over the processes of every process's data[i]: integers, so exact in any
  // order (the caller keeps the totals within 63 bits).
  virtual void sum_integers(std::int64_t* data, std::size_t n) = 0;
  // Throws SimulationError on every process with the lowest failing process's message (`failure`
  // on each: empty where it did not fail); returns if none failed. A check that may fail on one
  // process alone goes through here before the next collective, so no process waits for one
  // that has stopped.
  virtual void agree_on_failure(std::string failure) = 0;
  // The sums of `value` (one per local particle of body b, local indices [begin, end)) over
  // chunks of `chunk` consecutive global indices of the body, each summed in index order from 0:
  // the same chunk sums one process forms. Only this process's own particles count.
  virtual void chunk_sums(int b, std::size_t begin, std::size_t end, const double* value,
                          std::int64_t chunk, std::vector<double>& sums) = 0;
};

} // namespace talus
