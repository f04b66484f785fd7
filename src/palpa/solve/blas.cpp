// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/solve/blas.hpp"

#include <dlfcn.h>

#include <cstdlib>

#include <filesystem>
#include <fmt/format.h>

namespace palpa {

namespace {

// The file a loaded object's path resolves to (Debian's alternatives are a
// chain of symbolic links), or the path itself when it cannot be resolved.
std::string resolved(const char* path) {
  std::error_code ec;
  const std::filesystem::path p = std::filesystem::canonical(path, ec);
  return ec ? std::string(path) : p.string();
}

// The file that provides `function` to this process: the first loaded object
// that defines it, which is the one every caller (CHOLMOD included) binds to.
std::string provider_of(const char* function) {
  void* address = dlsym(RTLD_DEFAULT, function);
  Dl_info info{};
  if (address == nullptr || dladdr(address, &info) == 0 || info.dli_fname == nullptr) return {};
  return resolved(info.dli_fname);
}

template <class F>
F* symbol(const char* name) {
  // NOLINTNEXTLINE(cppcoreguidelines-pro-type-reinterpret-cast): dlsym returns void*
  return reinterpret_cast<F*>(dlsym(RTLD_DEFAULT, name));
}

using GetConfig = char*();
using GetThreads = int();
using SetThreads = void(int);

}  // namespace

BlasInfo loaded_blas() {
  BlasInfo info;
  // dgemm and dpotrf: the kernels of CHOLMOD's supernodal factorization.
  info.blas = provider_of("dgemm_");
  info.lapack = provider_of("dpotrf_");
  if (auto* config = symbol<GetConfig>("openblas_get_config")) {
    info.vendor = "OpenBLAS";
    if (const char* c = config()) info.config = c;
  } else if (info.blas.find("atlas") != std::string::npos) {
    info.vendor = "ATLAS";
  } else if (info.blas.find("/blas/") != std::string::npos) {
    info.vendor = "reference";
  } else {
    info.vendor = info.blas.empty() ? "none" : "unknown";
  }
  info.threads = blas_threads();
  return info;
}

std::string describe_blas() {
  const BlasInfo b = loaded_blas();
  const std::string what = b.config.empty() ? b.vendor : b.config;
  return fmt::format("BLAS: {} ({}), {} thread{}; LAPACK: {}", what, b.blas.empty() ? "not loaded" : b.blas,
                     b.threads, b.threads == 1 ? "" : "s", b.lapack.empty() ? "not loaded" : b.lapack);
}

int blas_threads() {
  if (auto* get = symbol<GetThreads>("openblas_get_num_threads")) return get();
  return 1;
}

void set_blas_threads(int n) {
  if (n < 1) n = 1;
  if (auto* set = symbol<SetThreads>("openblas_set_num_threads")) set(n);
}

void set_default_blas_threads() {
  if (std::getenv("OPENBLAS_NUM_THREADS") == nullptr && std::getenv("OMP_NUM_THREADS") == nullptr) {
    set_blas_threads(1);
  }
}

ScopedBlasThreads::ScopedBlasThreads(int n) : previous_(blas_threads()) {
  if (n != previous_) set_blas_threads(n);
}

ScopedBlasThreads::~ScopedBlasThreads() {
  if (blas_threads() != previous_) set_blas_threads(previous_);
}

}  // namespace palpa
