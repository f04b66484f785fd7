// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/design/run.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <spdlog/spdlog.h>

#include "palpa/core/atomic_file.hpp"
#include "palpa/core/error.hpp"
#include "palpa/core/ranks.hpp"
#include "palpa/core/input_file.hpp"
#include "palpa/core/termination.hpp"
#include "palpa/design/average_impression.hpp"
#include "palpa/design/cohort_output.hpp"
#include "palpa/design/output.hpp"
#include "palpa/core/termination.hpp"
#include "palpa/design/scene.hpp"
#include "palpa/design/start.hpp"

namespace palpa::design {

namespace {

// Whether the finished run in `summary` could go on past its iteration limit
// to `max_iterations`; says why not otherwise.
bool can_go_on(const std::filesystem::path& summary, const std::filesystem::path& out, int max_iterations) {
  const Json done = read_json_file(summary, InputUse::RunState);
  const JsonView d(done, summary.string());
  const int iterations = static_cast<int>(d.at("iterations").as_integer());
  // (A summary without a termination was written by an older palpa: not resumed.)
  const auto termination = d.find("termination");
  const bool at_limit =
      termination && parse_termination(termination->as_string(), termination->context()) == Termination::IterationLimit;
  if (at_limit && iterations < max_iterations) return true;
  spdlog::info("design: the run in {} is finished ({} iterations, stopped by {}); nothing to resume{}", out.string(),
               iterations, d.at("stop_reason").as_string(),
               at_limit ? fmt::format(" (raise --iterations above {} to go on)", iterations) : std::string());
  return false;
}

// The scene as the run takes it: with --start, --iterations, --threads and
// --method applied.
DesignScene read_run_scene(const DesignRun& run) {
  std::optional<Json> doc = run.scene_json;
  if (run.start) {
    if (!doc) doc = read_json_file(run.scene);
    // (A scene that is not an object, or whose design is not one, is left
    // for the reader to refuse.)
    if (doc->is_object()) {
      const bool has_design = doc->contains("design");
      if (*run.start == "scene") {
        if (has_design && (*doc)["design"].is_object()) (*doc)["design"].erase("start");
      } else if (!has_design) {
        (*doc)["design"] = Json{{"start", *run.start}};
      } else if ((*doc)["design"].is_object()) {
        (*doc)["design"]["start"] = *run.start;
      }
    }
  }
  DesignScene scene = doc ? read_design_scene(*doc, run.scene, run.baselines) : read_design_scene(run.scene, run.baselines);
  if (run.iterations) scene.options.max_iterations = *run.iterations;
  if (run.threads) scene.options.threads = *run.threads;
  if (run.method) scene.options.method = *run.method;
  scene.options.checkpoint = run.out / "checkpoint.json";
  return scene;
}

// The output folder made ready and the scene read: whether the run resumes,
// or nothing (a finished run left as it is).
std::optional<DesignScene> prepare(const DesignRun& run) {
  const std::filesystem::path& out = run.out;
  const std::filesystem::path checkpoint = out / "checkpoint.json";
  const std::filesystem::path finished = out / "summary.json";
  bool resume = run.resume;
  // --resume where there is nothing to resume starts afresh, so that a
  // workflow can always pass it.
  if (resume && !std::filesystem::exists(checkpoint)) {
    if (!run.overwrite) require_empty_output(out);  // (--resume was given: not offered again)
    spdlog::info("design: no checkpoint in {}: starting afresh", out.string());
    resume = false;
  }
  if (!resume && !run.overwrite) require_empty_output(out, "design run");
  DesignScene scene = read_run_scene(run);
  // A finished run is resumed only to go on past the iteration limit it
  // stopped at; otherwise it is left exactly as it is.
  if (resume && std::filesystem::exists(finished) && !can_go_on(finished, out, scene.options.max_iterations)) {
    return std::nullopt;
  }
  scene.options.resume = resume;
  if (!resume) {
    // A fresh run leaves no result of an earlier one that could pass for its own.
    std::error_code ec;
    std::filesystem::remove(checkpoint, ec);
    std::filesystem::remove(finished, ec);
  }
  fit_sit_and_relax_start(scene);
  return scene;
}

// prepare() on rank 0, which alone touches the output folder; the other
// ranks learn how it went (fresh, resumed, finished, or its error) and read
// the scene themselves.
std::optional<DesignScene> prepare_on_ranks(const DesignRun& run) {
  if (ranks::size() == 1) return prepare(run);
  std::string status;
  std::optional<DesignScene> scene;
  if (ranks::is_root()) {
    try {
      scene = prepare(run);
      status = !scene ? "done" : scene->options.resume ? "resume" : "fresh";
    } catch (const Error& e) {
      status = fmt::format("error{} {}", static_cast<int>(e.kind()), e.what());
      ranks::broadcast(status, 0);
      throw;
    }
  }
  ranks::broadcast(status, 0);
  if (ranks::is_root()) return scene;
  if (status.starts_with("error")) {
    const std::size_t space = status.find(' ');
    throw Error(static_cast<ErrorKind>(std::stoi(status.substr(5, space - 5))), status.substr(space + 1));
  }
  if (status == "done") return std::nullopt;
  scene = read_run_scene(run);
  scene->options.resume = status == "resume";
  return scene;
}

// Each body's own design beside the cohort's: the same settings, the body
// alone on the support, on the rank that holds it; what it reaches (from
// scratch, on the initial and on its own optimized support) to every rank.
std::vector<Json> single_designs(const DesignScene& scene, const ShapeOptimizer& cohort) {
  std::vector<Json> out;
  for (std::size_t i = 0; i < scene.cohort.size(); ++i) {
    const CohortMember& m = scene.cohort[i];
    std::string bytes;
    if (cohort.holds(i)) {
      try {
        spdlog::info("design: the body '{}' alone: its own design, to compare with", m.name);
        DesignOptions o = scene.options;
        o.cohort.reset();
        o.local = true;
        o.checkpoint.clear();
        o.resume = false;
        // It begins where the cohort's does: the scene's support, or the
        // body's own negative image where the cohort begins on the average's.
        rest::RestBody body = m.rest.body;
        SurfaceMesh start = scene.rest.support;
        if (scene.cohort_start_on_baseline) {
          start = average_impression({&m.rest.body}, scene.rest.support, scene.design_vertices,
                                     scene.rest.options.gravity, *scene.cohort_baseline);
          rest::place_clear_of(body, start, -m.rest.options.gravity, 1e-3);
        }
        ShapeOptimizer single(std::vector<DesignBody>{DesignBody{{}, body, m.rest.options}}, start,
                              scene.design_vertices, o);
        const DesignResult r = single.run();
        const Eigen::MatrixX3i& F = single.simulation().support().triangles();
        // Against the scene's support, as the cohort's figures are.
        const Evaluation before = single.solve_from_scratch(m.rest.body, scene.rest.support);
        const Evaluation after = single.solve_from_scratch(m.rest.body, SurfaceMesh{r.final.support, F});
        if (!before.ok || !after.ok) {
          throw Error(ErrorKind::Solver, fmt::format("the body '{}''s own design, from scratch: {}", m.name,
                                                     before.ok ? after.failure : before.failure));
        }
        const double zb = after.body().score.zeta_body / before.body().score.zeta_body;
        spdlog::info("design: the body '{}' alone, from scratch: ζ_body {:.1f}% lower in {} iterations", m.name,
                     100.0 * (1.0 - zb), r.iterations);
        bytes = Json{{"zeta_body_ratio", zb},
                     {"zeta_ratio", after.zeta / before.zeta},
                     {"body_peak_ratio", before.body().score.body_pressure.maxCoeff() /
                                             after.body().score.body_pressure.maxCoeff()},
                     {"final", evaluation_json(after, 0.0)},
                     {"iterations", r.iterations},
                     {"termination", std::string(to_string(r.stop.termination))},
                     {"seconds", r.seconds}}
                    .dump();
      } catch (const Error& e) {
        if (ranks::size() == 1) throw;
        bytes = Json{{"error", static_cast<int>(e.kind())}, {"message", e.what()}}.dump();
      }
    }
    if (ranks::size() > 1) ranks::broadcast(bytes, cohort.owner(i));
    Json j = Json::parse(bytes);
    if (j.contains("error")) throw Error(static_cast<ErrorKind>(j["error"].get<int>()), j["message"].get<std::string>());
    out.push_back(std::move(j));
  }
  return out;
}

}  // namespace

std::optional<Json> run_design(const DesignRun& run, SurfaceMesh* optimized) {
  const std::filesystem::path& out = run.out;
  const std::filesystem::path checkpoint = out / "checkpoint.json";
  std::optional<DesignScene> prepared = prepare_on_ranks(run);
  if (!prepared) return std::nullopt;
  DesignScene& scene = *prepared;
  const bool resume = scene.options.resume;
  const bool cohort = !scene.cohort.empty();
  if (!scene.start.empty()) {
    spdlog::info("design: starting from the baseline '{}' (the scene's own support, {}, is scored beside it)",
                 scene.start, scene.scene_support->source);
  }
  std::vector<DesignBody> bodies;
  if (cohort) {
    for (const CohortMember& m : scene.cohort) {
      spdlog::info("design: {}: body '{}' from {} ({} vertices, {} tetrahedra)", run.scene.string(), m.name,
                   m.rest.body_source, m.rest.body.mesh.V.rows(), m.rest.body.mesh.T.rows());
      bodies.push_back(DesignBody{m.name, m.rest.body, m.rest.options});
    }
    spdlog::info("design: one support for {} bodies ({} of their scores{}): support {} ({} vertices), {}",
                 bodies.size(), to_string(scene.options.cohort->aggregate),
                 ranks::size() > 1 ? fmt::format(", over {} processes", ranks::size()) : std::string(),
                 scene.rest.support_source, scene.rest.support.V.rows(), scene.region);
  } else {
    spdlog::info("design: {}: body from {} ({} vertices, {} tetrahedra), support {} ({} vertices), {}",
                 run.scene.string(), scene.rest.body_source, scene.rest.body.mesh.V.rows(),
                 scene.rest.body.mesh.T.rows(), scene.rest.support_source, scene.rest.support.V.rows(), scene.region);
    bodies.push_back(DesignBody{{}, scene.rest.body, scene.rest.options});
  }
  // A cohort may begin on the negative image of its average body; its
  // bodies are then lifted clear of it where they start inside.
  SurfaceMesh start = scene.rest.support;
  if (cohort && scene.cohort_start_on_baseline) {
    std::vector<const rest::RestBody*> placed;
    for (const CohortMember& m : scene.cohort) placed.push_back(&m.rest.body);
    start = average_impression(placed, scene.rest.support, scene.design_vertices, scene.rest.options.gravity,
                               *scene.cohort_baseline);
    for (DesignBody& b : bodies) rest::place_clear_of(b.body, start, -b.rest.gravity, 1e-3);
    spdlog::info("design: the cohort begins on the negative image of its average body (press {:.3g} mm)",
                 scene.cohort_baseline->press * 1e3);
  }
  ShapeOptimizer optimizer(std::move(bodies), start, scene.design_vertices, scene.options);
  if (cohort) {
    std::vector<std::string> each;
    for (std::size_t i = 0; i < optimizer.num_bodies(); ++i) {
      each.push_back(fmt::format("{} {:.6g}", optimizer.body_name(i), optimizer.initial_zeta()[static_cast<Eigen::Index>(i)]));
    }
    spdlog::info("design: initial shape: each body's ζ {}; γ = {:.4g}, φ = {:.6g}; {} design variables",
                 fmt::join(each, ", "), optimizer.gamma(), optimizer.initial().phi, optimizer.space().size());
  } else {
    spdlog::info("design: initial shape: ζ = {:.6g}, γ = {:.4g}, φ = {:.6g}; {} design variables",
                 optimizer.initial().zeta, optimizer.gamma(), optimizer.initial().phi, optimizer.space().size());
  }
  // The other ranks solve their bodies with rank 0 until the run ends; rank
  // 0 alone writes (the checkpoint during the run, then the outputs).
  if (!ranks::is_root()) {
    optimizer.run();
    if (cohort && scene.single_designs) single_designs(scene, optimizer);
    return std::nullopt;
  }
  // Only now: bad input leaves nothing behind.
  OutputFolder folder(out, OutputFolder::OnFailure::RemoveIfEmpty, OutputFolder::Lock::Exclusive,
                      resume ? OutputFolder::Start::Resumed : OutputFolder::Start::Fresh);
  DesignResult r;
  std::vector<Json> singles;
  try {
    r = optimizer.run();
    if (cohort && scene.single_designs) singles = single_designs(scene, optimizer);
  } catch (const Error& e) {
    if (e.kind() == ErrorKind::Interrupted) {
      // The best shape so far, as a shape to look at or make; no summary (the
      // run is not finished, nothing is checked from scratch).
      if (optimizer.last_accepted().rows() > 0) {
        write_support_shape(out, "support_interrupted",
                            SurfaceMesh{optimizer.last_accepted(), optimizer.simulation().support().triangles()});
        spdlog::warn("design: interrupted; the last finished iteration is in {} and its support in "
                     "support_interrupted.obj (m) and support_interrupted_mm.stl: continue with --resume",
                     checkpoint.string());
      } else {
        spdlog::warn("design: interrupted before the first iteration finished: nothing to keep");
      }
    }
    throw;
  }
  // The outputs count together: a failure part way (a full disk, a shape that
  // no longer solves from scratch) takes back the ones already written.
  const std::size_t written_before = folder.written_count();
  Json s;
  try {
    s = cohort ? write_cohort_outputs(out, scene, optimizer, r, singles) : write_design_outputs(out, scene, optimizer, r);
  } catch (...) {
    folder.remove_written_since(written_before);
    throw;
  }
  for (const char* f : {"support_interrupted.obj", "support_interrupted_mm.stl"}) {
    std::error_code ec;
    std::filesystem::remove(out / f, ec);  // an interruption's shape is not this run's result
  }
  folder.keep();
  if (optimized != nullptr) *optimized = SurfaceMesh{r.final.support, optimizer.simulation().support().triangles()};
  return s;
}

std::string design_headline(const Json& s) {
  if (s.contains("cohort")) {
    return fmt::format("design: {}, {:.1f} s", cohort_headline_text(s), s["seconds"].get<double>());
  }
  const Json& initial = s["initial"];
  const Json& optimized = s["final"];
  std::string verdict;
  for (const Json& w : s["worse_than_baselines"]) {
    verdict += fmt::format("; WORSE than the baseline '{}' on {}", w["baseline"].get<std::string>(),
                           fmt::join(w["on"].get<std::vector<std::string>>(), " and "));
  }
  if (s.contains("start")) {
    const Json& st = s["start"];
    verdict += fmt::format("; against the scene's own support ζ {:.1f}% lower, ζ_body {:.1f}% lower, body peak {:.3g} → "
                           "{:.3g} kPa",
                           st["zeta_reduction_percent"].get<double>(), st["zeta_body_reduction_percent"].get<double>(),
                           st["scene_support"]["peak_pressure_Pa"]["body"].get<double>() * 1e-3,
                           optimized["peak_pressure_Pa"]["body"].get<double>() * 1e-3);
  }
  return fmt::format(
      "design: from scratch, ζ {:.6g} → {:.6g} ({:.1f}% lower; the optimizer's own view {:.1f}%), ζ_body {:.1f}% lower, "
      "peak pressure {:.3g} → {:.3g} kPa (body), max penetration {:.3g} mm, {} iterations, {} equilibria, {:.1f} s "
      "({}){}",
      initial["zeta"].get<double>(), optimized["zeta"].get<double>(), s["zeta_reduction_percent"].get<double>(),
      s["optimizer"]["zeta_reduction_percent"].get<double>(), s["zeta_body_reduction_percent"].get<double>(),
      initial["peak_pressure_Pa"]["body"].get<double>() * 1e-3, optimized["peak_pressure_Pa"]["body"].get<double>() * 1e-3,
      optimized["max_penetration_m"].get<double>() * 1e3, s["iterations"].get<int>(),
      s["equilibrium_solves"].get<int>(), s["seconds"].get<double>(), s["stop_reason"].get<std::string>(), verdict);
}

}  // namespace palpa::design
