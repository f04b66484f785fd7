// SPDX-License-Identifier: AGPL-3.0-or-later
// Checkpoint and resume: a fit interrupted after its second iteration and
// resumed ends where an uninterrupted fit ends, bit for bit (nonlinear CG,
// and Levenberg–Marquardt, whose trust-region radius and iteration count,
// rejected steps included, are checkpointed); a checkpoint of another fit is
// refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "common/test_support.hpp"
#include "fit/fit_fixtures.hpp"
#include "palpa/core/interrupt.hpp"
#include "palpa/fit/fit.hpp"
#include "palpa/material/models.hpp"

namespace palpa::fit {
namespace {

using palpa::test::ScratchDir;

constexpr int kInterruptAfter = 2;

Dataset small_dataset(const ScratchDir& dir) {
  test::IndentationSpec spec;
  spec.true_depth = 6e-3;
  spec.layer_depth = "6 mm";
  spec.train_radii = {3e-3};
  spec.max_depth = 1.2e-3;
  spec.points = 8;
  spec.mesh_level = 0;
  spec.salt = 13;
  return read_dataset(test::write_indentation_dataset(dir.path(), material::NeoHookean(20e3, 0.3), spec).dataset);
}

FitOptions options(Optimizer opt) {
  FitOptions o;
  o.model = "neo-hookean";
  o.optimizer = opt;
  o.max_iterations = 6;
  o.function_tolerance = 1e-12;  // run every iteration
  o.simulation.mesh_level = 0;
  o.simulation.steps = 8;
  return o;
}

struct Runs {
  GuessResult whole;
  GuessResult resumed;
};

Runs interrupted_and_resumed(const Dataset& d, const FitOptions& o, const std::filesystem::path& checkpoint,
                             int interrupt_after = kInterruptAfter) {
  Runs runs;
  runs.whole = fit_dataset(d, o).guesses.at(0);

  FitControl c;
  c.checkpoint = checkpoint;
  int last = -1;
  c.on_iteration = [&](std::size_t, const GuessResult& r) {
    last = r.iterations;
    if (r.iterations == interrupt_after) request_interrupt();
  };
  try {
    fit_dataset(d, o, c);
    ADD_FAILURE() << "the fit was not interrupted";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::Interrupted) << e.what();
  }
  clear_interrupt();
  EXPECT_EQ(last, interrupt_after);
  EXPECT_TRUE(std::filesystem::exists(checkpoint));

  FitControl resume;
  resume.checkpoint = checkpoint;
  resume.resume = true;
  int first = -1;
  resume.on_iteration = [&](std::size_t, const GuessResult& r) {
    if (first < 0) first = r.iterations;
  };
  runs.resumed = fit_dataset(d, o, resume).guesses.at(0);
  // It continues after the checkpointed iteration (interrupted after the
  // last, it only reports where it ended).
  EXPECT_EQ(first, std::min(interrupt_after + 1, runs.whole.iterations))
      << "the resumed fit continues after the checkpointed iteration";
  return runs;
}

// The resumed run took the uninterrupted run's steps, bit for bit.
void expect_bit_for_bit(const Runs& runs) {
  EXPECT_EQ(runs.resumed.iterations, runs.whole.iterations);
  EXPECT_EQ(runs.resumed.material->params(), runs.whole.material->params());
  EXPECT_EQ(runs.resumed.objective_final, runs.whole.objective_final);
  EXPECT_EQ(runs.resumed.modulus_scale, runs.whole.modulus_scale);
  ASSERT_EQ(runs.resumed.history.size(), runs.whole.history.size());
  for (std::size_t k = 0; k < runs.whole.history.size(); ++k) {
    EXPECT_EQ(runs.resumed.history[k].objective, runs.whole.history[k].objective) << "iteration " << k;
  }
}

// At mesh level 1 the forces are extrapolated with level 0: both meshes'
// warm starts are checkpointed.
TEST(Checkpoint, ResumedNlcgEndsBitForBitWhereAnUninterruptedFitEnds) {
  ScratchDir dir;
  const Dataset d = small_dataset(dir);
  FitOptions o = options(Optimizer::Nlcg);
  o.simulation.mesh_level = 1;
  const Runs runs = interrupted_and_resumed(d, o, dir / "checkpoint.json");
  ASSERT_GT(runs.whole.iterations, kInterruptAfter) << runs.whole.stop.detail;
  expect_bit_for_bit(runs);
  RecordProperty("iterations", runs.whole.iterations);
}

// The trust-region radius is checkpointed with the point: the resumed
// Levenberg–Marquardt takes the uninterrupted run's steps, bit for bit.
TEST(Checkpoint, ResumedLmEndsBitForBitWhereAnUninterruptedFitEnds) {
  ScratchDir dir;
  const Dataset d = small_dataset(dir);
  FitOptions o = options(Optimizer::LevenbergMarquardt);
  o.max_iterations = 40;
  o.function_tolerance = 1e-9;
  const Runs runs = interrupted_and_resumed(d, o, dir / "checkpoint.json");
  ASSERT_GT(runs.whole.iterations, kInterruptAfter + 1) << runs.whole.stop.detail;
  expect_bit_for_bit(runs);
  RecordProperty("iterations", runs.whole.iterations);
}

// Levenberg–Marquardt's iteration limit counts its rejected steps too: a fit
// that rejected a step before the interrupt and then runs into the limit
// stops where the uninterrupted one stops (with the accepted iterations as
// the count, the resumed one had a step more to try).
TEST(Checkpoint, ResumedLmStopsAtTheIterationLimitWhereAnUninterruptedFitStops) {
  ScratchDir dir;
  test::IndentationSpec spec;
  spec.train_radii = {3e-3};
  spec.points = 6;
  spec.mesh_level = 0;
  spec.noise_rel = spec.noise_abs = 0.0;  // noise-free: the fit ends in tiny steps, some rejected
  const Dataset d = read_dataset(
      test::write_indentation_dataset(dir.path(), material::NeoHookean(20e3, 0.3), spec).dataset);
  FitOptions o = options(Optimizer::LevenbergMarquardt);
  o.max_iterations = 15;
  o.simulation.steps = 6;
  const GuessResult whole = fit_dataset(d, o).guesses.at(0);
  ASSERT_EQ(whole.stop.termination, Termination::IterationLimit) << whole.stop.detail;
  const int accepted = whole.iterations;
  ASSERT_LT(accepted, o.max_iterations) << "no step was rejected: the case does not test the limit";
  // Interrupted after its last accepted step: the rejected one came before.
  const Runs runs = interrupted_and_resumed(d, o, dir / "checkpoint.json", accepted);
  expect_bit_for_bit(runs);
}

std::vector<std::filesystem::path> warm_files(const std::filesystem::path& dir) {
  std::vector<std::filesystem::path> out;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    if (e.path().filename().string().starts_with("checkpoint.warm-")) out.push_back(e.path());
  }
  return out;
}

// The simulators' warm starts live in one binary file beside the checkpoint
// while the fit runs; a damaged one is refused by name; a finished fit leaves
// none behind.
TEST(Checkpoint, KeepsOneWarmStartFileAndRefusesADamagedOne) {
  ScratchDir dir;
  const Dataset d = small_dataset(dir);
  const FitOptions o = options(Optimizer::Nlcg);
  FitControl c;
  c.checkpoint = dir / "checkpoint.json";
  c.on_iteration = [&](std::size_t, const GuessResult& r) {
    if (r.iterations == kInterruptAfter) request_interrupt();
  };
  EXPECT_TRUE(palpa::test::throws_error([&] { fit_dataset(d, o, c); }, ErrorKind::Interrupted, {}));
  clear_interrupt();
  const auto files = warm_files(dir.path());
  ASSERT_EQ(files.size(), 1u);
  const std::uintmax_t size = std::filesystem::file_size(files[0]);
  EXPECT_GT(size, 1000u);

  FitControl resume;
  resume.checkpoint = c.checkpoint;
  resume.resume = true;
  std::filesystem::copy_file(files[0], dir / "saved.bin");
  std::filesystem::resize_file(files[0], size - 8);
  EXPECT_TRUE(palpa::test::throws_error([&] { fit_dataset(d, o, resume); }, ErrorKind::Input,
                                        {files[0].filename().string(), "missing or damaged", "warm_start"}));
  std::filesystem::remove(files[0]);
  EXPECT_TRUE(palpa::test::throws_error([&] { fit_dataset(d, o, resume); }, ErrorKind::Input,
                                        {files[0].filename().string(), "missing or damaged"}));
  std::filesystem::copy_file(dir / "saved.bin", files[0]);
  const FitResult done = fit_dataset(d, o, resume);
  EXPECT_TRUE(done.guesses.at(0).done);
  EXPECT_TRUE(warm_files(dir.path()).empty());
}

// Ctrl-C during a layer-depth search, while several guesses run at once:
// every guess stops at its next check and the fit throws Interrupted (the
// interrupt must not cancel a guess's own parallel loops half done, which
// left it reading simulations that never ran), with the checkpoint written.
TEST(Checkpoint, AnInterruptDuringADepthSearchThrowsInterrupted) {
  for (const Optimizer opt : {Optimizer::LevenbergMarquardt, Optimizer::Nlcg}) {
    SCOPED_TRACE(std::string(to_string(opt)));
    ScratchDir dir;
    test::IndentationSpec spec;
    spec.true_depth = 6e-3;
    spec.layer_depth = Json{{"from", "4 mm"}, {"to", "8 mm"}, {"count", 4}};
    spec.train_radii = {2e-3, 3e-3, 4e-3};
    spec.max_depth = 1.2e-3;
    spec.points = 8;
    spec.mesh_level = 0;
    spec.salt = 17;
    const Dataset d =
        read_dataset(test::write_indentation_dataset(dir.path(), material::NeoHookean(20e3, 0.3), spec).dataset);
    ASSERT_EQ(d.layer_depths.size(), 4u);
    FitControl c;
    c.checkpoint = dir / "checkpoint.json";
    // At the first recorded iteration of any guess: the other guesses are
    // then inside their simulations.
    c.on_iteration = [&](std::size_t, const GuessResult&) { request_interrupt(); };
    EXPECT_TRUE(palpa::test::throws_error([&] { fit_dataset(d, options(opt), c); }, ErrorKind::Interrupted, {}));
    clear_interrupt();
    EXPECT_TRUE(std::filesystem::exists(c.checkpoint));
  }
}

// A depth search that chooses on the small indentations fits one guess: an
// interrupt inside it resumes there (the profile is recomputed, the same
// guess chosen) and ends bit for bit where an uninterrupted search ends; the
// finished search counts as finished with that one guess done.
TEST(Checkpoint, ASmallIndentationDepthSearchResumesItsChosenGuess) {
  ScratchDir dir;
  test::IndentationSpec spec;
  spec.true_depth = 6e-3;
  spec.layer_depth = Json{{"from", "4 mm"}, {"to", "8 mm"}, {"count", 3}};
  spec.train_radii = {2e-3, 3e-3, 4e-3};
  spec.max_depth = 1.2e-3;
  spec.points = 30;
  spec.mesh_level = 0;
  spec.poisson = 0.3;  // the profile holds ν at the dataset's (0.45 here would choose 8 mm)
  spec.salt = 19;
  const Dataset d =
      read_dataset(test::write_indentation_dataset(dir.path(), material::NeoHookean(20e3, 0.36), spec).dataset);
  FitOptions o = options(Optimizer::LevenbergMarquardt);
  o.max_iterations = 40;
  o.function_tolerance = 1e-9;
  const FitResult whole = fit_dataset(d, o);
  ASSERT_TRUE(whole.small_profile.has_value());
  EXPECT_EQ(whole.best, 1u);  // 6 mm
  const GuessResult& w = whole.guesses[whole.best];
  constexpr int kStopAfter = 1;  // (it converges in 3)
  ASSERT_GT(w.iterations, kStopAfter + 1) << w.stop.detail;

  FitControl c;
  c.checkpoint = dir / "checkpoint.json";
  c.on_iteration = [&](std::size_t, const GuessResult& r) {
    if (r.iterations == kStopAfter) request_interrupt();
  };
  EXPECT_TRUE(palpa::test::throws_error([&] { fit_dataset(d, o, c); }, ErrorKind::Interrupted, {}));
  clear_interrupt();
  EXPECT_FALSE(fit_finished(d, o, c.checkpoint));
  c.resume = true;
  c.on_iteration = nullptr;
  const FitResult resumed = fit_dataset(d, o, c);
  ASSERT_EQ(resumed.best, whole.best);
  const GuessResult& r = resumed.guesses[resumed.best];
  EXPECT_EQ(r.iterations, w.iterations);
  EXPECT_EQ(r.material->params(), w.material->params());
  EXPECT_EQ(r.objective_final, w.objective_final);
  EXPECT_TRUE(fit_finished(d, o, c.checkpoint));
}

TEST(Checkpoint, ACheckpointOfAnotherFitIsRefused) {
  ScratchDir dir;
  const Dataset d = small_dataset(dir);
  FitOptions o = options(Optimizer::Nlcg);
  o.max_iterations = 1;
  FitControl c;
  c.checkpoint = dir / "checkpoint.json";
  fit_dataset(d, o, c);
  ASSERT_TRUE(std::filesystem::exists(c.checkpoint));
  c.resume = true;
  // Other options.
  FitOptions other = o;
  other.model = "ogden";
  EXPECT_TRUE(palpa::test::throws_error([&] { fit_dataset(d, other, c); }, ErrorKind::Input,
                                        {"checkpoint.json", "fingerprint", "differ"}));
  // Another dataset (one curve value changed).
  ScratchDir dir2;
  Dataset d2 = small_dataset(dir2);
  test::write_force_csv(d2.curves[0].file, {d2.curves[0].x, std::vector<double>(d2.curves[0].y.size(), 0.5)});
  d2 = read_dataset(d2.file);
  EXPECT_TRUE(palpa::test::throws_error([&] { fit_dataset(d2, o, c); }, ErrorKind::Input,
                                        {"checkpoint.json", "fingerprint"}));
  // No checkpoint at all.
  FitControl none;
  none.checkpoint = dir / "none.json";
  none.resume = true;
  EXPECT_TRUE(palpa::test::throws_error([&] { fit_dataset(d, o, none); }, ErrorKind::Input, {"none.json", "does not exist"}));
  // The same fit resumes (it is done: nothing to do, same result).
  const FitResult again = fit_dataset(d, o, c);
  EXPECT_TRUE(again.guesses.at(0).done);
}

}  // namespace
}  // namespace palpa::fit
