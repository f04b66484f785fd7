// SPDX-License-Identifier: AGPL-3.0-or-later
// The browser check that the reports' tests rely on fails where it must: a
// console error, an uncaught exception, a blank page, a picture outside the
// file; and passes a drawn, self-contained page.
#include <gtest/gtest.h>

#include "common/test_support.hpp"

namespace palpa {
namespace {

using test::ScratchDir;

TEST(BrowserCheck, FailsOnConsoleErrorsBlankPagesAndOutsideFilesAndPassesADrawnPage) {
  ScratchDir dir;
  const std::string drawing =
      R"(<svg xmlns="http://www.w3.org/2000/svg" width="600" height="400"><rect width="600" height="400" fill="#fff"/>)"
      R"(<circle cx="200" cy="200" r="150" fill="#2a6"/><rect x="350" y="60" width="200" height="280" fill="#c33"/>)"
      R"(<text x="20" y="390" font-size="20">palpa</text></svg>)";
  dir.write("drawn.html", "<!DOCTYPE html><html><body><h1>A drawn page</h1>" + drawing + "</body></html>");
  dir.write("error.html", "<!DOCTYPE html><html><body>" + drawing + "<script>console.error('boom')</script></body></html>");
  dir.write("throws.html", "<!DOCTYPE html><html><body>" + drawing + "<script>noSuchFunction()</script></body></html>");
  dir.write("blank.html", "<!DOCTYPE html><html><body></body></html>");
  dir.write("outside.html", "<!DOCTYPE html><html><body>" + drawing + "<img src=\"plot.svg\"></body></html>");
  const auto good = test::check_page_in_browser(dir / "drawn.html");
  EXPECT_EQ(good.exit_code, 0) << good.out << good.err;
  for (const auto& [page, why] : {std::pair{"error.html", "console"}, std::pair{"throws.html", "Uncaught"},
                                  std::pair{"blank.html", "looks blank"}, std::pair{"outside.html", "outside itself"}}) {
    const auto r = test::check_page_in_browser(dir / page);
    EXPECT_EQ(r.exit_code, 1) << page << ": " << r.out << r.err;
    EXPECT_NE(r.out.find(why), std::string::npos) << page << ": " << r.out;
  }
}

}  // namespace
}  // namespace palpa
