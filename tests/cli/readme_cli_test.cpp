// SPDX-License-Identifier: AGPL-3.0-or-later
// The README's commands, run as a new user would: every command of the code
// blocks of the walkthrough ("## A subject, step by step") and under
// "## Commands", in order, from a folder that holds the bundled examples as
// the repository root does, each ending with exit 0.
//
// By default the iterative commands run shortened (fit: one shape iteration
// on the coarsest mesh, design: one iteration), which still runs every stage
// and writes every file, and the long examples are left out (long_example);
// PALPA_README_FULL=1 runs every command exactly as written and prints the
// time of each (the figures the README quotes).
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "common/test_support.hpp"

namespace palpa {
namespace {

using test::ScratchDir;

// The README's sections whose commands run: the walkthrough as one sequence,
// and the reference, one sequence per ### section.
constexpr const char* kWalkthrough = "## A subject, step by step";
constexpr const char* kReference = "## Commands";

struct ReadmeCommand {
  int line = 0;             // 1-based line of the README where it starts
  std::string section;      // the ### heading above it (the walkthrough's ## heading)
  std::string text;         // the command, continuation lines joined
  std::string assignments;  // shell variables set earlier in the same section
};

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t");
  if (b == std::string::npos) return "";
  const auto e = s.find_last_not_of(" \t");
  return s.substr(b, e - b + 1);
}

// The line without a trailing shell comment (a '#' after blank space, outside quotes).
std::string strip_comment(const std::string& s) {
  char quote = 0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const char c = s[i];
    if (quote != 0) {
      if (c == quote) quote = 0;
    } else if (c == '\'' || c == '"') {
      quote = c;
    } else if (c == '#' && (i == 0 || s[i - 1] == ' ' || s[i - 1] == '\t')) {
      return s.substr(0, i);
    }
  }
  return s;
}

bool is_assignment(const std::string& s) {
  const auto eq = s.find('=');
  if (eq == std::string::npos || eq == 0) return false;
  for (std::size_t i = 0; i < eq; ++i) {
    const char c = s[i];
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_')) return false;
  }
  return s.find(' ') == std::string::npos || s.find(' ') > eq;
}

// Every command of the ```sh blocks of the walkthrough and of the reference
// (up to the next "## "): palpa commands, shell variables set for the
// section's later commands, and `mkdir -p` for the folders of outputs.
std::vector<ReadmeCommand> readme_commands(const std::string& readme,
                                           std::vector<std::string>& problems) {
  std::vector<ReadmeCommand> out;
  std::istringstream in(readme);
  std::string raw;
  int n = 0;
  bool in_commands = false, in_block = false;
  std::string section, pending, assignments;
  int pending_line = 0;
  while (std::getline(in, raw)) {
    ++n;
    if (!in_block && raw.rfind("## ", 0) == 0) {
      in_commands = raw == kWalkthrough || raw == kReference;
      section = raw == kWalkthrough ? raw.substr(3) : "";
      assignments.clear();
    }
    if (!in_commands) continue;
    if (!in_block && raw.rfind("### ", 0) == 0 && section != std::string(kWalkthrough).substr(3)) {
      section = raw.substr(4);
      assignments.clear();
    }
    if (raw.rfind("```", 0) == 0) {
      if (in_block) {
        in_block = false;
        if (!pending.empty())
          problems.push_back(fmt::format("README.md:{}: a block ends in a '\\'", n));
        pending.clear();
      } else if (raw == "```sh") {
        in_block = true;
      }
      continue;
    }
    if (!in_block) continue;
    std::string text = strip_comment(raw);
    const bool continued = !trim(text).empty() && trim(text).back() == '\\';
    if (continued) text = trim(text).substr(0, trim(text).size() - 1);
    if (pending.empty()) pending_line = n;
    pending += (pending.empty() ? "" : " ") + trim(text);
    if (continued) continue;
    const std::string command = trim(pending);
    pending.clear();
    if (command.empty()) continue;
    if (is_assignment(command)) {
      assignments += command + "; ";
    } else if (command.rfind("palpa ", 0) == 0 || command.rfind("mkdir -p ", 0) == 0) {
      out.push_back(ReadmeCommand{pending_line, section, command, assignments});
    } else {
      problems.push_back(
          fmt::format("README.md:{}: '{}' is not a palpa command", pending_line, command));
    }
  }
  return out;
}

// The long examples (10 s to many minutes on 2 cores): the quick run leaves
// them to PALPA_README_FULL=1. Their siblings in the same sections (the first
// poke, the seated body and the foot at rest, the thigh's hollow design) run
// in both.
bool long_example(const std::string& command) {
  for (const char* scene :
       {"--mesh-level 3 --vtu frames", "examples/sim3d/punch/scene.json",
        "examples/rest/chair/flat.json", "examples/rest/foot/negative-image.json",
        "examples/rest/mouse/", "examples/design/thigh/scene.json", "examples/design/chair/",
        "examples/design/shoe/", "examples/design/mouse/", "examples/design/deformable-chair/", "examples/design/cohort/",
        "-full/scene.json"}) {
    if (command.find(scene) != std::string::npos) return true;
  }
  return false;
}

// `command` with option `name` set to `value`: its value replaced where it is
// given, the option added where it is not.
std::string with_option(const std::string& command, const std::string& name, const std::string& value) {
  const std::size_t at = command.find(" " + name + " ");
  if (at == std::string::npos) return command + " " + name + " " + value;
  const std::size_t from = at + name.size() + 2;
  const std::size_t to = std::min(command.find(' ', from), command.size());
  return command.substr(0, from) + value + command.substr(to);
}

// The shortened form of an iterative command (see the file comment).
std::string shortened(const std::string& command) {
  if (command.rfind("palpa fit ", 0) == 0)
    return with_option(with_option(command, "--max-iterations", "1"), "--mesh-level", "0");
  if (command.rfind("palpa design ", 0) == 0) return with_option(command, "--iterations", "1");
  return command;
}

struct Ran {
  ReadmeCommand command;
  std::string run;  // the command line as run
  int exit_code = -1;
  double seconds = 0.0;
  std::string out, err;
};

Ran run_in(const ReadmeCommand& c, const std::string& command, const std::filesystem::path& dir) {
  const auto out = dir / ".readme-stdout";
  const auto err = dir / ".readme-stderr";
  const std::string script =
      fmt::format("cd '{}' && palpa() {{ '{}' \"$@\"; }}; {}{} >'{}' 2>'{}' </dev/null",
                  dir.string(), test::palpa_binary(), c.assignments, command, out.string(), err.string());
  const auto start = std::chrono::steady_clock::now();
  const int status = std::system(script.c_str());
  Ran r;
  r.command = c;
  r.run = command;
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = test::read_text(out);
  r.err = test::read_text(err);
  std::filesystem::remove(out);
  std::filesystem::remove(err);
  return r;
}

std::string tail(const std::string& s, std::size_t n) {
  return s.size() <= n ? s : "…" + s.substr(s.size() - n);
}

// The expected results the README and the examples' notes promise, on the
// outputs of the commands that make them.
void check_results(const std::vector<Ran>& ran, const ScratchDir& dir) {
  for (const auto& r : ran) {
    if (r.exit_code != 0) continue;  // failed, or not run
    const std::string& t = r.command.text;
    if (t.rfind("palpa demo -o stages-demo", 0) == 0) {
      EXPECT_TRUE(std::filesystem::exists(dir / "stages-demo" / "summary.txt"));
      EXPECT_TRUE(std::filesystem::exists(dir / "stages-demo" / "tissue_uniaxial.csv"));
      EXPECT_TRUE(std::filesystem::exists(dir / "stages-demo" / "tissue_poke.csv"));
      EXPECT_NE(r.out.find("poke         3 mm punch, 10 mm layer"), std::string::npos) << r.out;
      EXPECT_NE(r.out.find("tissue (neo-hookean-volume): small-strain E = 10 kPa"),
                std::string::npos)
          << r.out;
    }
    // Every rest example carries its load, holds the penetration target and
    // inverts no tet.
    if (t.rfind("palpa rest ", 0) == 0) {
      const std::string out =
          t.substr(t.find(" -o ") + 4, t.find(' ', t.find(" -o ") + 4) - t.find(" -o ") - 4);
      const auto s = nlohmann::json::parse(test::read_text(dir / out / "summary.json"));
      EXPECT_LT(s["balance_error"].get<double>(), 5e-3) << t;
      EXPECT_NEAR(s["max_penetration_m"].get<double>(), 3e-4, 0.15 * 3e-4) << t;
      EXPECT_GT(s["min_det_F"].get<double>(), 0.0) << t;
      EXPECT_GT(s["contacts"]["body_vertices"].get<int>(), 20) << t;
      if (out.rfind("foot", 0) == 0) {
        // The pitch torque (2 N·m about +y) is carried by the contact moment.
        EXPECT_NEAR(s["contact_torque_Nm"][1].get<double>(), -2.0, 0.1);
      }
      if (out == "chair") EXPECT_GT(s["body"]["self_intersections_removed"].get<int>(), 0);
    }
    // The walkthrough ends in the subject's report, with every step's part in it.
    if (t.rfind("palpa subject report ", 0) == 0) {
      const std::string page = test::read_text(dir / t.substr(t.find(" -o ") + 4));
      // The locations' fits, the rest table, the design's headline and the comparison's figures.
      for (const char* part : {"buttock-left", "knee-right", "body PPI", "the body's ζ", "relative_rms"})
        EXPECT_NE(page.find(part), std::string::npos) << t << " has no " << part;
    }
  }
}

// A section's commands run in order in one folder. A section that works on
// the outputs of another runs after it, in its folder.
const std::map<std::string, std::string>& runs_after() {
  static const std::map<std::string, std::string> m{{"`palpa compare`", "`palpa design`"},
                                                    {"`palpa convert`", "`palpa mesh`"}};
  return m;
}

struct Group {
  std::string name;  // the section, or "a then b"
  std::vector<ReadmeCommand> commands;
};

void PrintTo(const Group& g, std::ostream* os) {
  *os << g.name << " (" << g.commands.size() << " commands)";
}

std::vector<Group> readme_groups() {
  std::vector<std::string> problems;
  const auto commands = readme_commands(test::read_text(test::source_path("README.md")), problems);
  std::vector<Group> groups;
  std::map<std::string, std::size_t> at;
  for (const auto& c : commands) {
    std::string key = c.section;
    if (const auto it = runs_after().find(key); it != runs_after().end()) key = it->second;
    if (!at.contains(key)) {
      at[key] = groups.size();
      groups.push_back(Group{key, {}});
    }
    Group& g = groups[at[key]];
    if (key != c.section && g.name.find(c.section) == std::string::npos)
      g.name += " then " + c.section;
    g.commands.push_back(c);
  }
  return groups;
}

std::string test_name(const std::string& section) {
  std::string n;
  for (const char ch : section) {
    if (std::isalnum(static_cast<unsigned char>(ch)))
      n += ch;
    else if (!n.empty() && n.back() != '_')
      n += '_';
  }
  while (!n.empty() && n.back() == '_') n.pop_back();
  return n.empty() ? "unnamed" : n;
}

class ReadmeSection : public ::testing::TestWithParam<Group> {};

TEST_P(ReadmeSection, EveryCommandRunsInOrderFromTheRepositoryRoot) {
  const Group& group = GetParam();
  const bool full = std::getenv("PALPA_README_FULL") != nullptr;
  ScratchDir dir;
  std::filesystem::create_directory_symlink(test::source_path("examples"), dir / "examples");
  std::vector<Ran> ran;
  for (const auto& c : group.commands) {
    if (!full && long_example(c.text)) {
      Ran skipped;
      skipped.command = c;
      skipped.exit_code = -2;
      ran.push_back(skipped);
      continue;
    }
    ran.push_back(run_in(c, full ? c.text : shortened(c.text), dir.path()));
    const Ran& r = ran.back();
    EXPECT_EQ(r.exit_code, 0) << "README.md:" << c.line << " (" << c.section << "): " << r.run
                              << "\nstderr: " << tail(r.err, 3000);
  }
  std::cout << fmt::format("{}: {} commands{}:\n", group.name, ran.size(),
                           full ? "" : " (iterative ones shortened)");
  for (const auto& r : ran) {
    std::cout << (r.exit_code == -2
                      ? fmt::format(
                            "  long, not run (PALPA_README_FULL=1 runs it)  README.md:{}  {}\n",
                            r.command.line, r.command.text.substr(0, 100))
                      : fmt::format("  {:7.1f} s  exit {}  README.md:{}  {}\n", r.seconds,
                                    r.exit_code, r.command.line, r.command.text.substr(0, 100)));
  }
  check_results(ran, dir);
}

INSTANTIATE_TEST_SUITE_P(Readme, ReadmeSection, ::testing::ValuesIn(readme_groups()),
                         [](const ::testing::TestParamInfo<Group>& info) {
                           return test_name(info.param.name);
                         });

TEST(ReadmeCli, HasCommandsInEverySectionAndNoneThatIsNotPalpa) {
  std::vector<std::string> problems;
  const auto commands = readme_commands(test::read_text(test::source_path("README.md")), problems);
  for (const auto& p : problems) ADD_FAILURE() << p;
  // A parser that finds nothing (a renamed heading) must not pass.
  EXPECT_GE(commands.size(), 40u);
  EXPECT_GE(std::count_if(commands.begin(), commands.end(),
                          [](const auto& c) { return "## " + c.section == kWalkthrough; }),
            12);
  const auto groups = readme_groups();
  EXPECT_GE(groups.size(), 9u);
  for (const auto& entry : runs_after()) {
    const std::string& section = entry.first;
    EXPECT_TRUE(std::any_of(commands.begin(), commands.end(),
                            [&](const auto& c) { return c.section == section; }))
        << section << " has no commands";
  }
}

// The examples in the help texts name bundled files, as the README does:
// every `examples/...` path a help text shows exists in the repository.
TEST(ReadmeCli, TheHelpExamplesNameBundledFiles) {
  std::size_t paths = 0;
  for (const char* command : {"--help", "demo --help", "material --help", "poke --help", "fit --help",
                              "sim3d --help", "mesh --help", "mesh layer --help", "rest --help",
                              "design --help", "compare --help", "convert --help", "acquire --help"}) {
    const test::CommandResult r = test::run_palpa(command);
    ASSERT_EQ(r.exit_code, 0) << "palpa " << command << "\n" << r.err;
    std::istringstream words(r.out);
    std::string word;
    while (words >> word) {
      const std::size_t at = word.find("examples/");
      if (at == std::string::npos) continue;
      std::string path = word.substr(at);
      while (!path.empty() && std::string(")],;'\"").find(path.back()) != std::string::npos) path.pop_back();
      ++paths;
      EXPECT_TRUE(std::filesystem::exists(test::source_path(path))) << "palpa " << command << " names " << path;
    }
  }
  // A help text without bundled examples (or a reader that finds none) must not pass.
  EXPECT_GE(paths, 10u);
}

TEST(ReadmeCli, TheCommandParserJoinsLinesAndStripsComments) {
  const std::string readme =
      "# x\n## Commands\n### `palpa a`\n```sh\ne=examples/acquire   # where\n"
      "palpa poke --x $e/f.csv \\\n    --unit '0.1 m' -o c.csv   # a comment\n```\n"
      "```json\n{\"not\": \"a command\"}\n```\n## File formats\n```sh\npalpa ignored\n```\n";
  std::vector<std::string> problems;
  const auto c = readme_commands(readme, problems);
  EXPECT_TRUE(problems.empty());
  ASSERT_EQ(c.size(), 1u);
  EXPECT_EQ(c[0].text, "palpa poke --x $e/f.csv --unit '0.1 m' -o c.csv");
  EXPECT_EQ(c[0].assignments, "e=examples/acquire; ");
  EXPECT_EQ(c[0].line, 6);
  EXPECT_EQ(c[0].section, "`palpa a`");

  problems.clear();
  readme_commands("## Commands\n```sh\nSCENE -o OUT\n```\n", problems);
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_NE(problems[0].find("not a palpa command"), std::string::npos);
}

TEST(ReadmeCli, TheWalkthroughIsOneSequenceAndShortenedCommandsKeepTheirOptions) {
  const std::string readme =
      "## A subject, step by step\n### 1. Acquire\n```sh\ns=examples/subject\nmkdir -p walk\n"
      "palpa subject check $s/x.json\n```\n### 2. Fit\n```sh\npalpa fit d.json --mesh-level 2 -o f\n```\n"
      "## Units\n```sh\nmkdir -p not-run\n```\n## Commands\n### `palpa a`\n```sh\npalpa design s.json -o d\n```\n";
  std::vector<std::string> problems;
  const auto c = readme_commands(readme, problems);
  EXPECT_TRUE(problems.empty());
  ASSERT_EQ(c.size(), 4u);
  for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(c[i].section, "A subject, step by step");
  EXPECT_EQ(c[1].text, "palpa subject check $s/x.json");
  // A variable holds across the walkthrough's blocks, and not past it.
  EXPECT_EQ(c[2].assignments, "s=examples/subject; ");
  EXPECT_EQ(c[3].section, "`palpa a`");
  EXPECT_EQ(c[3].assignments, "");
  EXPECT_EQ(shortened(c[2].text), "palpa fit d.json --mesh-level 0 -o f --max-iterations 1");
  EXPECT_EQ(shortened(c[3].text), "palpa design s.json -o d --iterations 1");
}

}  // namespace
}  // namespace palpa
