// SPDX-License-Identifier: AGPL-3.0-or-later
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "palpa/core/interrupt.hpp"
#include "palpa/core/error.hpp"
#include "palpa/core/progress.hpp"

namespace palpa {
namespace {

std::string capture(const std::function<void(std::FILE*)>& f) {
  char* buf = nullptr;
  std::size_t len = 0;
  std::FILE* mem = open_memstream(&buf, &len);
  f(mem);
  std::fclose(mem);
  std::string out(buf, len);
  std::free(buf);
  return out;
}

TEST(Progress, PlainStyleIsSparse) {
  const std::string out = capture([](std::FILE* f) {
    Progress p("depths", 1000, Progress::Style::Plain, f);
    for (int i = 0; i < 1000; ++i) p.advance();
    p.finish();
  });
  // Start line, at most one line per tenth (time-gated), and the final line.
  const auto lines = std::count(out.begin(), out.end(), '\n');
  EXPECT_GE(lines, 2);
  EXPECT_LE(lines, 12);
  EXPECT_NE(out.find("depths: started (1000 steps)"), std::string::npos);
  EXPECT_NE(out.find("depths: 100% (1000/1000)"), std::string::npos);
  EXPECT_EQ(out.find('\r'), std::string::npos);
}

TEST(Progress, BarStyleRedrawsInPlace) {
  const std::string out = capture([](std::FILE* f) {
    Progress p("fit", 3, Progress::Style::Bar, f);
    p.advance(3);
    p.finish();
  });
  EXPECT_NE(out.find('\r'), std::string::npos);
  EXPECT_NE(out.find("100% (3/3)"), std::string::npos);
}

TEST(Progress, SilentPrintsNothing) {
  const std::string out = capture([](std::FILE* f) {
    Progress p("x", 10, Progress::Style::Silent, f);
    p.advance(10);
    p.finish();
  });
  EXPECT_TRUE(out.empty());
}

TEST(Interrupt, CheckThrowsOnceRequested) {
  clear_interrupt();
  EXPECT_NO_THROW(check_interrupt());
  request_interrupt();
  try {
    check_interrupt();
    ADD_FAILURE() << "no throw";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::Interrupted);
  }
  clear_interrupt();
  EXPECT_FALSE(interrupt_requested());
}

}  // namespace
}  // namespace palpa
