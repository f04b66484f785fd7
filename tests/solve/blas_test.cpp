// SPDX-License-Identifier: AGPL-3.0-or-later
// The BLAS and LAPACK under CHOLMOD, as loaded into this test program (which
// links CHOLMOD, so both are loaded), and the thread pin around TBB regions.

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "palpa/solve/blas.hpp"

namespace palpa {
namespace {

TEST(Blas, NamesTheLoadedLibraries) {
  const BlasInfo b = loaded_blas();
  ASSERT_FALSE(b.blas.empty()) << "CHOLMOD is linked, so a BLAS must be loaded";
  ASSERT_FALSE(b.lapack.empty());
  EXPECT_TRUE(std::filesystem::exists(b.blas)) << b.blas;
  EXPECT_TRUE(std::filesystem::exists(b.lapack)) << b.lapack;
  EXPECT_NE(b.vendor, "none");
  EXPECT_GE(b.threads, 1);
  if (b.vendor == "OpenBLAS") {
    EXPECT_NE(b.config.find("OpenBLAS"), std::string::npos) << b.config;
  }
  const std::string line = describe_blas();
  EXPECT_EQ(line.rfind("BLAS: ", 0), 0u) << line;
  EXPECT_NE(line.find(b.blas), std::string::npos) << line;
  EXPECT_NE(line.find("LAPACK: " + b.lapack), std::string::npos) << line;
}

TEST(Blas, ScopedThreadsPinAndRestore) {
  const int before = blas_threads();
  // A BLAS with thread control (OpenBLAS) really changes its count, from
  // whatever it starts at (the test presets start it at one thread); without
  // control the count is 1, and pinning to 1 keeps it.
  const int other = loaded_blas().vendor == "OpenBLAS" && before == 1 ? 2 : 1;
  {
    ScopedBlasThreads pin(other);
    EXPECT_EQ(blas_threads(), other);
  }
  EXPECT_EQ(blas_threads(), before);
}

}  // namespace
}  // namespace palpa
