// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Scenes of `palpa design`: a rest scene (rest/scene.hpp) under the version
// key "palpa_design", plus what to optimize and how:
//
// {
//   "palpa_design": 1,
//   "body": {...}, "core": {...}, "support": {...}, "contact": {...}, ...
//   "design": {
//     "method": "cg",            // or "lbfgs"
//     "region": {"min": ["-100 mm", ...], "max": [...]},  // optional box [world]
//     "facing": "25 deg",        // only vertices whose normal is within this angle of −gravity
//     "direction": "normal",     // or "free": 3D moves
//     "exponent": 3,             // of the ergonomic score (2, 3 or 4)
//     "smoothing": {"exponent": -2, "iterations": 5},   // γ = 10^exponent · ζ0/ψ0; or {"gamma": 1e9}
//     "iterations": 30, "min_decrease": 1e-4,
//     "filter": "15 mm",         // radius of the design filter (design/filter.hpp); 0: per-vertex moves;
//                                // default 1.5 mean edge lengths of the region
//     "moves": ["1 um", "10 um", "0.1 mm", "0.2 mm", "0.5 mm", "0.7 mm", "1 mm", "2 mm"],
//     "threads": 0,              // simulations at once; 0: min(#moves, cores)
//     "post_smoothing": 0,       // Taubin rounds on the result
//     "pose_to_seat_threshold": "2 mm", // contact distance of the estimate without elasticity
//     "start": "sit and relax"   // begin from this baseline's support; the scene's own support
//                                // is scored beside it
//   },
//   "baselines": [{"name": "negative image", "support": {"negative_image": {...}}},
//                 {"name": "sit and relax", "sit_and_relax": {"support": {"negative_image": {...}},
//                                                             "smoothness": 1}}]
//     // other supports (the "support" format) scored alike; Sit & Relax: the
//     // pressures on that support frozen and the design region fitted to the
//     // body with them (design/baselines.hpp)
// }
//
// A cohort: one support for several bodies (design/cohort.hpp). "bodies"
// replaces "body"; each entry is a body of its own, its "body" and "core"
// from a scene file (each subject's design.json from `palpa subject body`) or
// given inline, everything else (support, contact, design) the cohort's:
//
// {
//   "palpa_design": 1,
//   "bodies": [{"name": "tiny-a", "scene": "out/tiny-a/body/design.json"},
//              {"name": "small", "body": {...}, "core": {...}}],  // "core": overrides the scene's
//   "cohort": {"objective": "mean",    // or "quantile" (with "quantile": 0.9), or "max" (with "sharpness": 0.05)
//              "single_designs": true,  // also each body's own design, to compare with
//              "baseline": {"press": "10 mm", "smoothing": 5}},  // the negative image of the average
//                                       // body, scored beside (the default; false: none)
//              "start": "baseline"}    // begin on that baseline instead of the scene's support
//   "support": {...}, "contact": {...}, "design": {...}
// }

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "palpa/design/average_impression.hpp"
#include "palpa/design/optimizer.hpp"
#include "palpa/rest/scene.hpp"

namespace palpa::design {

// Another support scored with the same physics as the optimized one.
struct Baseline {
  std::string name;
  rest::RestBody body;    // as placed for this support (a negative image lowers it)
  SurfaceMesh support;    // Sit & Relax: the negative image the pressures come from
  std::string source;
  bool sit_and_relax = false;
  double smoothness = 1.0;  // λ of the Sit & Relax fit
};

// The scene's own body placement and support, kept when the design starts
// from a baseline's support instead.
struct SceneSupport {
  rest::RestBody body;
  SurfaceMesh support;
  std::string source;
};

// A Sit & Relax start as fitted (design/start.hpp).
struct SitAndRelaxStart {
  SurfaceMesh support;              // the scene's support with its design region fitted
  double scale = 1.0;               // SitAndRelaxFit::scale
  double zeta_negative_image = 0.0; // ζ on the negative image the frozen pressures come from
};

// One body of a cohort scene, as its own rest scene (its body and core from
// its entry, everything else the cohort's).
struct CohortMember {
  std::string name;
  rest::RestScene rest;
  std::string source;  // the scene file its body came from, or "inline"
};

struct DesignScene {
  rest::RestScene rest;  // with `design.start`, the start baseline's body and support; a cohort's first body
  std::string start;     // the baseline the design starts from; empty: the scene's support
  // A Sit & Relax start is fitted to solved equilibria, after the scene is
  // read (fit_sit_and_relax_start): until then `rest` holds the scene's own
  // support and this the baseline to fit; then start_fit holds the fit.
  std::optional<Baseline> start_to_fit;
  std::optional<SitAndRelaxStart> start_fit;
  double start_lift = 0.0;  // how far the body was lifted clear of the start's support [m]
  std::optional<SceneSupport> scene_support;  // set with `start`
  std::vector<Baseline> baselines;
  std::vector<int> design_vertices;  // rows of rest.support.V
  DesignOptions options;
  std::string region;                // how the design vertices were chosen, for the summary
  // A cohort scene's bodies, in its order (empty: one body, `rest`);
  // options.cohort holds its objective.
  std::vector<CohortMember> cohort;
  // "single_designs": also shape each body's own support with the same
  // settings, the price of one support for all (design/cohort_output.hpp).
  bool single_designs = false;
  // "baseline": the negative image of the average body, scored beside the
  // cohort's support (design/average_impression.hpp); false: none.
  std::optional<AverageImpressionOptions> cohort_baseline;
  // "start": "baseline": the cohort's design begins on that baseline (and
  // each body's own design on its own negative image); every figure is
  // still against the scene's support.
  bool cohort_start_on_baseline = false;
};

// Makes a baseline's support, with the body as placed for it, where the
// design begins (s.start names the baseline; the scene's own support is kept
// in s.scene_support by the caller): failures name it, and the body is lifted
// clear where a skin vertex starts inside it, as the baseline's own score
// lifts it (s.start_lift, logged).
void begin_on_start(DesignScene& s, const rest::RestBody& body, const SurfaceMesh& support, const std::string& source);

// A baseline's or a cohort body's name as it appears in file names
// (baseline_<slug>.obj, bodies/<slug>/, …):
// every character other than a letter or digit becomes '_'.
std::string baseline_slug(const std::string& name);

// Throws palpa::Error (Input) naming the file and field; a region holding no
// support vertex is refused, and so are two baselines whose files would be
// the same (names equal after baseline_slug). Without `baselines` the baselines' entries are
// checked but their supports are not built (a negative image is a mesh
// generation of its own) and none is returned, but the one named by
// `design.start` is built (it is where the design begins).
DesignScene read_design_scene(const std::filesystem::path& path, bool baselines = true);
// The same from a scene already parsed; `path` names it in messages and is
// what relative paths in it are relative to (its folder).
DesignScene read_design_scene(const Json& doc, const std::filesystem::path& path, bool baselines = true);

// The support vertices facing `up` (outward normal within `angle` [rad] of
// it) and inside the box [lo, hi] [m]. Normals: area-weighted, outward (an
// inward-wound mesh is read as flipped).
std::vector<int> facing_vertices(const SurfaceMesh& support, const Eigen::Vector3d& up, double angle,
                                 const Eigen::Vector3d& lo, const Eigen::Vector3d& hi);

}  // namespace palpa::design
