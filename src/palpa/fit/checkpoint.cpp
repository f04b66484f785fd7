// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/fit/checkpoint.hpp"

#include "palpa/core/text.hpp"

#include <fmt/format.h>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>

#include "palpa/core/checkpoint.hpp"
#include "palpa/core/atomic_file.hpp"
#include "palpa/core/error.hpp"
#include "palpa/material/material_file.hpp"

namespace palpa::fit {

namespace {

std::string file_text(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

Json vector_json(const Eigen::VectorXd& v) { return Json(std::vector<double>(v.data(), v.data() + v.size())); }

Eigen::VectorXd json_vector(const JsonView& v) {
  const std::vector<double> a = v.as_number_array();
  return Eigen::Map<const Eigen::VectorXd>(a.data(), static_cast<Eigen::Index>(a.size()));
}

// The warm-start file: "palpa-warm-start 2\n", then little-endian u64
// counts and f64 values: #curves; per curve max_depth, then the solutions of
// each mesh (that of the mesh level, then of the coarser one extrapolation
// uses): their count, and per solution its size and entries.
constexpr std::string_view kWarmMagic = "palpa-warm-start 2\n";

void put_u64(std::string& out, std::uint64_t v) { out.append(reinterpret_cast<const char*>(&v), sizeof v); }
void put_f64(std::string& out, double v) { out.append(reinterpret_cast<const char*>(&v), sizeof v); }

std::string warm_bytes(const std::vector<axisym::WarmStart>& warm) {
  std::string out(kWarmMagic);
  put_u64(out, warm.size());
  for (const axisym::WarmStart& w : warm) {
    put_f64(out, w.max_depth);
    for (const auto* level : {&w.solutions, &w.coarse_solutions}) {
      put_u64(out, level->size());
      for (const Eigen::VectorXd& x : *level) {
        put_u64(out, static_cast<std::uint64_t>(x.size()));
        out.append(reinterpret_cast<const char*>(x.data()), static_cast<std::size_t>(x.size()) * sizeof(double));
      }
    }
  }
  return out;
}

// Reads what warm_bytes wrote; false if the bytes do not hold exactly that.
bool parse_warm(std::string_view bytes, std::vector<axisym::WarmStart>& warm) {
  if (bytes.substr(0, kWarmMagic.size()) != kWarmMagic) return false;
  std::size_t at = kWarmMagic.size();
  const auto take = [&](void* dst, std::size_t n) {
    if (bytes.size() - at < n) return false;
    std::memcpy(dst, bytes.data() + at, n);
    at += n;
    return true;
  };
  std::uint64_t curves = 0;
  if (!take(&curves, 8) || curves > bytes.size()) return false;
  warm.assign(static_cast<std::size_t>(curves), {});
  for (axisym::WarmStart& w : warm) {
    if (!take(&w.max_depth, 8)) return false;
    for (auto* level : {&w.solutions, &w.coarse_solutions}) {
      std::uint64_t count = 0;
      if (!take(&count, 8) || count > bytes.size()) return false;
      level->resize(static_cast<std::size_t>(count));
      for (Eigen::VectorXd& x : *level) {
        std::uint64_t n = 0;
        if (!take(&n, 8) || n > (bytes.size() - at) / sizeof(double)) return false;
        x.resize(static_cast<Eigen::Index>(n));
        if (!take(x.data(), static_cast<std::size_t>(n) * sizeof(double))) return false;
      }
    }
  }
  return at == bytes.size();
}

}  // namespace

Checkpoint::Checkpoint(std::filesystem::path path, const Dataset& d, const FitOptions& o,
                       const material::Material& initial)
    : path_(std::move(path)) {
  if (path_.empty()) return;
  std::string text = file_text(d.file);
  for (const auto& c : d.curves) text += "\n--\n" + file_text(c.file);
  Json opts{{"model", o.model},
            {"optimizer", std::string(to_string(o.optimizer))},
            {"max_iterations", o.max_iterations},
            {"function_tolerance", o.function_tolerance},
            {"mesh_level", o.simulation.mesh_level},
            {"extrapolate", o.simulation.extrapolate},
            {"steps", o.simulation.steps},
            {"element", static_cast<int>(o.simulation.element)},
            {"fillet", o.simulation.fillet_radius},
            {"fixed", o.fixed},
            {"nu_range", {poisson_range(d, o).lo, poisson_range(d, o).hi}},
            {"coordinates", 2},
            {"ogden_terms", o.ogden_terms},
            {"starts", o.starts},
            {"start_iterations", o.start_iterations},
            {"spline", {o.spline_layout.f.lo, o.spline_layout.f.hi, o.spline_layout.f.knots, o.spline_layout.g.lo,
                        o.spline_layout.g.hi, o.spline_layout.g.knots, o.spline_layout.h.lo, o.spline_layout.h.hi,
                        o.spline_layout.h.knots}},
            {"modulus_only", o.modulus_only},
            {"adapt_spline_ranges", o.adapt_spline_ranges},
            {"smoothing", o.smoothing},
            {"depth_from", std::string(to_string(o.depth_from))},
            {"initial", material::material_to_json(initial)}};
  text += "\n--\n" + opts.dump();
  fingerprint_ = palpa::fingerprint(text);
  doc_ = checkpoint_document("fit", fingerprint_);
  doc_["guesses"] = Json::object();
}

void Checkpoint::load() {
  if (path_.empty()) {
    throw_input_error("there is no checkpoint to resume from", ErrorContext{"", 0, 0, "resume"},
                      "an output folder of an interrupted fit");
  }
  if (!std::filesystem::exists(path_)) {
    throw_input_error(fmt::format("checkpoint '{}' does not exist", path_.string()),
                      ErrorContext{path_.string(), 0, 0, ""}, "the output folder of an interrupted fit");
  }
  doc_ = read_checkpoint(
      path_, {"fit", fingerprint_, "the dataset, its curve files or the fit options differ from the interrupted fit's",
              "the same dataset and options as the interrupted fit (or start afresh without --resume)"});
}

void Checkpoint::store(std::size_t g, const GuessResult& r, const GuessState& s,
                       const std::vector<axisym::WarmStart>* warm) {
  if (path_.empty()) return;
  const std::string key = std::to_string(g);
  const Json before = doc_["guesses"].contains(key) ? doc_["guesses"][key] : Json();
  std::string old_warm;
  if (doc_["guesses"].contains(key) && doc_["guesses"][key].contains("warm_start")) {
    old_warm = doc_["guesses"][key]["warm_start"]["file"].get<std::string>();
  }
  Json warm_json;
  if (warm != nullptr && !warm->empty() && !r.done) {
    if (warm_serial_.size() <= g) warm_serial_.resize(g + 1, 0);
    const std::string name =
        fmt::format("{}.warm-{}-{}.bin", path_.stem().string(), g, ++warm_serial_[g]);
    const std::string bytes = warm_bytes(*warm);
    write_file_atomic(path_.parent_path() / name, [&](std::ostream& out) { out << bytes; }, true);
    warm_json = Json{{"file", name}, {"bytes", bytes.size()}, {"fingerprint", palpa::fingerprint(bytes)}};
  }
  Json hist = Json::array();
  for (const auto& h : r.history) hist.push_back({h.iteration, h.objective, h.evaluations, h.seconds});
  Json st{{"x", vector_json(s.x)},
          {"gradient", vector_json(s.gradient)},
          {"direction", vector_json(s.direction)},
          {"objective", s.objective},
          {"step", s.step},
          {"slope", s.slope},
          {"since_restart", s.since_restart},
          {"trust_region_radius", s.trust_region_radius},
          {"solver_iterations", s.solver_iterations}};
  doc_["guesses"][key] = Json{
      {"layer_depth_m", r.layer_depth},
      {"modulus_scale", r.modulus_scale},
      {"sum_sim_squared", r.sum_sim_squared},
      {"objective_initial", r.objective_initial},
      {"objective_stage1", r.objective_stage1},
      {"objective_final", r.objective_final},
      {"stage1_material", material::material_to_json(*r.stage1_material)},
      {"stage2_start", material::material_to_json(*r.stage2_start)},
      {"material", material::material_to_json(*r.material)},
      {"history", hist},
      {"iterations", r.iterations},
      {"evaluations", r.evaluations},
      {"seconds", r.seconds},
      {"termination", std::string(to_string(r.stop.termination))},
      {"stop_reason", r.stop.detail},
      {"done", r.done},
      {"state", st}};
  if (!r.starts.empty()) {
    Json starts = Json::array();
    for (const auto& t : r.starts) {
      starts.push_back({{"label", t.label},
                        {"objective_start", number_or_null(t.objective_start)},
                        {"objective_end", number_or_null(t.objective_end)},
                        {"evaluations", t.evaluations}});
    }
    doc_["guesses"][key]["starts"] = starts;
  }
  if (!warm_json.is_null()) doc_["guesses"][key]["warm_start"] = warm_json;
  try {
    write_json_file(path_, doc_);
  } catch (...) {
    // The checkpoint on disk is the one before: the warm-start file just
    // written is named by nothing, and goes.
    if (!warm_json.is_null()) {
      std::error_code ec;
      std::filesystem::remove(path_.parent_path() / warm_json["file"].get<std::string>(), ec);
    }
    if (before.is_null()) {
      doc_["guesses"].erase(key);
    } else {
      doc_["guesses"][key] = before;
    }
    throw;
  }
  // Only now is the previous warm-start file no longer named.
  if (!old_warm.empty() && (warm_json.is_null() || warm_json["file"] != old_warm)) {
    std::error_code ec;
    std::filesystem::remove(path_.parent_path() / old_warm, ec);
  }
}

bool Checkpoint::done(std::size_t g) const {
  if (path_.empty() || !doc_.contains("guesses")) return false;
  const std::string key = std::to_string(g);
  if (!doc_["guesses"].contains(key)) return false;
  return JsonView(doc_["guesses"][key], path_.string(), "guesses." + key).at("done").as_bool();
}

bool Checkpoint::restore(std::size_t g, GuessResult& r, GuessState& s, std::vector<axisym::WarmStart>* warm) const {
  if (path_.empty() || !doc_.contains("guesses")) return false;
  const std::string key = std::to_string(g);
  if (!doc_["guesses"].contains(key)) return false;
  const JsonView v(doc_["guesses"][key], path_.string(), "guesses." + key);
  r.layer_depth = v.at("layer_depth_m").as_number();
  r.modulus_scale = v.at("modulus_scale").as_number();
  r.sum_sim_squared = v.has("sum_sim_squared") ? v.at("sum_sim_squared").as_number() : 0.0;
  r.objective_initial = v.at("objective_initial").as_number();
  r.objective_stage1 = v.at("objective_stage1").as_number();
  r.objective_final = v.at("objective_final").as_number();
  r.stage1_material = std::shared_ptr<material::Material>(material::material_from_json(v.at("stage1_material")));
  r.stage2_start = std::shared_ptr<material::Material>(material::material_from_json(v.at("stage2_start")));
  r.material = std::shared_ptr<material::Material>(material::material_from_json(v.at("material")));
  r.history.clear();
  const JsonView h = v.at("history");
  for (std::size_t i = 0; i < h.size(); ++i) {
    const std::vector<double> a = h.at(i).as_number_array();
    if (a.size() != 4) h.at(i).fail("not [iteration, objective, evaluations, seconds]");
    r.history.push_back(IterationRecord{static_cast<int>(a[0]), a[1], static_cast<int>(a[2]), a[3]});
  }
  r.starts.clear();
  if (v.has("starts")) {
    const JsonView t = v.at("starts");
    for (std::size_t i = 0; i < t.size(); ++i) {
      const JsonView e = t.at(i);
      const auto number = [&](const char* name) {
        return e.at(name).json().is_null() ? std::numeric_limits<double>::infinity() : e.at(name).as_number();
      };
      r.starts.push_back(StartTrial{e.at("label").as_string(), number("objective_start"), number("objective_end"),
                                    static_cast<int>(e.at("evaluations").as_integer())});
    }
  }
  r.iterations = static_cast<int>(v.at("iterations").as_integer());
  r.evaluations = static_cast<int>(v.at("evaluations").as_integer());
  r.seconds = v.at("seconds").as_number();
  r.stop.termination = parse_termination(v.at("termination").as_string(), v.at("termination").context());
  r.stop.detail = v.at("stop_reason").as_string();
  r.done = v.at("done").as_bool();
  const JsonView st = v.at("state");
  s.x = json_vector(st.at("x"));
  s.gradient = json_vector(st.at("gradient"));
  s.direction = json_vector(st.at("direction"));
  s.objective = st.at("objective").as_number();
  s.step = st.at("step").as_number();
  s.slope = st.at("slope").as_number();
  s.since_restart = static_cast<int>(st.at("since_restart").as_integer());
  // (Checkpoints written before it was saved restart the trust region.)
  s.trust_region_radius = st.has("trust_region_radius") ? st.at("trust_region_radius").as_number() : 0.0;
  s.solver_iterations = st.has("solver_iterations") ? static_cast<int>(st.at("solver_iterations").as_integer()) : 0;
  if (warm != nullptr && v.has("warm_start")) {
    const JsonView w = v.at("warm_start");
    const std::string name = w.at("file").as_string();
    const std::filesystem::path file = path_.parent_path() / name;
    const std::string bytes = file_text(file);
    if (!std::filesystem::exists(file) || bytes.size() != static_cast<std::size_t>(w.at("bytes").as_integer()) ||
        palpa::fingerprint(bytes) != w.at("fingerprint").as_string() || !parse_warm(bytes, *warm)) {
      w.at("file").fail(fmt::format("the warm-start file '{}' beside the checkpoint is missing or damaged",
                                    file.string()),
                        "the output folder of the interrupted fit as it was left (or start afresh without --resume)");
    }
  }
  return true;
}

}  // namespace palpa::fit
