#include "talus/parallel/processes.hpp"

#include "talus/parallel/decomposition.hpp"

#include "talus/output/files.hpp"

#ifdef TALUS_MPI
#include "talus/parallel/seed_share.hpp"

#include <mpi.h>
#endif

namespace talus {

#ifdef TALUS_MPI
namespace {
bool mpi_on() {
  int on = 0;
  MPI_Initialized(&on);
  return on != 0;
}
} // namespace

int process_rank() {
  int r = 0;
  if (mpi_on()) MPI_Comm_rank(MPI_COMM_WORLD, &r);
  return r;
}

int process_count() {
  int n = 1;
  if (mpi_on()) MPI_Comm_size(MPI_COMM_WORLD, &n);
  return n;
}

int processes_on_this_node() {
  static const int here = [] {
    if (!mpi_on()) return 1;
    MPI_Comm node;
    MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &node);
    int n = 1;
    MPI_Comm_size(node, &n);
    MPI_Comm_free(&node);
    return n;
  }();
  return here;
}

std::string first_failure(const std::string& failure) {
  if (process_count() == 1) return failure;
  return first_message(MPI_COMM_WORLD,
                       failure.empty() ? no_key : static_cast<std::uint64_t>(process_rank()),
                       failure);
}

void max_over_processes(double* values, int n) {
  if (process_count() > 1)
    MPI_Allreduce(MPI_IN_PLACE, values, n, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
}
int max_over_processes(int value) {
  if (process_count() > 1) MPI_Allreduce(MPI_IN_PLACE, &value, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  return value;
}
void sum_over_processes(double* values, int n) {
  if (process_count() > 1)
    MPI_Allreduce(MPI_IN_PLACE, values, n, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
}
void wait_for_processes() {
  if (process_count() > 1) MPI_Barrier(MPI_COMM_WORLD);
}

ProcessSession::ProcessSession(int* argc, char*** argv) {
  int provided = 0;
  MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided);
  processes_on_this_node(); // collective: here, where every process calls it
}
ProcessSession::~ProcessSession() {
  MPI_Finalize();
}

void on_rank_zero(const std::function<void()>& f) {
  if (process_count() == 1) return f();
  int kind = 0; // 1: RunFolderError, 2: OutputError
  std::string message;
  if (process_rank() == 0) {
    try {
      f();
    } catch (const RunFolderError& e) {
      kind = 1, message = e.what();
    } catch (const OutputError& e) {
      kind = 2, message = e.what();
    }
  }
  int n = static_cast<int>(message.size());
  MPI_Bcast(&kind, 1, MPI_INT, 0, MPI_COMM_WORLD);
  MPI_Bcast(&n, 1, MPI_INT, 0, MPI_COMM_WORLD);
  message.resize(static_cast<std::size_t>(n));
  MPI_Bcast(message.data(), n, MPI_CHAR, 0, MPI_COMM_WORLD);
  if (kind == 1) throw RunFolderError(message);
  if (kind == 2) throw OutputError(message);
}
#else
int process_rank() {
  return 0;
}
int process_count() {
  return 1;
}
int processes_on_this_node() {
  return 1;
}
std::string first_failure(const std::string& failure) {
  return failure;
}
void max_over_processes(double*, int) {}
int max_over_processes(int value) {
  return value;
}
void sum_over_processes(double*, int) {}
void wait_for_processes() {}
ProcessSession::ProcessSession(int*, char***) {}
ProcessSession::~ProcessSession() = default;
void on_rank_zero(const std::function<void()>& f) {
  f();
}
#endif

MemoryBudget this_machine_budget() {
  MemoryBudget budget;
  budget.processes = process_count();
  budget.processes_here = processes_on_this_node();
  budget.share = [n = budget.processes, here = budget.processes_here](double columns) {
    return memory_share(n, here, columns, ghost_columns(max_normal_smoothing));
  };
  return budget;
}

} // namespace talus
