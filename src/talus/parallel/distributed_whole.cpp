// Distributed<D>: what output gathers to rank 0 (frames and checkpoints in one process's order,
// the contact nodes and the pore pool, the whole state for the tests' hash) and the release.
#include "talus/parallel/arrays.hpp"
#include "talus/parallel/distributed.hpp"

#include <algorithm>
#include <cstring>
#include <iterator>
#include <stdexcept>

namespace talus {

void gather_in_pieces(MPI_Comm comm, const std::vector<char>& mine,
                      const std::function<void(const std::vector<char>&)>& take) {
  constexpr std::size_t piece = std::size_t{1} << 30;
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  if (rank != 0) {
    std::uint64_t n = mine.size();
    MPI_Send(&n, 1, MPI_UINT64_T, 0, 0, comm);
    for (std::size_t at = 0; at < mine.size(); at += piece)
      MPI_Send(mine.data() + at, static_cast<int>(std::min(piece, mine.size() - at)), MPI_BYTE, 0,
               1, comm);
    return;
  }
  take(mine);
  std::vector<char> theirs;
  for (int q = 1; q < size; ++q) {
    std::uint64_t n = 0;
    MPI_Recv(&n, 1, MPI_UINT64_T, q, 0, comm, MPI_STATUS_IGNORE);
    theirs.resize(n);
    for (std::size_t at = 0; at < n; at += piece)
      MPI_Recv(theirs.data() + at, static_cast<int>(std::min<std::size_t>(piece, n - at)), MPI_BYTE,
               q, 1, comm, MPI_STATUS_IGNORE);
    take(theirs);
  }
}

template <int D>
void Distributed<D>::release() {
  sim_.release(); // the baseline: every process's own particles' elastic energy, summed exactly
}

template <int D>
std::vector<ContactNodeForce<D>> Distributed<D>::gather_contact_nodes() {
  const std::vector<ContactNodeForce<D>> nodes = sim_.contact_nodes(); // rows this process owns
  std::vector<char> node_buf(nodes.size() * sizeof(ContactNodeForce<D>));
  std::memcpy(node_buf.data(), static_cast<const void*>(nodes.data()), node_buf.size());
  std::vector<char> all_nodes;
  gather_in_pieces(comm_, node_buf, [&](const std::vector<char>& rows) {
    all_nodes.insert(all_nodes.end(), rows.begin(), rows.end());
  });
  // Every process's own rows, in process order, which is node-plane order.
  std::vector<ContactNodeForce<D>> every(all_nodes.size() / sizeof(ContactNodeForce<D>));
  std::memcpy(static_cast<void*>(every.data()), all_nodes.data(), all_nodes.size());
  return every;
}

// Per chunk of the spans' positions, rank 0 receives every process's records (the position's
// offset in the chunk, then its bytes) and places them: the chunk's values in one process's
// order.
template <int D>
void Distributed<D>::gather(std::size_t width, const Fill& fill, const Take& take,
                            const Spans& spans) {
  const std::size_t n = count(spans);
  const std::size_t chunk = std::clamp<std::size_t>((std::size_t{64} << 20) / (width + 4), 1,
                                                    std::max<std::size_t>(n, 1));
  std::vector<std::pair<std::uint32_t, std::uint32_t>> rows; // (global index, share row)
  for (std::size_t k = 0; k < share_own_.size(); ++k)
    if (share_own_[k]) rows.emplace_back(share_index_[k], static_cast<std::uint32_t>(k));
  std::sort(rows.begin(), rows.end());
  // Each own particle in a span, at its position in the spans' concatenation.
  std::vector<std::pair<std::size_t, std::uint32_t>> placed_rows; // (position, share row)
  std::size_t skipped = 0, r = 0;
  for (std::size_t s = 0; s < spans.size(); ++s) {
    skipped += spans[s].first - (s == 0 ? 0 : spans[s - 1].second);
    while (r < rows.size() && rows[r].first < spans[s].first)
      ++r;
    for (; r < rows.size() && rows[r].first < spans[s].second; ++r)
      placed_rows.emplace_back(rows[r].first - skipped, rows[r].second);
  }
  std::vector<char> mine, all, placed(rank_ == 0 ? chunk * width : 0);
  std::vector<int> counts(size_), at(size_);
  std::size_t next = 0;
  for (std::size_t g0 = 0; g0 < n; g0 += chunk) {
    const std::size_t g1 = std::min(n, g0 + chunk);
    mine.clear();
    for (; next < placed_rows.size() && placed_rows[next].first < g1; ++next) {
      const auto offset = static_cast<std::uint32_t>(placed_rows[next].first - g0);
      const std::size_t pos = mine.size();
      mine.resize(pos + 4 + width);
      std::memcpy(mine.data() + pos, &offset, 4);
      fill(placed_rows[next].second, mine.data() + pos + 4);
    }
    const int bytes = static_cast<int>(mine.size());
    MPI_Gather(&bytes, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, comm_);
    if (rank_ == 0) {
      for (int q = 0, sum = 0; q < size_; ++q)
        at[q] = sum, sum += counts[q];
      all.resize(static_cast<std::size_t>(at[size_ - 1] + counts[size_ - 1]));
    }
    MPI_Gatherv(mine.data(), bytes, MPI_BYTE, all.data(), counts.data(), at.data(), MPI_BYTE, 0,
                comm_);
    if (rank_ != 0) continue;
    if (all.size() != (g1 - g0) * (4 + width))
      abort_run(std::logic_error("gathering a frame: a particle is owned by no process or two"));
    for (std::size_t pos = 0; pos < all.size(); pos += 4 + width) {
      std::uint32_t offset = 0;
      std::memcpy(&offset, all.data() + pos, 4);
      std::memcpy(placed.data() + std::size_t{offset} * width, all.data() + pos + 4, width);
    }
    take(placed.data(), g1 - g0);
  }
}

// Each own particle whose global index lies in a span, then the maxima over the processes.
template <int D>
void Distributed<D>::reduce_max(const Spans& spans, const std::function<void(std::size_t p)>& f,
                                std::vector<double>& largest) {
  for (std::size_t k = 0; k < share_own_.size(); ++k) {
    if (!share_own_[k]) continue;
    const std::size_t g = share_index_[k];
    const auto after = std::upper_bound(spans.begin(), spans.end(), g,
                                        [](std::size_t i, const auto& s) { return i < s.first; });
    if (after != spans.begin() && g < std::prev(after)->second) f(k);
  }
  MPI_Allreduce(MPI_IN_PLACE, largest.data(), static_cast<int>(largest.size()), MPI_DOUBLE, MPI_MAX,
                comm_);
}

template <int D>
void Distributed<D>::check_particles() {
  std::string failure;
  try {
    sim_.check_particles();
  } catch (const SimulationError& e) {
    failure = e.what();
  }
  agree_on_failure(failure);
}

// Each process sends its own particles' pool entries (offset, then the entry), which rank 0
// writes into its pool in place.
template <int D>
void Distributed<D>::gather_tables() {
  std::vector<ContactNodeForce<D>> nodes = gather_contact_nodes();
  const Particles<D>& S = sim_.particles();
  std::vector<char> mine;
  for (std::size_t k = 0; k < S.size(); ++k) {
    const std::int64_t o = S.pore[k];
    if (!share_own_[k] || o < 0) continue;
    const std::size_t at = mine.size(), n = pool_size_[o] * sizeof(double);
    mine.resize(at + sizeof o + n);
    std::memcpy(mine.data() + at, &o, sizeof o);
    std::memcpy(mine.data() + at + sizeof o, sim_.pore_pool().data.data() + o, n);
  }
  gather_in_pieces(comm_, mine, [&](const std::vector<char>& entries) {
    for (std::size_t at = 0; at < entries.size();) {
      std::int64_t o = 0;
      std::memcpy(&o, entries.data() + at, sizeof o);
      const std::size_t n = pool_size_[o] * sizeof(double);
      std::memcpy(store_.pore_state().data() + o, entries.data() + at + sizeof o, n);
      at += sizeof o + n;
    }
  });
  if (rank_ == 0) store_.set_gathered_contact_nodes(std::move(nodes));
}

template <int D>
void Distributed<D>::gather_to_root() {
  std::vector<ContactNodeForce<D>> nodes = gather_contact_nodes();
  std::vector<char> buf;
  Particles<D> share = store_.take_particles();
  for (std::size_t k = 0; k < share_own_.size(); ++k)
    if (share_own_[k]) pack(share, k, share_index_[k], buf);
  // Rank 0 writes each process's records into their slots of the whole state as they arrive.
  Particles<D> staged;
  if (rank_ == 0) each_array(staged, [&](auto& a) { a.resize(body_begin_.back()); });
  gather_in_pieces(comm_, buf, [&](const std::vector<char>& records) {
    for (std::size_t pos = 0; pos < records.size();)
      pos = unpack_in_place(records, pos, staged);
  });
  if (rank_ != 0) {
    store_.replace_particles(std::move(share), true);
    return;
  }
  staged.body_begin = body_begin_;
  parked_share_ = std::move(share);
  store_.replace_particles(std::move(staged), true);
  store_.set_gathered_contact_nodes(std::move(nodes));
}

template <int D>
void Distributed<D>::restore_share() {
  if (rank_ != 0) return;
  store_.take_particles(); // the whole state goes
  store_.replace_particles(std::move(parked_share_), true);
  store_.set_gathered_contact_nodes(std::nullopt);
}

template class Distributed<2>;
template class Distributed<3>;

} // namespace talus
