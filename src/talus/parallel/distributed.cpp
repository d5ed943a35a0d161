#include "talus/parallel/distributed.hpp"

#include "talus/core/particle_sort.hpp"
#include "talus/parallel/arrays.hpp"
#include "talus/parallel/decomposition.hpp"
#include "talus/parallel/seed_share.hpp"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <fmt/format.h>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>
#include <type_traits>

namespace talus {

namespace {

template <class T>
using element_t = typename std::decay_t<T>::value_type;

} // namespace

template <int D>
void Distributed<D>::init() {
  MPI_Comm_rank(comm_, &rank_);
  MPI_Comm_size(comm_, &size_);
  // The surface points' Gauss-Seidel sweep runs in one order over the whole body.
  if (size_ > 1 && !sim_.setup().surface_pairs.empty())
    throw DecompositionError("[[contact]] law = \"surface\" runs on one process for now: run "
                             "this case without mpirun (threads share its work)");
  affine_ = sim_.setup().apic;
  const Grid<D>& G = sim_.grid();
  for (int d = 1; d < D; ++d)
    cells_per_column_ *= G.cells[d];
  ghost_width_ = ghost_columns(sim_.setup().normal_smoothing, sim_.setup().xpic);
  record_bytes_ = sizeof(std::uint32_t);
  each_array(own_, [&](auto& a) { record_bytes_ += sizeof(element_t<decltype(a)>); });
  // The pore pool's entries, in offset order: each runs to the next one.
  const auto& entries = sim_.pore_pool().entries;
  pool_size_.assign(sim_.pore_pool().data.size(), 0);
  for (std::size_t k = 0; k < entries.size(); ++k)
    pool_size_[entries[k].first] = static_cast<std::uint32_t>(
        (k + 1 < entries.size() ? entries[k + 1].first : sim_.pore_pool().data.size()) -
        entries[k].first);
}

template <int D>
Distributed<D>::Distributed(Simulation<D>& sim, MPI_Comm comm, std::int64_t rebalance_interval,
                            Start start)
    : sim_(sim), comm_(comm), rebalance_interval_(rebalance_interval) {
  init();
  // The whole state, the same on every process, is checked here: a bad particle in it stops
  // every process alike, before any share's first step could stop one alone.
  sim_.check_particles();
  Particles<D> all = store_.take_particles();
  body_begin_ = all.body_begin;
  std::vector<std::int64_t> counts(static_cast<std::size_t>(sim_.grid().cells[0]), 0);
  for (std::size_t p = 0; p < all.size(); ++p)
    ++counts[owner_column(all.x[p])];
  if (start == Start::even_columns) std::fill(counts.begin(), counts.end(), 1);
  bounds_ = slab_bounds(counts, size_, ghost_width_);
  // Own particles: those of the slab, in the whole state's order (the global index).
  std::vector<std::uint32_t> mine;
  for (std::size_t p = 0; p < all.size(); ++p)
    if (slab_owner(bounds_, owner_column(all.x[p])) == rank_)
      mine.push_back(static_cast<std::uint32_t>(p));
  each_array_pair(own_, all, [&](auto& o, auto& a) {
    o.resize(mine.size());
    for (std::size_t i = 0; i < mine.size(); ++i)
      o[i] = a[mine[i]];
  });
  own_index_ = mine;
  own_.body_begin = body_begin_of(own_index_);
  // A restored state's contact nodes: rank 0's to gather, once.
  if (rank_ != 0) store_.drop_contact_nodes();
  store_.set_exchange(this);
  fields_stand_ = false;
  build_share();
}

template <int D>
Distributed<D>::Distributed(Simulation<D>& sim, MPI_Comm comm, std::vector<std::int64_t> bounds,
                            std::vector<std::size_t> body_begin, std::int64_t rebalance_interval,
                            std::optional<std::vector<std::uint32_t>> restored_rows)
    : sim_(sim), comm_(comm), rebalance_interval_(rebalance_interval), bounds_(std::move(bounds)),
      body_begin_(std::move(body_begin)) {
  init();
  // The own particles' global indices: a new case's stand in id order, which is one process's.
  own_index_ = restored_rows ? std::move(*restored_rows) : sim_.particles().id;
  // Each process checks its own particles, named by their global indices (the share is the own
  // particles until build_share); every process stops with the first failure.
  share_index_ = own_index_;
  share_own_.assign(own_index_.size(), 1);
  store_.set_exchange(this);
  check_particles();
  own_ = store_.take_particles();
  own_.body_begin = body_begin_of(own_index_);
  // A restored state's contact nodes: rank 0's to gather, once.
  if (restored_rows && rank_ != 0) store_.drop_contact_nodes();
  fields_stand_ = false;
  build_share();
  if (!restored_rows) sim_.set_energy_baseline();
}

template <int D>
std::int64_t Distributed<D>::owner_column(const Vec<D>& x) const {
  return talus::owner_column(sim_.grid(), x, cells_per_column_);
}

template <int D>
std::int64_t Distributed<D>::column(const Vec<D>& x) const {
  const Grid<D>& G = sim_.grid();
  return std::clamp<std::int64_t>(G.cell_of(x)[0], 0, G.cells[0] - 1);
}

template <int D>
std::vector<std::size_t>
Distributed<D>::body_begin_of(const std::vector<std::uint32_t>& index) const {
  std::vector<std::size_t> begin(body_begin_.size());
  for (std::size_t b = 0; b < body_begin_.size(); ++b)
    begin[b] = static_cast<std::size_t>(
        std::lower_bound(index.begin(), index.end(), body_begin_[b]) - index.begin());
  return begin;
}

template <int D>
void Distributed<D>::pack(Particles<D>& P, std::size_t p, std::uint32_t g, std::vector<char>& buf) {
  auto put = [&](const void* data, std::size_t n) {
    const std::size_t at = buf.size();
    buf.resize(at + n);
    std::memcpy(buf.data() + at, data, n);
  };
  put(&g, sizeof g);
  each_array(P, [&](auto& a) { put(&a[p], sizeof(element_t<decltype(a)>)); });
  if (const std::int64_t o = P.pore[p]; o >= 0)
    put(sim_.pore_pool().data.data() + o, pool_size_[o] * sizeof(double));
}

template <int D>
std::size_t Distributed<D>::unpack(const std::vector<char>& buf, std::size_t pos, Particles<D>& P,
                                   std::vector<std::uint32_t>& index) {
  std::uint32_t g;
  std::memcpy(&g, buf.data() + pos, sizeof g);
  pos += sizeof g;
  index.push_back(g);
  each_array(P, [&](auto& a) {
    a.emplace_back();
    std::memcpy(static_cast<void*>(&a.back()), buf.data() + pos, sizeof(element_t<decltype(a)>));
    pos += sizeof(element_t<decltype(a)>);
  });
  if (const std::int64_t o = P.pore.back(); o >= 0) {
    std::memcpy(store_.pore_state().data() + o, buf.data() + pos, pool_size_[o] * sizeof(double));
    pos += pool_size_[o] * sizeof(double);
  }
  return pos;
}

template <int D>
std::size_t Distributed<D>::unpack_in_place(const std::vector<char>& buf, std::size_t pos,
                                            Particles<D>& P) {
  std::uint32_t g;
  std::memcpy(&g, buf.data() + pos, sizeof g);
  pos += sizeof g;
  each_array(P, [&](auto& a) {
    std::memcpy(static_cast<void*>(&a[g]), buf.data() + pos, sizeof(element_t<decltype(a)>));
    pos += sizeof(element_t<decltype(a)>);
  });
  if (const std::int64_t o = P.pore[g]; o >= 0) {
    std::memcpy(store_.pore_state().data() + o, buf.data() + pos, pool_size_[o] * sizeof(double));
    pos += pool_size_[o] * sizeof(double);
  }
  return pos;
}

template <int D>
const std::vector<char>& Distributed<D>::all_to_all(const std::vector<std::vector<char>>& buffers,
                                                    double& sent) {
  // MPI counts are int: a step's exchange of more than 2 GiB stops the run (abort_run) rather
  // than wrapping around.
  auto count = [&](std::size_t bytes) {
    if (bytes > static_cast<std::size_t>(std::numeric_limits<int>::max()))
      throw std::runtime_error(fmt::format(
          "process {} of {}: {:.3g} GB of particles to exchange in one step, more than MPI's "
          "2 GiB per call: run on more processes",
          rank_, size_, static_cast<double>(bytes) / 1e9));
    return static_cast<int>(bytes);
  };
  std::vector<int> send_n(size_), recv_n(size_), send_at(size_, 0), recv_at(size_, 0);
  std::size_t out_total = 0;
  for (int q = 0; q < size_; ++q)
    send_n[q] = count(buffers[q].size()), sent += send_n[q], out_total += buffers[q].size();
  count(out_total);
  MPI_Alltoall(send_n.data(), 1, MPI_INT, recv_n.data(), 1, MPI_INT, comm_);
  std::vector<char>& out_buf = send_buf_;
  std::vector<char>& in_buf = recv_buf_;
  out_buf.clear();
  for (int q = 0; q < size_; ++q) {
    send_at[q] = static_cast<int>(out_buf.size());
    out_buf.insert(out_buf.end(), buffers[q].begin(), buffers[q].end());
  }
  std::size_t in_total = 0;
  for (int q = 0; q < size_; ++q)
    recv_at[q] = static_cast<int>(in_total), in_total += static_cast<std::size_t>(recv_n[q]);
  const int total = count(in_total);
  in_buf.resize(static_cast<std::size_t>(total));
  MPI_Alltoallv(out_buf.data(), send_n.data(), send_at.data(), MPI_BYTE, in_buf.data(),
                recv_n.data(), recv_at.data(), MPI_BYTE, comm_);
  return in_buf;
}

// Ghosts: every own particle goes to each other process whose slab, widened by ghost_width_
// columns, holds its column. The share is the own and ghost particles merged by global index.
template <int D>
void Distributed<D>::build_share() {
  std::vector<std::uint32_t>& rows = rows_;
  rows.resize(own_index_.size());
  std::iota(rows.begin(), rows.end(), 0u);
  send_ghosts(own_, rows, own_index_);
  merge_share(own_, rows, own_index_);
  // The share holds them now (collect_own takes them back).
  each_array(own_, [](auto& a) { a.clear(); });
}

// The share anew: rows `rows` of `own` (global indices `index`, ascending) and the ghosts
// received (ghost_, ghost_index_) merged by global index into the spare arrays, then handed to
// the simulation. Ownership follows each particle's position.
template <int D>
void Distributed<D>::merge_share(Particles<D>& own, const std::vector<std::uint32_t>& rows,
                                 const std::vector<std::uint32_t>& index) {
  const std::vector<std::uint32_t>& ghost_index = ghost_index_;
  ghosts_ = ghost_index.size();
  std::vector<std::uint32_t> g_order(ghost_index.size());
  std::iota(g_order.begin(), g_order.end(), 0u);
  std::sort(g_order.begin(), g_order.end(),
            [&](std::uint32_t a, std::uint32_t b) { return ghost_index[a] < ghost_index[b]; });
  // Share slot k takes own row i as i, or ghost j as the own count + j.
  const std::size_t n_own = rows.size(), n = n_own + ghost_index.size();
  std::vector<std::uint32_t> from(n);
  share_index_.resize(n);
  for (std::size_t k = 0, i = 0, j = 0; k < n; ++k) {
    if (j == g_order.size() || (i < n_own && index[i] < ghost_index[g_order[j]])) {
      from[k] = static_cast<std::uint32_t>(i), share_index_[k] = index[i++];
    } else {
      from[k] = static_cast<std::uint32_t>(n_own + g_order[j]);
      share_index_[k] = ghost_index[g_order[j++]];
    }
  }
  Particles<D> share = std::move(spare_); // the last share's arrays: no new allocation
  each_array_pair(share, own, [&](auto& s, auto& o) {
    s.resize(n);
    for (std::size_t k = 0; k < n; ++k)
      if (from[k] < n_own) s[k] = o[rows[from[k]]];
  });
  each_array_pair(share, ghost_, [&](auto& s, auto& g) {
    for (std::size_t k = 0; k < n; ++k)
      if (from[k] >= n_own) s[k] = g[from[k] - n_own];
  });
  share.body_begin = body_begin_of(share_index_);
  set_ownership(share);
  store_.replace_particles(std::move(share), fields_stand_);
  fields_stand_ = true;
}

// Each share particle is this process's own if its owner column lies in the slab.
template <int D>
void Distributed<D>::set_ownership(const Particles<D>& share) {
  share_own_.resize(share.size());
  own_count_ = 0;
  const std::int64_t lo = bounds_[rank_], hi = bounds_[rank_ + 1];
  for (std::size_t k = 0; k < share.size(); ++k) {
    const std::int64_t c = owner_column(share.x[k]); // in [0, cells), as the slabs are
    share_own_[k] = c >= lo && c < hi;
    own_count_ += share_own_[k];
  }
}

// Sends each own particle of P (rows of the share, or of own_) to every other process whose
// slab, widened by ghost_width_ columns, holds its column, and unpacks what the others sent into
// ghost_ / ghost_index_. Records going to the particle's new owner count as migration.
template <int D>
void Distributed<D>::send_ghosts(Particles<D>& P, const std::vector<std::uint32_t>& rows,
                                 const std::vector<std::uint32_t>& index) {
  std::vector<std::vector<char>>& out = outgoing_;
  out.resize(size_);
  for (auto& o : out)
    o.clear();
  double migrating = 0;
  // A particle farther than the ghost width from both cuts of this slab goes to no one.
  const std::int64_t inner_lo = bounds_[rank_] + ghost_width_;
  const std::int64_t inner_hi = bounds_[rank_ + 1] - ghost_width_;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const std::size_t p = rows[i];
    const std::int64_t c = column(P.x[p]);
    if (c >= inner_lo && c < inner_hi) continue;
    const int q_lo = slab_owner(bounds_, c - ghost_width_);
    const int q_hi = slab_owner(bounds_, c + ghost_width_);
    const int owner = slab_owner(bounds_, owner_column(P.x[p]));
    for (int q = q_lo; q <= q_hi; ++q)
      if (q != rank_ && c >= bounds_[q] - ghost_width_ && c < bounds_[q + 1] + ghost_width_) {
        const std::size_t at = out[q].size();
        pack(P, p, index[i], out[q]);
        if (q == owner) migrating += static_cast<double>(out[q].size() - at);
      }
  }
  double sent = 0;
  const std::vector<char>& in = all_to_all(out, sent);
  ghost_bytes_ += sent - migrating, migration_bytes_ += migrating;
  // Reused: its arrays keep their capacity from step to step.
  each_array(ghost_, [](auto& a) { a.clear(); });
  ghost_.body_begin = body_begin_;
  ghost_index_.clear();
  for (std::size_t pos = 0; pos < in.size();)
    pos = unpack(in, pos, ghost_, ghost_index_);
}

// After a step: each process sends its own particles to the neighbours' widened slabs by their
// new positions. Unless a particle crossed the edge of a widened slab, the share then holds the
// same particles in the same slots as before, and only the ghosts' slots take the owners'
// values; otherwise it is merged anew. A particle that crossed into a neighbour's slab is held
// there as a ghost already, so migration is the change of its owner.
template <int D>
void Distributed<D>::refresh_share() {
  Particles<D>& S = store_.share_in_place();
  const std::int64_t reach_lo = bounds_[rank_] - ghost_width_;
  const std::int64_t reach_hi = bounds_[rank_ + 1] + ghost_width_;
  std::vector<std::uint32_t>& rows = rows_;   // own slots, still within reach
  std::vector<std::uint32_t>& index = index_; // their global indices
  std::vector<std::uint32_t>& ghost_slots = ghost_slots_;
  rows.clear(), index.clear(), ghost_slots.clear();
  bool same = true;
  for (std::size_t k = 0; k < S.size(); ++k) {
    if (!share_own_[k]) {
      ghost_slots.push_back(static_cast<std::uint32_t>(k));
      continue;
    }
    const std::int64_t c = column(S.x[k]);
    if (c < reach_lo || c >= reach_hi) {
      same = false; // out of reach: it leaves the share
      continue;
    }
    rows.push_back(static_cast<std::uint32_t>(k)), index.push_back(share_index_[k]);
  }
  send_ghosts(S, rows, index);
  // The ghosts arrive in their senders' share order, ascending global index within each sender.
  std::vector<std::uint32_t>& g_order = g_order_;
  g_order.resize(ghost_index_.size());
  std::iota(g_order.begin(), g_order.end(), 0u);
  std::sort(g_order.begin(), g_order.end(),
            [&](std::uint32_t a, std::uint32_t b) { return ghost_index_[a] < ghost_index_[b]; });
  same = same && g_order.size() == ghost_slots.size();
  for (std::size_t j = 0; same && j < g_order.size(); ++j)
    same = ghost_index_[g_order[j]] == share_index_[ghost_slots[j]];
  if (!same) {
    ++rebuilds_;
    Particles<D> last = store_.take_particles();
    spare_.body_begin = body_begin_;
    merge_share(last, rows, index);
    spare_ = std::move(last);
    return;
  }
  each_array_pair(S, ghost_, [&](auto& s, auto& g) {
    for (std::size_t j = 0; j < g_order.size(); ++j)
      s[ghost_slots[j]] = g[g_order[j]];
  });
  set_ownership(S);
}

template <int D>
void Distributed<D>::collect_own() {
  spare_ = store_.take_particles(); // kept for the next share's arrays
  Particles<D>& share = spare_;
  std::vector<std::uint32_t> keep;
  for (std::size_t k = 0; k < share_own_.size(); ++k)
    if (share_own_[k]) keep.push_back(static_cast<std::uint32_t>(k));
  each_array_pair(own_, share, [&](auto& o, auto& s) {
    o.resize(keep.size());
    for (std::size_t i = 0; i < keep.size(); ++i)
      o[i] = s[keep[i]];
  });
  own_index_.resize(keep.size());
  for (std::size_t i = 0; i < keep.size(); ++i)
    own_index_[i] = share_index_[keep[i]];
  own_.body_begin = body_begin_of(own_index_);
}

template <int D>
void Distributed<D>::migrate() {
  std::vector<std::vector<char>> out(size_);
  std::vector<std::uint32_t> stay;
  for (std::size_t p = 0; p < own_index_.size(); ++p) {
    const int q = slab_owner(bounds_, owner_column(own_.x[p]));
    if (q == rank_)
      stay.push_back(static_cast<std::uint32_t>(p));
    else
      pack(own_, p, own_index_[p], out[q]);
  }
  const std::vector<char>& in = all_to_all(out, migration_bytes_);
  Particles<D> arrived;
  arrived.body_begin = body_begin_;
  std::vector<std::uint32_t> arrived_index;
  for (std::size_t pos = 0; pos < in.size();)
    pos = unpack(in, pos, arrived, arrived_index);
  if (stay.size() == own_index_.size() && arrived_index.empty()) return;
  // The staying and the arrived particles merged by global index.
  std::vector<std::uint32_t> a_order(arrived_index.size());
  std::iota(a_order.begin(), a_order.end(), 0u);
  std::sort(a_order.begin(), a_order.end(),
            [&](std::uint32_t a, std::uint32_t b) { return arrived_index[a] < arrived_index[b]; });
  const std::size_t n = stay.size() + arrived_index.size();
  const std::uint32_t n_stay = static_cast<std::uint32_t>(stay.size());
  std::vector<std::uint32_t> from(n), index(n);
  for (std::size_t k = 0, i = 0, j = 0; k < n; ++k) {
    if (j == a_order.size() ||
        (i < stay.size() && own_index_[stay[i]] < arrived_index[a_order[j]])) {
      from[k] = static_cast<std::uint32_t>(i), index[k] = own_index_[stay[i++]];
    } else {
      from[k] = n_stay + a_order[j], index[k] = arrived_index[a_order[j++]];
    }
  }
  Particles<D> merged;
  each_array_pair(merged, own_, [&](auto& m, auto& o) {
    m.resize(n);
    for (std::size_t k = 0; k < n; ++k)
      if (from[k] < n_stay) m[k] = o[stay[from[k]]];
  });
  each_array_pair(merged, arrived, [&](auto& m, auto& a) {
    for (std::size_t k = 0; k < n; ++k)
      if (from[k] >= n_stay) m[k] = a[from[k] - n_stay];
  });
  own_ = std::move(merged);
  own_index_ = std::move(index);
  own_.body_begin = body_begin_of(own_index_);
}

// One process's sort (Simulation::sort_particles_by_cell, stable by cell within each body) of
// the own particles; the new global index of each is the count of the body's particles on the
// processes before this one (whose cells all come first) plus its place here.
template <int D>
void Distributed<D>::sort_own() {
  const int B = static_cast<int>(body_begin_.size()) - 1;
  apply_order(own_, order_by_cell(sim_.grid(), own_.x, own_.body_begin));
  std::vector<std::int64_t> count(B), before(B, 0);
  for (int b = 0; b < B; ++b)
    count[b] = static_cast<std::int64_t>(own_.body_begin[b + 1] - own_.body_begin[b]);
  MPI_Exscan(count.data(), before.data(), B, MPI_INT64_T, MPI_SUM, comm_);
  if (rank_ == 0) std::fill(before.begin(), before.end(), 0);
  for (int b = 0; b < B; ++b)
    for (std::size_t p = own_.body_begin[b]; p < own_.body_begin[b + 1]; ++p)
      own_index_[p] =
          static_cast<std::uint32_t>(body_begin_[b] + before[b] + (p - own_.body_begin[b]));
}

// New slab bounds from the particle count per column; the particles whose slab changed move.
template <int D>
void Distributed<D>::rebalance() {
  std::vector<std::int64_t> counts(static_cast<std::size_t>(sim_.grid().cells[0]), 0);
  for (std::size_t p = 0; p < own_index_.size(); ++p)
    ++counts[owner_column(own_.x[p])];
  MPI_Allreduce(MPI_IN_PLACE, counts.data(), static_cast<int>(counts.size()), MPI_INT64_T, MPI_SUM,
                comm_);
  std::vector<std::int64_t> bounds = slab_bounds(counts, size_, ghost_width_);
  if (bounds == bounds_) return;
  bounds_ = std::move(bounds);
  ++rebalances_;
  migrate();
  fields_stand_ = false; // the fixed bodies' particles of the share change: rescatter them
}

template <int D>
void Distributed<D>::abort_run(const std::exception& e) const {
  std::fprintf(stderr, "talus: process %d of %d: %s\n", rank_, size_, e.what());
  std::fflush(stderr);
  MPI_Abort(comm_, 1);
  std::abort();
}

template <int D>
void Distributed<D>::step(double dt_limit) {
  try {
    const std::int64_t step = sim_.steps();
    const bool rebalance_due =
        rebalance_interval_ > 0 && step > 0 && step % rebalance_interval_ == 0;
    const bool sort_due = step % store_.sort_interval() == 0;
    if (rebalance_due || sort_due) {
      collect_own();
      if (rebalance_due) rebalance();
      if (sort_due) sort_own();
      build_share();
    }
    // Own particles' positions before the step: none may move more than a cell.
    const Particles<D>& S = sim_.particles();
    std::vector<Vec<D>>& before = before_;
    before.clear();
    for (std::size_t k = 0; k < share_own_.size(); ++k)
      if (share_own_[k]) before.push_back(S.x[k]);
    // A failure the step reports (at its end, past its collective points: a bad particle, det F
    // <= 0, a collapsed time step) is agreed on, and every process stops with the first one.
    std::string failure;
    try {
      sim_.step(dt_limit);
      const double h = sim_.grid().h;
      for (std::size_t k = 0, i = 0; k < share_own_.size(); ++k) {
        if (!share_own_[k]) continue;
        const Vec<D> dx = sim_.particles().x[k] - before[i++];
        if (dx.cwiseAbs().maxCoeff() > h)
          throw SimulationError(fmt::format(
              "step {}, time {:.6g} s: particle id {} moved {:.4g} m in one step, more than a "
              "cell ({:.4g} m): reduce the time step (simulation.cfl) or check the case",
              sim_.steps() - 1, sim_.time(), sim_.particles().id[k], dx.norm(), h));
      }
    } catch (const SimulationError& e) {
      failure = e.what();
    }
    agree_on_failure(failure);
    refresh_share();
  } catch (const SimulationError&) {
    throw; // every process throws it
  } catch (const std::exception& e) {
    abort_run(e);
  }
}

// The lowest process that failed sends its message; every process then throws it.
template <int D>
void Distributed<D>::agree_on_failure(std::string failure) {
  const std::uint64_t key = failure.empty() ? no_key : static_cast<std::uint64_t>(rank_);
  if (!failure.empty()) failure = fmt::format("process {} of {}: {}", rank_, size_, failure);
  failure = first_message(comm_, key, std::move(failure));
  if (!failure.empty()) throw SimulationError(failure);
}

template class Distributed<2>;
template class Distributed<3>;

} // namespace talus
