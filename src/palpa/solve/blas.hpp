// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// The dense BLAS and LAPACK under CHOLMOD's supernodal factorization, as loaded
// at run time. Debian lets several implementations provide libblas.so.3 and
// liblapack.so.3 (reference, ATLAS, OpenBLAS serial/pthread/OpenMP) and picks
// one by its alternatives system, with no rebuild of palpa; what is loaded
// decides how fast a large 3D factorization is, so palpa says which it is.
//
// Threads: OpenBLAS's pthread build runs each large dense kernel on several
// threads of its own. palpa's element loops and the design's parallel trials
// run on TBB; when several TBB tasks factor at once, a multi-threaded BLAS
// under each of them oversubscribes the cores. ScopedBlasThreads pins BLAS to
// a thread count around such a region (a no-op where the BLAS has no thread
// control, as with ATLAS, the reference BLAS and OpenBLAS's serial build).

#include <string>

namespace palpa {

struct BlasInfo {
  std::string blas;     // the file that provides dgemm_ (links resolved), or "" when none is loaded
  std::string lapack;   // the file that provides dpotrf_
  std::string vendor;   // "OpenBLAS", "ATLAS", "reference", or "unknown"
  std::string config;   // OpenBLAS's own configuration line (version, core), else ""
  int threads = 1;      // threads a BLAS call may use now (1 where there is no control)
};

// Asks the dynamic linker which loaded objects provide the BLAS and LAPACK
// routines (the alternatives' links resolved to the real files).
BlasInfo loaded_blas();

// One line for `palpa --version` and verbose logs, e.g.
// "BLAS: OpenBLAS 0.3.21 ... (/usr/lib/.../openblas-pthread/libblas.so.3), 2 threads;
//  LAPACK: /usr/lib/.../liblapack.so.3".
std::string describe_blas();

// The BLAS's thread count, and setting it (no-op without thread control).
int blas_threads();
void set_blas_threads(int n);
// How palpa starts (the command line and the Python module alike): the BLAS
// on one thread unless OPENBLAS_NUM_THREADS or OMP_NUM_THREADS asks for more.
// palpa's own loops use every core through TBB, and OpenBLAS's threads beside
// them oversubscribe the cores (the foot at rest took 83 s instead of 12 s on
// 2 busy cores); and a factorization's last bits then do not depend on where
// palpa runs.
void set_default_blas_threads();

// Sets the BLAS thread count for its lifetime and restores it after. Call it
// from one thread (the one that starts the parallel region).
class ScopedBlasThreads {
 public:
  explicit ScopedBlasThreads(int n);
  ~ScopedBlasThreads();
  ScopedBlasThreads(const ScopedBlasThreads&) = delete;
  ScopedBlasThreads& operator=(const ScopedBlasThreads&) = delete;

 private:
  int previous_;
};

}  // namespace palpa
