// SPDX-License-Identifier: AGPL-3.0-or-later
// palpa command line. Exit codes: 0 success, 2 bad input or usage, 3 solver
// failure, 1 internal error, 130 interrupted (SIGINT), 143 stopped (SIGTERM).

#include <cstdlib>
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>
#include <memory>
#include <tbb/global_control.h>

#include "cli_common.hpp"
#include "commands.hpp"
#include "palpa/core/error.hpp"
#include "palpa/core/input_file.hpp"
#include "palpa/core/interrupt.hpp"
#include "palpa/core/log.hpp"
#include "palpa/core/parallel.hpp"
#include "palpa/core/ranks.hpp"
#include "palpa/core/version.hpp"
#include "palpa/solve/blas.hpp"

namespace {

// Writes to stderr without throwing, whatever stderr is (a full file, a
// file-size limit, a closed pipe): the exit code still says what happened.
void say(const std::string& line) noexcept { std::fputs(line.c_str(), stderr); }

int report(const palpa::Error& e) {
  // Spread over processes, each says it once: rank 0.
  if (!palpa::ranks::is_root()) return palpa::exit_code(e.kind());
  switch (e.kind()) {
    case palpa::ErrorKind::Input:
      say(fmt::format("palpa: error: {}\n", e.what()));
      break;
    case palpa::ErrorKind::Solver:
      say(fmt::format("palpa: solver failure: {}\n", e.what()));
      break;
    case palpa::ErrorKind::Interrupted:
      say("palpa: interrupted; no file was left half-written\n");
      break;
    case palpa::ErrorKind::Internal:
      say(fmt::format("palpa: internal error (please report): {}\n", e.what()));
      break;
  }
  return palpa::exit_code(e.kind());
}

int run(int argc, char** argv);

}  // namespace

int main(int argc, char** argv) {
  // Launched by mpirun or srun: one of several processes (a cohort design
  // spreads its bodies over them); otherwise no MPI at all.
  try {
    palpa::ranks::init(argc, argv);
  } catch (const palpa::Error& e) {
    return report(e);
  }
  const int code = run(argc, argv);
  palpa::ranks::finalize(code);
  return code;
}

namespace {

int run(int argc, char** argv) {
  palpa::set_default_blas_threads();
  // No output of a run replaces a file it read as an input (input_file.hpp).
  palpa::guard_inputs(true);
  CLI::App app{
      "palpa: soft-tissue mechanics. Turns poking measurements into fitted nonlinear tissue\n"
      "materials and uses them to shape supports (chairs, soles, mice) for even contact\n"
      "pressure. Values inside are SI; options take units (\"2 mm\", \"12 kPa\").",
      "palpa"};
  // The version, and the dense BLAS/LAPACK that CHOLMOD runs on (which one
  // Debian's alternatives chose decides the speed of large 3D factorizations).
  app.set_version_flag(
      "--version", [] { return std::string("palpa ") + palpa::kVersion + "\n" + palpa::describe_blas(); },
      "Print the version and the BLAS and LAPACK in use, then exit");
  app.require_subcommand(1);
  app.fallthrough();

  int verbose = 0;
  bool quiet = false;
  // At most this many cores for palpa's parallel loops and a design's
  // simultaneous equilibria (TBB's limit): one job of many on a shared node.
  int threads = 0;
  std::unique_ptr<tbb::global_control> thread_limit;
  app.add_option("--threads", threads, "Cores to use at most (default 0: all of this machine's)")
      ->check(CLI::Range(0, palpa::kMaxThreads));
  app.add_flag("-v,--verbose", verbose, "More output (repeat for more: -vv)");
  app.add_flag("-q,--quiet", quiet, "Only warnings and errors; no progress bars");

  palpa::cli::add_demo_command(app);
  palpa::cli::add_material_command(app);
  palpa::cli::add_poke_command(app);
  palpa::cli::add_fit_command(app);
  palpa::cli::add_sim3d_command(app);
  palpa::cli::add_rest_command(app);
  palpa::cli::add_design_command(app);
  palpa::cli::add_compare_command(app);
  palpa::cli::add_mesh_command(app);
  palpa::cli::add_acquire_command(app);
  palpa::cli::add_subject_command(app);
  palpa::cli::add_convert_command(app);
  palpa::cli::add_units_command(app);

  palpa::install_interrupt_handlers();
  try {
    app.parse_complete_callback([&] {
      palpa::Verbosity v = palpa::Verbosity::Normal;
      if (quiet) v = palpa::Verbosity::Quiet;
      if (verbose == 1) v = palpa::Verbosity::Verbose;
      if (verbose >= 2) v = palpa::Verbosity::Trace;
      palpa::configure_logging(v);
      // The other processes of an MPI run log only their errors: rank 0
      // tells the story.
      if (!palpa::ranks::is_root()) spdlog::set_level(spdlog::level::err);
      if (threads > 0) {
        thread_limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                             static_cast<std::size_t>(threads));
      }
      spdlog::debug("palpa {}; {}; cores: {}", palpa::kVersion, palpa::describe_blas(),
                    tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism));

      palpa::cli::check_distinct_paths(app);
    });
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? palpa::kExitOk : palpa::kExitInput;
  } catch (const palpa::Error& e) {
    return report(e);
  } catch (const std::bad_alloc&) {
    say("palpa: error: out of memory\n");
    return palpa::kExitInternal;
  } catch (const std::exception& e) {
    say(fmt::format("palpa: internal error (please report): {}\n", e.what()));
    return palpa::kExitInternal;
  }
  return palpa::kExitOk;
}

}  // namespace
