#include "talus/parallel/seed_share.hpp"

#include "talus/case/geometry.hpp"
#include "talus/case/parse.hpp"
#include "talus/setup/initial_state.hpp"
#include "talus/setup/interface.hpp"
#include "talus/setup/seeds.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>

namespace talus {

namespace {

// Columns of seeds kept beyond the slab, each side: the overlap check and the interface marks
// look one cell around a particle, and the K0 column of a particle is its own column or a
// neighbour's (floor of the same quotient, rounded apart).
constexpr std::int64_t seed_margin = 3;

} // namespace

std::string first_message(MPI_Comm comm, std::uint64_t key, std::string message) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  std::uint64_t least = key;
  MPI_Allreduce(MPI_IN_PLACE, &least, 1, MPI_UINT64_T, MPI_MIN, comm);
  if (least == no_key) return {};
  int from = key == least ? rank : size;
  MPI_Allreduce(MPI_IN_PLACE, &from, 1, MPI_INT, MPI_MIN, comm);
  int n = static_cast<int>(message.size());
  MPI_Bcast(&n, 1, MPI_INT, from, comm);
  message.resize(static_cast<std::size_t>(n));
  MPI_Bcast(message.data(), n, MPI_CHAR, from, comm);
  return message;
}

template <int D>
SharedSeeding<D> seed_share(const Case& c, MPI_Comm comm, SlabStart start) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  Vec<D> origin, extent;
  for (int d = 0; d < D; ++d)
    origin[d] = c.grid.origin[d], extent[d] = c.grid.extent[d];
  const Grid<D> G(origin, extent, c.grid.cell_size);
  std::int64_t per_column = 1;
  for (int d = 1; d < D; ++d)
    per_column *= G.cells[d];
  auto column = [&](const Vec<D>& x) { return owner_column(G, x, per_column); };
  const std::size_t B = c.bodies.size();

  // First walk: the particles per column, per body, and each body's mass summed in id order.
  SharedSeeding<D> out;
  Seeded<D>& s = out.seeded;
  std::vector<std::int64_t> counts(static_cast<std::size_t>(G.cells[0]), 0);
  out.body_begin.assign(1, 0);
  for (std::size_t b = 0; b < B; ++b) {
    const SeedParticle<D> sp = seed_particle<D>(c, b);
    std::size_t n = 0;
    double mass = 0.0;
    for_each_seed_of<D>(c, b, [&](const Vec<D>& x) { ++counts[column(x)], ++n, mass += sp.m; });
    require_particles(c, b, n);
    out.body_begin.push_back(out.body_begin.back() + n);
    s.body_mass.push_back(mass);
    s.body_count.push_back(n);
  }
  s.total = out.body_begin.back();
  std::vector<std::int64_t> slab_counts = counts;
  if (start == SlabStart::even_columns) std::fill(slab_counts.begin(), slab_counts.end(), 1);
  out.bounds =
      slab_bounds(slab_counts, size, ghost_columns(c.contact.normal_smoothing, c.simulation.xpic));
  const std::int64_t lo = out.bounds[rank], hi = out.bounds[rank + 1];
  const std::int64_t from = std::max<std::int64_t>(lo - seed_margin, 0);
  const std::int64_t to = std::min<std::int64_t>(hi + seed_margin, G.cells[0]);

  // Second walk: the seeds of the slab and its margin, with the whole case's ids.
  Particles<D> P;
  P.reserve(static_cast<std::size_t>(
      std::accumulate(counts.begin() + from, counts.begin() + to, std::int64_t{0})));
  std::uint32_t id = 0;
  for (std::size_t b = 0; b < B; ++b) {
    const SeedParticle<D> sp = seed_particle<D>(c, b);
    for_each_seed_of<D>(c, b, [&](const Vec<D>& x) {
      if (const std::int64_t k = column(x); k >= from && k < to) {
        P.push_back(x, sp.v, sp.m, sp.vol);
        P.id.back() = id;
      }
      ++id;
    });
    P.body_begin.push_back(P.size());
  }
  std::vector<char> own(P.size());
  for (std::size_t p = 0; p < P.size(); ++p) {
    const std::int64_t k = column(P.x[p]);
    own[p] = k >= lo && k < hi;
  }

  // Overlaps: each process checks its own particles against the margin's too; the least id
  // that overlaps is the one a single process names first (its order is the ids').
  std::string message;
  const std::size_t hit = find_body_overlap<D>(c, P, &own, message);
  message = first_message(comm, hit < P.size() ? P.id[hit] : no_key, message);
  if (!message.empty()) throw CaseError(message);
  // K0 stresses (per vertical column, complete with the margin) and interface marks.
  if (c.initial_state.method == InitialState::Method::k0) apply_k0_stress<D>(c, P);
  std::vector<std::size_t> marked = mark_interface_particles<D>(c, P, &own);
  std::vector<unsigned long> total_marked(marked.begin(), marked.end());
  MPI_Allreduce(MPI_IN_PLACE, total_marked.data(), static_cast<int>(total_marked.size()),
                MPI_UNSIGNED_LONG, MPI_SUM, comm);
  s.warnings = unbonded_interface_warnings(c, {total_marked.begin(), total_marked.end()});

  // This process keeps its own particles (in id order, as they were filled).
  Particles<D>& mine = s.particles;
  std::vector<std::size_t> keep;
  for (std::size_t p = 0; p < P.size(); ++p)
    if (own[p]) keep.push_back(p);
  Particles<D>::for_each_array_pair(mine, P, [&](auto& m, auto& a) {
    m.resize(keep.size());
    for (std::size_t i = 0; i < keep.size(); ++i)
      m[i] = a[keep[i]];
  });
  mine.body_begin.assign(1, 0);
  for (std::size_t b = 0; b < B; ++b)
    mine.body_begin.push_back(static_cast<std::size_t>(
        std::lower_bound(mine.id.begin(), mine.id.end(), out.body_begin[b + 1]) - mine.id.begin()));
  P = Particles<D>();

  // The pore pool's particles: every process's, by id.
  std::vector<std::int64_t> pore;
  for (std::size_t p = 0; p < mine.size(); ++p)
    if (mine.iface[p] >= 0 && has_pore_state(c.interfaces[mine.iface[p]]))
      pore.push_back(mine.id[p]), pore.push_back(mine.iface[p]);
  int n = static_cast<int>(pore.size());
  std::vector<int> ns(size), at(size, 0);
  MPI_Allgather(&n, 1, MPI_INT, ns.data(), 1, MPI_INT, comm);
  for (int q = 1; q < size; ++q)
    at[q] = at[q - 1] + ns[q - 1];
  std::vector<std::int64_t> all(static_cast<std::size_t>(at[size - 1] + ns[size - 1]));
  MPI_Allgatherv(pore.data(), n, MPI_INT64_T, all.data(), ns.data(), at.data(), MPI_INT64_T, comm);
  for (std::size_t k = 0; k < all.size(); k += 2)
    s.pore_particles.emplace_back(static_cast<std::uint32_t>(all[k]), static_cast<int>(all[k + 1]));
  std::sort(s.pore_particles.begin(), s.pore_particles.end());

  // Probes: the nearest particle over every process (the least distance, then the least id).
  for (const ProbeSpec& pr : c.probes) {
    Vec<D> near;
    for (int d = 0; d < D; ++d)
      near[d] = pr.near[d];
    double best[3] = {inf, inf, 0.0}; // squared distance, id, distance
    if (mine.body_begin[pr.body] < mine.body_begin[pr.body + 1]) {
      const std::size_t p = nearest_particle(mine, pr.body, near);
      best[0] = (mine.x[p] - near).squaredNorm(), best[1] = mine.id[p];
      best[2] = (mine.x[p] - near).norm();
    }
    std::vector<double> every(3 * static_cast<std::size_t>(size));
    MPI_Allgather(best, 3, MPI_DOUBLE, every.data(), 3, MPI_DOUBLE, comm);
    std::size_t q = 0;
    for (std::size_t r = 1; r < static_cast<std::size_t>(size); ++r)
      if (std::make_pair(every[3 * r], every[3 * r + 1]) <
          std::make_pair(every[3 * q], every[3 * q + 1]))
        q = r;
    if (std::string w = probe_gap_warning(c, pr, every[3 * q + 2]); !w.empty())
      s.warnings.push_back(w);
  }
  return out;
}

template <int D>
void choose_slab(LoadArchive& ar, const Grid<D>& G, int ghost, MPI_Comm comm, RestoredShare& out,
                 SlabStart start) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  std::int64_t per_column = 1;
  for (int d = 1; d < D; ++d)
    per_column *= G.cells[d];
  ar.set_choose(
      [&G, &out, rank, size, per_column, ghost, start](std::size_t, const LoadArchive::Scan& scan) {
        // Each chunk's positions, one column at a time (copied: the bytes need not be aligned).
        auto columns = [&](auto&& f) {
          scan([&](std::size_t first, const char* data, std::size_t count) {
            for (std::size_t i = 0; i < count; ++i) {
              Vec<D> x;
              std::memcpy(static_cast<void*>(&x), data + i * sizeof(Vec<D>), sizeof(Vec<D>));
              f(first + i, owner_column(G, x, per_column));
            }
          });
        };
        std::vector<std::int64_t> counts(static_cast<std::size_t>(G.cells[0]), 0);
        columns([&](std::size_t, std::int64_t col) { ++counts[col]; });
        if (start == SlabStart::even_columns) std::fill(counts.begin(), counts.end(), 1);
        out.bounds = slab_bounds(counts, size, ghost);
        out.rows.clear();
        columns([&](std::size_t row, std::int64_t col) {
          if (slab_owner(out.bounds, col) == rank)
            out.rows.push_back(static_cast<std::uint32_t>(row));
        });
        return out.rows;
      });
}

template void choose_slab<2>(LoadArchive&, const Grid<2>&, int, MPI_Comm, RestoredShare&,
                             SlabStart);
template void choose_slab<3>(LoadArchive&, const Grid<3>&, int, MPI_Comm, RestoredShare&,
                             SlabStart);
template SharedSeeding<2> seed_share<2>(const Case&, MPI_Comm, SlabStart);
template SharedSeeding<3> seed_share<3>(const Case&, MPI_Comm, SlabStart);

} // namespace talus
