// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/core/ranks.hpp"

#include <mpi.h>

#include <algorithm>
#include <cstdlib>
#include <fmt/format.h>
#include <limits>

#include "palpa/core/error.hpp"

namespace palpa::ranks {

namespace {

bool g_active = false;
int g_rank = 0;
int g_size = 1;

bool launched_by_mpi() {
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK"}) {
    if (std::getenv(v) != nullptr) return true;
  }
  return false;
}

void check(int code, const char* what) {
  if (code != MPI_SUCCESS) throw Error(ErrorKind::Internal, fmt::format("MPI: {} failed (code {})", what, code));
}

}  // namespace

void init(int& argc, char**& argv) {
  if (g_active || !launched_by_mpi()) return;
  int provided = 0;
  // Only the thread that called init talks to MPI (the others are TBB's).
  check(MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided), "MPI_Init_thread");
  g_active = true;
  check(MPI_Comm_rank(MPI_COMM_WORLD, &g_rank), "MPI_Comm_rank");
  check(MPI_Comm_size(MPI_COMM_WORLD, &g_size), "MPI_Comm_size");
}

void finalize(int exit_code) {
  if (!g_active) return;
  g_active = false;
  if (exit_code != 0 && g_size > 1) MPI_Abort(MPI_COMM_WORLD, exit_code);
  MPI_Finalize();
}

int rank() noexcept { return g_rank; }
int size() noexcept { return g_size; }
bool is_root() noexcept { return g_rank == 0; }

void broadcast(std::string& bytes, int root) {
  if (g_size == 1) return;
  unsigned long long n = bytes.size();
  check(MPI_Bcast(&n, 1, MPI_UNSIGNED_LONG_LONG, root, MPI_COMM_WORLD), "MPI_Bcast");
  if (g_rank != root) bytes.resize(static_cast<std::size_t>(n));
  // In pieces MPI's int counts can hold.
  constexpr std::size_t chunk = std::numeric_limits<int>::max() / 2;
  for (std::size_t at = 0; at < bytes.size(); at += chunk) {
    const int count = static_cast<int>(std::min(chunk, bytes.size() - at));
    check(MPI_Bcast(bytes.data() + at, count, MPI_CHAR, root, MPI_COMM_WORLD), "MPI_Bcast");
  }
}

bool broadcast_flag(bool value, int root) {
  if (g_size == 1) return value;
  int v = value ? 1 : 0;
  check(MPI_Bcast(&v, 1, MPI_INT, root, MPI_COMM_WORLD), "MPI_Bcast");
  return v != 0;
}

}  // namespace palpa::ranks
