// Distributed<D>'s whole state on rank 0 (with_whole_state, for output, checkpoints and the
// release) and the energy baseline formed across processes.
#include "talus/parallel/arrays.hpp"
#include "talus/parallel/distributed.hpp"

#include <cstring>

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

// The energy budget's baseline, each body's elastic energy summed in id order as one process
// sums it (Simulation::strain_energy): every process sends its own particles' terms with their
// ids, rank 0 places them by id, sums each body's range and sends the sums to every process.
template <int D>
void Distributed<D>::set_energy_baseline() {
  const Particles<D>& S = sim_.particles();
  struct Term {
    std::uint32_t id;
    double energy;
  };
  std::vector<char> mine;
  for (std::size_t k = 0; k < S.size(); ++k)
    if (share_own_[k]) {
      const Term t{S.id[k], sim_.strain_energy_of(k)};
      const std::size_t at = mine.size();
      mine.resize(at + sizeof t);
      std::memcpy(mine.data() + at, &t, sizeof t);
    }
  std::vector<double> by_id(rank_ == 0 ? body_begin_.back() : 0, 0.0);
  gather_in_pieces(comm_, mine, [&](const std::vector<char>& terms) {
    for (std::size_t at = 0; at < terms.size(); at += sizeof(Term)) {
      Term t;
      std::memcpy(&t, terms.data() + at, sizeof t);
      by_id[t.id] = t.energy;
    }
  });
  const std::size_t B = body_begin_.size() - 1;
  std::vector<double> baseline(B, 0.0);
  if (rank_ == 0) {
    for (std::size_t b = 0; b < B; ++b)
      if (!sim_.setup().bodies[b].rigid)
        for (std::size_t i = body_begin_[b]; i < body_begin_[b + 1]; ++i)
          baseline[b] += by_id[i];
  }
  MPI_Bcast(baseline.data(), static_cast<int>(B), MPI_DOUBLE, 0, comm_);
  sim_.set_energy_baseline(std::move(baseline));
}

template <int D>
void Distributed<D>::release() {
  sim_.release();
  // The elastic energy at release is a sum over every particle: rank 0 forms it from the whole.
  with_whole_state([](Simulation<D>& sim) { sim.release(); });
}

template <int D>
void Distributed<D>::gather_to_root() {
  std::vector<char> buf;
  Particles<D> share = sim_.take_particles();
  for (std::size_t k = 0; k < share_own_.size(); ++k)
    if (share_own_[k]) pack(share, k, share_index_[k], buf);
  const std::vector<ContactNodeForce<D>> nodes = sim_.contact_nodes(); // rows this process owns
  std::vector<char> node_buf(nodes.size() * sizeof(ContactNodeForce<D>));
  std::memcpy(node_buf.data(), static_cast<const void*>(nodes.data()), node_buf.size());
  // Rank 0 writes each process's records into their slots of the whole state as they arrive.
  Particles<D> staged;
  if (rank_ == 0) staged.for_each_array([&](auto& a) { a.resize(body_begin_.back()); });
  gather_in_pieces(comm_, buf, [&](const std::vector<char>& records) {
    for (std::size_t pos = 0; pos < records.size();)
      pos = unpack_in_place(records, pos, staged);
  });
  std::vector<char> all_nodes;
  gather_in_pieces(comm_, node_buf, [&](const std::vector<char>& rows) {
    all_nodes.insert(all_nodes.end(), rows.begin(), rows.end());
  });
  if (rank_ != 0) {
    sim_.replace_particles(std::move(share), true);
    return;
  }
  staged.body_begin = body_begin_;
  // Contact nodes: every process's own rows, in process order, which is node-plane order.
  std::vector<ContactNodeForce<D>> every(all_nodes.size() / sizeof(ContactNodeForce<D>));
  std::memcpy(static_cast<void*>(every.data()), all_nodes.data(), all_nodes.size());
  parked_share_ = std::move(share);
  sim_.replace_particles(std::move(staged), true);
  sim_.set_gathered_contact_nodes(std::move(every));
}

template <int D>
void Distributed<D>::restore_share() {
  if (rank_ != 0) return;
  sim_.take_particles(); // the whole state goes
  sim_.replace_particles(std::move(parked_share_), true);
  sim_.set_gathered_contact_nodes(std::nullopt);
}

template class Distributed<2>;
template class Distributed<3>;

} // namespace talus
