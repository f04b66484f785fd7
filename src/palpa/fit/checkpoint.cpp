#include "palpa/fit/checkpoint.hpp"

#include "palpa/core/text.hpp"

#include <fmt/format.h>

#include <fstream>
#include <sstream>

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
            {"steps", o.simulation.steps},
            {"element", static_cast<int>(o.simulation.element)},
            {"fillet", o.simulation.fillet_radius},
            {"fixed", o.fixed},
            {"ogden_terms", o.ogden_terms},
            {"spline", {o.spline_layout.f.lo, o.spline_layout.f.hi, o.spline_layout.f.knots, o.spline_layout.g.lo,
                        o.spline_layout.g.hi, o.spline_layout.g.knots, o.spline_layout.h.lo, o.spline_layout.h.hi,
                        o.spline_layout.h.knots}},
            {"modulus_only", o.modulus_only},
            {"adapt_spline_ranges", o.adapt_spline_ranges},
            {"smoothing", o.smoothing},
            {"initial", material::material_to_json(initial)}};
  text += "\n--\n" + opts.dump();
  fingerprint_ = palpa::fingerprint(text);
  doc_ = Json{{"palpa_fit_checkpoint", 1}, {"fingerprint", fingerprint_}, {"guesses", Json::object()}};
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
  Json j = read_json_file(path_);
  const JsonView v(j, path_.string());
  if (!v.is_object() || !v.has("palpa_fit_checkpoint")) v.fail("not a fit checkpoint", "a palpa fit checkpoint");
  if (v.at("fingerprint").as_string() != fingerprint_) {
    v.at("fingerprint").fail("the dataset, its curve files or the fit options differ from the interrupted fit's",
                             "the same dataset and options as the interrupted fit (or start afresh without --resume)");
  }
  doc_ = std::move(j);
}

void Checkpoint::store(std::size_t g, const GuessResult& r, const GuessState& s) {
  if (path_.empty()) return;
  Json hist = Json::array();
  for (const auto& h : r.history) hist.push_back({h.iteration, h.objective, h.evaluations, h.seconds});
  Json st{{"x", vector_json(s.x)},
          {"gradient", vector_json(s.gradient)},
          {"direction", vector_json(s.direction)},
          {"objective", s.objective},
          {"step", s.step},
          {"slope", s.slope},
          {"since_restart", s.since_restart}};
  doc_["guesses"][std::to_string(g)] = Json{
      {"layer_depth_m", r.layer_depth},
      {"modulus_scale", r.modulus_scale},
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
      {"stop_reason", r.stop_reason},
      {"done", r.done},
      {"state", st}};
  write_json_file(path_, doc_);
}

bool Checkpoint::restore(std::size_t g, GuessResult& r, GuessState& s) const {
  if (path_.empty() || !doc_.contains("guesses")) return false;
  const std::string key = std::to_string(g);
  if (!doc_["guesses"].contains(key)) return false;
  const JsonView v(doc_["guesses"][key], path_.string(), "guesses." + key);
  r.layer_depth = v.at("layer_depth_m").as_number();
  r.modulus_scale = v.at("modulus_scale").as_number();
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
  r.iterations = static_cast<int>(v.at("iterations").as_integer());
  r.evaluations = static_cast<int>(v.at("evaluations").as_integer());
  r.seconds = v.at("seconds").as_number();
  r.stop_reason = v.at("stop_reason").as_string();
  r.done = v.at("done").as_bool();
  const JsonView st = v.at("state");
  s.x = json_vector(st.at("x"));
  s.gradient = json_vector(st.at("gradient"));
  s.direction = json_vector(st.at("direction"));
  s.objective = st.at("objective").as_number();
  s.step = st.at("step").as_number();
  s.slope = st.at("slope").as_number();
  s.since_restart = static_cast<int>(st.at("since_restart").as_integer());
  return true;
}

}  // namespace palpa::fit
