// SPDX-License-Identifier: AGPL-3.0-or-later
// Benchmark of the axisymmetric punch-indentation simulator (palpa::axisym).
// Prints one JSON line per figure (see BENCHMARKS.md).
//
// Problem: a rigid flat punch of radius a = 3 mm on a layer D = 10 mm thick on
// a rigid base, neo-hookean-isochoric tissue with the small-strain constants
// E = 10 kPa, ν = 0.45 (C10 = μ/2, D1 = 2/K), stick contact under the punch.
//
//  1. curve_default_mesh: 20-step curves at mesh level 2 with the default
//     element (F-bar), to d = 2 mm and to d = a = 3 mm. Figure: wall time of
//     PokeSimulator::run(), Newton iterations, numeric factorizations.
//     Reference: one CHOLMOD numeric factorization of the true Hessian at the
//     final depth (analysed once, median of repetitions); ratio "curve / one
//     factorization". Accuracy context: the force at the final depth and the
//     last Newton residual.
//  2. CalculiX side by side (when `ccx` is on PATH; otherwise one line saying
//     it was skipped). The input deck is written here from palpa's mesh: CAX4
//     elements on palpa's nodes (x = r, y = z), *HYPERELASTIC, NEO HOOKE with
//     the same C10 and D1, the face nodes r <= a prescribed (u_y = −d,
//     u_x = 0), base fixed, axis u_x = 0, *STEP, NLGEOM with automatic
//     increments of at most one depth step and *TIME POINTS on the schedule,
//     *NODE PRINT of the RF totals of the face nodes. CalculiX expands every
//     CAX4 into one C3D8 brick over a 2° wedge (its manual, "Four-node
//     axisymmetric element") and its *NODE PRINT forces are those of that
//     segment: full circle = 180 × printed total.
//     - ccx_force_convention: that factor, measured in the same run on a
//       uniaxial cylinder of two CAX4.
//     - ccx_comparison: the 2 mm and 3 mm schedules of (1), ccx with
//       OMP_NUM_THREADS unset, = 1 and = the number of cores; palpa with the
//       Standard element (full integration, like CAX4) with the punch acting
//       only through the face nodes (exactly CalculiX's model), with its punch
//       contact, and as shipped (F-bar), on all cores and on one thread.
//       Forces at every depth both reached, relative differences, wall
//       times and the ratios palpa / ccx.
//     - convergence_limit: 20 steps to 5 mm for a = 1, 3, 5 mm: the deepest
//       depth each solver converged to, and det F of the states CalculiX
//       printed, at its own 2×2 Gauss points, at palpa's 3×3 points and at
//       the element corners (palpa rejects any state with det F <= 0 at one
//       of its Gauss points).
//  3. scaling: the 2 mm curve in 10 steps at mesh levels 1–4 (F-bar): time,
//     DOFs, Newton iterations, factorizations, force; then the least-squares
//     exponent of time against DOFs on log–log axes.
//
//  4. accuracy: error against time of the small-depth stiffness on the case
//     of Hayes et al. (1972) that the tests use (a/D = 1, ν = 0.45,
//     frictionless, neo-Hookean, d = 1e-4 a), against the analytic layer
//     stiffness of tests/axisym/layer_reference: one mesh alone and the
//     extrapolated force (each level with the one below) at levels 1–5, and
//     for each variant the cheapest level within 1% and within 0.3%, with the
//     ratio of those times. With ccx on PATH, CalculiX CAX8 too: palpa's
//     meshes at levels 0–4 (--quick: 0–2) with a mid-side node on every edge,
//     the same material and boundary conditions, wall time of the ccx process
//     (median of 3; level 4: one run).
//
// Figures 1 and 4 use the default (extrapolated) force; the CalculiX
// comparison and the scaling figure use one mesh (extrapolation off), so that
// both solvers solve the same mesh and the times scale with its size.
//
//  5. foam: the bundled foam example's 4.05 mm curve with its true material
//     (Newton iterations and factorizations per step), and how deep its
//     1.03 mm punch gets.
//
// Options: --quick (levels 1–2 only, no CalculiX; accuracy to level 3), --keep
// (keep the CalculiX working folders and print where they are), --only
// curves|ccx|scaling|accuracy|foam.

#include <sys/resource.h>
#include <unistd.h>

#include <Eigen/Core>
#include <Eigen/LU>
#include <Eigen/SparseCore>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <tbb/global_control.h>
#include <thread>
#include <vector>

#include "bench_util.hpp"
#include "palpa/axisym/element.hpp"
#include "palpa/axisym/poke.hpp"
#include "palpa/core/error.hpp"
#include "palpa/material/material_file.hpp"
#include "palpa/material/models.hpp"
#include "palpa/solve/sparse_cholesky.hpp"
#include "axisym/layer_reference.hpp"

namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using palpa::axisym::AxisymMesh;
using palpa::axisym::ElementFormulation;
using palpa::axisym::PokeCurve;
using palpa::axisym::PokeModel;
using palpa::axisym::PokeOptions;
using palpa::axisym::PokeSample;
using palpa::axisym::PokeSetup;
using palpa::axisym::PokeSimulator;
using palpa::axisym::PunchContact;
using palpa::material::IsochoricInvariant;
using SpMat = Eigen::SparseMatrix<double>;
using Clock = std::chrono::steady_clock;

constexpr double kPunchRadius = 3e-3;  // a [m]
constexpr double kThickness = 10e-3;   // D [m]
constexpr double kYoung = 10e3;        // E [Pa]
constexpr double kPoisson = 0.45;

// Timing: bench::median_seconds, one measurement for runs over 1.5 s.
constexpr double kLongRun = 1.5;
using palpa::bench::median_seconds;
using palpa::bench::seconds_since;

// v rounded to n significant digits (keeps the JSON lines readable).
double sig(double v, int n) {
  if (!std::isfinite(v) || v == 0.0) return v;
  return std::stod(fmt::format("{:.{}g}", v, n));
}

// Least-squares slope of log(y) against log(x).
double fitted_exponent(const std::vector<double>& x, const std::vector<double>& y) {
  const auto n = static_cast<double>(x.size());
  double sx = 0.0;
  double sy = 0.0;
  double sxx = 0.0;
  double sxy = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double lx = std::log(x[i]);
    const double ly = std::log(y[i]);
    sx += lx;
    sy += ly;
    sxx += lx * lx;
    sxy += lx * ly;
  }
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

// Peak resident memory of this process so far [MiB].
double peak_rss_mib() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_maxrss) / 1024.0;
}

// Peak resident memory of the finished child processes so far [MiB].
double peak_child_rss_mib() {
  rusage u{};
  getrusage(RUSAGE_CHILDREN, &u);
  return static_cast<double>(u.ru_maxrss) / 1024.0;
}

struct Tissue {
  double mu = 0.0;   // [Pa]
  double bulk = 0.0; // [Pa]
  double c10 = 0.0;  // [Pa]
  double d1 = 0.0;   // [1/Pa]
};

Tissue tissue() {
  Tissue t;
  t.mu = kYoung / (2.0 * (1.0 + kPoisson));
  t.bulk = kYoung / (3.0 * (1.0 - 2.0 * kPoisson));
  t.c10 = 0.5 * t.mu;
  t.d1 = 2.0 / t.bulk;
  return t;
}

IsochoricInvariant tissue_material() {
  const Tissue t = tissue();
  return IsochoricInvariant::neo_hookean(t.c10, t.d1);
}

PokeSetup make_setup(int level, ElementFormulation element, double punch_radius = kPunchRadius) {
  PokeSetup s;
  s.geometry.punch_radius = punch_radius;
  s.geometry.thickness = kThickness;
  s.mesh_level = level;
  s.contact = PunchContact::Stick;
  s.element = element;
  return s;
}

const char* element_name(ElementFormulation e) {
  return e == ElementFormulation::FBar ? "fbar" : "standard";
}

json problem_json(int level, ElementFormulation element, double depth, int steps,
                  double punch_radius = kPunchRadius) {
  const Tissue t = tissue();
  return {{"punch_radius_mm", punch_radius * 1e3},
          {"thickness_mm", kThickness * 1e3},
          {"depth_mm", depth * 1e3},
          {"steps", steps},
          {"mesh_level", level},
          {"extrapolated", false},
          {"element", element_name(element)},
          {"contact", "stick"},
          {"model", "neo-hookean-isochoric"},
          {"E_Pa", kYoung},
          {"nu", kPoisson},
          {"C10_Pa", t.c10},
          {"D1_per_Pa", t.d1}};
}

// ------------------------------------------------------------ palpa curves

struct CurveResult {
  bool ok = false;             // the whole schedule converged
  std::string error;           // why not, otherwise
  PokeCurve curve;             // when ok
  std::vector<PokeSample> samples;  // every depth that converged (also when not ok)
  double seconds = 0.0;        // run() wall time, to the end or to the failure (median if repeated)
  double setup_seconds = 0.0;  // model construction (mesh, geometry, pattern)
  Eigen::Index dofs = 0;
  Eigen::VectorXd x_final;     // free DOFs at the deepest converged depth
  int max_contact_nodes = 0;
  double final_residual = 0.0;

  double deepest_depth() const { return samples.empty() ? 0.0 : samples.back().depth; }
};

// Runs the curve (repeated on fresh simulators when short; `repeat` false:
// once) and keeps the samples and final free DOFs of the last run. A depth
// that does not converge ends the run: ok is false, error says why.
CurveResult run_curve(const PokeSetup& setup, double depth, int steps, bool repeat) {
  const IsochoricInvariant material = tissue_material();
  CurveResult r;
  PokeOptions options;
  options.max_depth = depth;
  options.steps = steps;
  std::unique_ptr<PokeSimulator> sim;
  const auto make = [&] {
    const auto t0 = Clock::now();
    sim = std::make_unique<PokeSimulator>(material, setup);
    r.setup_seconds = seconds_since(t0);
    r.samples.clear();
    r.max_contact_nodes = 0;
  };
  const auto work = [&] {
    try {
      r.curve = sim->run(options, [&](const PokeModel&, const Eigen::VectorXd& x, const PokeSample& s) {
        r.x_final = x;
        r.samples.push_back(s);
        r.max_contact_nodes = std::max(r.max_contact_nodes, s.contact_nodes);
        r.final_residual = s.residual;
      });
      r.ok = true;
      r.error.clear();
    } catch (const palpa::Error& e) {
      r.ok = false;
      r.error = e.what();
    }
  };
  if (repeat) {
    r.seconds = median_seconds(make, work, kLongRun);
  } else {
    make();
    const auto t0 = Clock::now();
    work();
    r.seconds = seconds_since(t0);
  }
  r.dofs = sim->model().num_dofs();
  return r;
}

struct FactorReference {
  double seconds = 0.0;
  Eigen::Index nnz = 0;
  bool supernodal = false;
  double factor_nonzeros = 0.0;
  std::string status;
};

// One CHOLMOD numeric factorization of the model's true Hessian at x
// (analysed once; median of repeated factorizations).
FactorReference factorization_reference(const PokeSetup& setup, double depth, const Eigen::VectorXd& x) {
  const IsochoricInvariant material = tissue_material();
  PokeModel model(material, setup);
  model.set_depth(depth);
  model.set_true_hessian(true);
  SpMat H;
  model.hessian(x, H);
  palpa::SparseCholesky chol;
  FactorReference f;
  (void)chol.analyze(H);
  palpa::FactorStatus status = palpa::FactorStatus::Ok;
  f.seconds = median_seconds([] {}, [&] { status = chol.factorize(H); }, kLongRun);
  f.status = std::string(palpa::to_string(status));
  f.nnz = H.nonZeros();
  f.supernodal = chol.is_supernodal();
  f.factor_nonzeros = chol.factor_nonzeros();
  return f;
}

// ------------------------------------------------------------ figure 1

void bench_default_curves() {
  const int level = 2;
  for (double depth : {2e-3, kPunchRadius}) {
    const int steps = 20;
    const PokeSetup setup = make_setup(level, ElementFormulation::FBar);
    json j = {{"bench", "poke"}, {"figure", "curve_default_mesh"}};
    j["problem"] = problem_json(level, ElementFormulation::FBar, depth, steps);
    j["problem"]["extrapolated"] = palpa::axisym::extrapolates(setup);
    const CurveResult r = run_curve(setup, depth, steps, true);
    j["dofs"] = r.dofs;
    if (!r.ok) {
      j["error"] = r.error;
      palpa::bench::emit(j);
      continue;
    }
    const FactorReference f = factorization_reference(setup, depth, r.x_final);
    const PokeSample& last = r.curve.samples.back();
    j["seconds"] = r.seconds;
    j["setup_seconds"] = r.setup_seconds;
    j["newton_iterations"] = r.curve.newton_iterations;
    j["factorizations"] = r.curve.factorizations;
    j["analyses"] = r.curve.analyses;
    j["step_cuts"] = [&] {
      int cuts = 0;
      for (std::size_t k = 1; k < r.curve.samples.size(); ++k) cuts += r.curve.samples[k].substeps - 1;
      return cuts;
    }();
    j["reference"] = "one CHOLMOD numeric factorization of the true Hessian at the final depth";
    j["reference_seconds"] = f.seconds;
    j["reference_status"] = f.status;
    j["reference_supernodal"] = f.supernodal;
    j["hessian_nonzeros_lower"] = f.nnz;
    j["factor_nonzeros"] = f.factor_nonzeros;
    j["ratio_curve_to_factorization"] = r.seconds / f.seconds;
    j["curve_time_per_factorization_done_in_reference_units"] =
        r.seconds / f.seconds / static_cast<double>(std::max<std::int64_t>(1, r.curve.factorizations));
    j["force_final_N"] = last.force;
    j["residual_final_N"] = last.residual;
    j["min_jacobian_final"] = last.min_jacobian;
    j["contact_nodes_final"] = last.contact_nodes;
    j["max_penetration_final_um"] = last.max_penetration * 1e6;
    j["peak_rss_mib"] = peak_rss_mib();
    palpa::bench::emit(j);
    std::fflush(stdout);
  }
}

// ------------------------------------------------------------ figure 5

// The bundled foam example's true material (examples/fit/foam): the curve a
// fit simulates most, 4.05 mm punch to 4 mm in 20 steps, frictionless, at the
// default level, one mesh and extrapolated: Newton iterations and
// factorizations per depth step and mesh, seconds. And how deep the smallest
// punch (1.03 mm, to 4 mm) gets at levels 1–2 before its rim cells are
// crushed.
void bench_foam() {
  const fs::path file = fs::path(PALPA_EXAMPLES_DIR) / "fit" / "foam" / "true-material.json";
  const auto m = palpa::material::read_material_file(file).material;
  for (const bool extrapolate : {false, true}) {
    PokeSetup s;
    s.geometry.punch_radius = 4.05e-3;
    s.geometry.thickness = 10e-3;
    s.geometry.outer_radius = 50e-3;  // the sample's 100 mm width
    s.contact = PunchContact::Frictionless;
    s.extrapolate = extrapolate;
    PokeOptions o;
    o.max_depth = 4e-3;
    o.steps = 20;
    PokeCurve c;
    std::unique_ptr<PokeSimulator> sim;
    const double secs = median_seconds([&] { sim = std::make_unique<PokeSimulator>(*m, s); },
                                       [&] { c = sim->run(o); }, kLongRun);
    const double mesh_steps = o.steps * (extrapolate ? 2.0 : 1.0);
    palpa::bench::emit({{"bench", "poke"},
                        {"figure", "foam_curve"},
                        {"material", file.string()},
                        {"variant", extrapolate ? "extrapolated (levels 2 and 1)" : "one mesh (level 2)"},
                        {"force_final_N", sig(c.samples.back().force, 6)},
                        {"newton_iterations", c.newton_iterations},
                        {"factorizations", c.factorizations},
                        {"iterations_per_step_and_mesh", sig(c.newton_iterations / mesh_steps, 3)},
                        {"factorizations_per_step_and_mesh", sig(static_cast<double>(c.factorizations) / mesh_steps, 3)},
                        {"seconds", sig(secs, 3)}});
    std::fflush(stdout);
  }
  for (int level : {1, 2}) {
    PokeSetup s;
    s.geometry.punch_radius = 1.03e-3;
    s.geometry.thickness = 10e-3;
    s.geometry.outer_radius = 50e-3;
    s.contact = PunchContact::Frictionless;
    s.mesh_level = level;
    s.extrapolate = false;
    PokeOptions o;
    o.max_depth = 4e-3;
    o.steps = 20;
    PokeSimulator sim(*m, s);
    double reached = 0.0;
    const auto t0 = Clock::now();
    std::string error;
    try {
      sim.run(o, [&](const PokeModel&, const Eigen::VectorXd&, const PokeSample& x) { reached = x.depth; });
    } catch (const palpa::Error& e) {
      error = e.problem();
    }
    palpa::bench::emit({{"bench", "poke"},
                        {"figure", "foam_small_punch_reach"},
                        {"punch_radius_mm", 1.03},
                        {"level", level},
                        {"reached_mm", sig(reached * 1e3, 4)},
                        {"planned_mm", 4.0},
                        {"seconds", sig(seconds_since(t0), 3)},
                        {"stopped", error}});
    std::fflush(stdout);
  }
}

// ------------------------------------------------------------ CalculiX

// Is `name` an executable file in one of the folders of PATH?
std::optional<fs::path> find_on_path(const std::string& name) {
  const char* path = std::getenv("PATH");
  if (path == nullptr) return std::nullopt;
  std::stringstream ss(path);
  std::string dir;
  while (std::getline(ss, dir, ':')) {
    if (dir.empty()) continue;
    const fs::path p = fs::path(dir) / name;
    std::error_code ec;
    if (access(p.c_str(), X_OK) == 0 && fs::is_regular_file(p, ec)) return p;
  }
  return std::nullopt;
}

// A fresh, empty folder under the system's temporary folder.
fs::path make_work_folder(const std::string& tag) {
  std::string pattern = (fs::temp_directory_path() / ("palpa_bench_poke_" + tag + "_XXXXXX")).string();
  std::vector<char> buf(pattern.begin(), pattern.end());
  buf.push_back('\0');
  if (mkdtemp(buf.data()) == nullptr) throw std::runtime_error("cannot create a temporary folder");
  return fs::path(buf.data());
}

std::string read_text(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Units in the deck: mm, N, MPa (= N/mm²), so forces come out in N.
constexpr double kMm = 1e3;     // m -> mm
constexpr double kMpa = 1e-6;   // Pa -> MPa

void write_node_set(std::ostringstream& out, const std::string& name, const std::vector<int>& nodes) {
  out << "*NSET, NSET=" << name << "\n";
  for (std::size_t k = 0; k < nodes.size(); ++k) {
    out << nodes[k] + 1 << (k + 1 == nodes.size() || k % 12 == 11 ? "\n" : ", ");
  }
}

// A number for a deck line: CalculiX reads fields of at most 20 characters
// and lines of at most 132.
std::string num(double v) { return fmt::format("{:.10g}", v); }

// "*NODE, NSET=NALL" and palpa's nodes in mm: palpa node i is CalculiX node i + 1.
void write_mesh_nodes(std::ostringstream& out, const AxisymMesh& mesh) {
  out << "*NODE, NSET=NALL\n";
  for (Eigen::Index n = 0; n < mesh.num_nodes(); ++n) {
    out << n + 1 << ", " << num(mesh.nodes(n, 0) * kMm) << ", " << num(mesh.nodes(n, 1) * kMm) << "\n";
  }
}

// The CalculiX input deck of the prescribed-node punch on palpa's mesh:
// palpa node i is CalculiX node i + 1, element e is element e + 1.
// With `print_displacements`, the nodal displacements of every node are
// printed too (only where they are inspected: printing costs CalculiX time).
std::string ccx_deck(const AxisymMesh& mesh, const std::vector<int>& face_nodes, double depth, int steps,
                     bool print_displacements = false) {
  const Tissue t = tissue();
  std::ostringstream out;
  out << "** palpa poke benchmark: flat punch on a layer, prescribed face nodes (stick)\n";
  out << "** units: mm, N, MPa; x = r, y = z (top surface y = 0)\n";
  write_mesh_nodes(out, mesh);
  out << "*ELEMENT, TYPE=CAX4, ELSET=EALL\n";
  for (Eigen::Index e = 0; e < mesh.num_elements(); ++e) {
    out << e + 1;
    for (int k = 0; k < 4; ++k) out << ", " << mesh.quads(e, k) + 1;
    out << "\n";
  }
  write_node_set(out, "BASE", mesh.base_nodes);
  write_node_set(out, "AXIS", mesh.axis_nodes);
  write_node_set(out, "PUNCH", face_nodes);
  out << "*MATERIAL, NAME=TISSUE\n";
  out << "*HYPERELASTIC, NEO HOOKE\n";
  out << num(t.c10 * kMpa) << ", " << num(t.d1 / kMpa) << "\n";
  out << "*SOLID SECTION, ELSET=EALL, MATERIAL=TISSUE\n";
  out << "*BOUNDARY\n";
  out << "BASE, 1, 2\n";
  out << "AXIS, 1, 1\n";
  out << "PUNCH, 1, 1\n";
  out << "*TIME POINTS, NAME=SCHEDULE\n";
  for (int k = 1; k <= steps; ++k) {
    out << num(static_cast<double>(k) / steps) << (k == steps || k % 6 == 0 ? "\n" : ", ");
  }
  const double inc = 1.0 / steps;
  out << "*STEP, NLGEOM, INC=100000\n";
  out << "*STATIC\n";
  // initial increment, step time, minimum increment, maximum increment
  out << num(inc) << ", 1, " << num(inc * 1e-4) << ", " << num(inc) << "\n";
  out << "*BOUNDARY\n";
  out << "PUNCH, 2, 2, " << num(-depth * kMm) << "\n";
  out << "*NODE PRINT, NSET=PUNCH, TOTALS=ONLY, TIME POINTS=SCHEDULE\n";
  out << "RF\n";
  if (print_displacements) {
    out << "*NODE PRINT, NSET=NALL, TIME POINTS=SCHEDULE\n";
    out << "U\n";
  }
  out << "*END STEP\n";
  return out.str();
}

// The CalculiX deck of the same punch with quadratic elements: every quad of
// palpa's mesh becomes a CAX8 with mid-side nodes at its edge midpoints
// (numbered after palpa's nodes), the face nodes r <= a and the mid-sides
// between two of them prescribed u_y = −d (and u_x = 0 for stick), the base
// fixed, the axis u_x = 0; one *STATIC increment (small depths).
std::string ccx_deck_cax8(const AxisymMesh& mesh, const std::vector<int>& face_nodes, double depth, bool stick,
                          const palpa::material::Material& m) {
  const auto elastic = palpa::material::small_strain_constants(m);
  const double c10 = 0.5 * elastic.mu;
  const double d1 = 2.0 / elastic.bulk();
  std::map<std::pair<int, int>, int> midside;  // sorted corner pair -> node (0-based)
  Eigen::Index next = mesh.num_nodes();
  std::vector<Eigen::Vector2d> extra;
  const auto mid = [&](int a, int b) {
    const std::pair<int, int> key(std::min(a, b), std::max(a, b));
    const auto it = midside.find(key);
    if (it != midside.end()) return it->second;
    const int id = static_cast<int>(next++);
    midside.emplace(key, id);
    extra.push_back(0.5 * (mesh.nodes.row(a) + mesh.nodes.row(b)).transpose());
    return id;
  };
  std::vector<std::array<int, 8>> elements;
  for (Eigen::Index e = 0; e < mesh.num_elements(); ++e) {
    std::array<int, 8> q{};
    for (int k = 0; k < 4; ++k) q[static_cast<std::size_t>(k)] = mesh.quads(e, k);
    for (int k = 0; k < 4; ++k) q[static_cast<std::size_t>(4 + k)] = mid(q[static_cast<std::size_t>(k)], q[static_cast<std::size_t>((k + 1) % 4)]);
    elements.push_back(q);
  }
  // A set of corner nodes with the mid-sides of the edges between two of them.
  const auto with_midsides = [&](const std::vector<int>& corners) {
    std::vector<int> out = corners;
    std::vector<char> in(static_cast<std::size_t>(mesh.num_nodes()), 0);
    for (int n : corners) in[static_cast<std::size_t>(n)] = 1;
    for (const auto& [key, id] : midside) {
      if (in[static_cast<std::size_t>(key.first)] && in[static_cast<std::size_t>(key.second)]) out.push_back(id);
    }
    return out;
  };
  std::ostringstream out;
  out << "** palpa poke benchmark: flat punch on a layer, CAX8, prescribed face nodes\n";
  out << "** units: mm, N, MPa; x = r, y = z (top surface y = 0)\n";
  write_mesh_nodes(out, mesh);
  for (std::size_t k = 0; k < extra.size(); ++k) {
    out << mesh.num_nodes() + static_cast<Eigen::Index>(k) + 1 << ", " << num(extra[k][0] * kMm) << ", "
        << num(extra[k][1] * kMm) << "\n";
  }
  out << "*ELEMENT, TYPE=CAX8, ELSET=EALL\n";
  for (std::size_t e = 0; e < elements.size(); ++e) {
    out << e + 1;
    for (int k = 0; k < 8; ++k) out << ", " << elements[e][static_cast<std::size_t>(k)] + 1;
    out << "\n";
  }
  write_node_set(out, "BASE", with_midsides(mesh.base_nodes));
  write_node_set(out, "AXIS", with_midsides(mesh.axis_nodes));
  write_node_set(out, "PUNCH", with_midsides(face_nodes));
  out << "*MATERIAL, NAME=TISSUE\n";
  out << "*HYPERELASTIC, NEO HOOKE\n";
  out << num(c10 * kMpa) << ", " << num(d1 / kMpa) << "\n";
  out << "*SOLID SECTION, ELSET=EALL, MATERIAL=TISSUE\n";
  out << "*BOUNDARY\n";
  out << "BASE, 1, 2\n";
  out << "AXIS, 1, 1\n";
  if (stick) out << "PUNCH, 1, 1\n";
  out << "*STEP, NLGEOM\n";
  out << "*STATIC\n";
  out << "*BOUNDARY\n";
  out << "PUNCH, 2, 2, " << num(-depth * kMm) << "\n";
  out << "*NODE PRINT, NSET=PUNCH, TOTALS=ONLY\n";
  out << "RF\n";
  out << "*END STEP\n";
  return out.str();
}

struct CcxRun {
  bool finished = false;   // the whole step converged
  double seconds = 0.0;    // wall time of the ccx process
  double reported_seconds = std::nan("");  // "Total CalculiX Time" of its log
  std::vector<double> times;    // step times with printed totals
  std::vector<double> force_y;  // printed total RF_y of the punch set (2° segment)
  // Printed displacements (if requested): step time and #N × 2 (u_r, u_z) [mm].
  std::vector<std::pair<double, Eigen::MatrixX2d>> displacements;
  double last_converged_time = 0.0;
  int increments = 0;           // converged increments
  int attempts_failed = 0;      // increment attempts that did not converge
  int iterations = 0;           // all equilibrium iterations (failed attempts included)
  std::string solver;           // the linear solver named in the log
  std::string threads;          // the first thread line of the log
  std::string error;            // the first *ERROR line, if any
  fs::path folder;
};

// Parses the .dat: "total force (fx,fy,fz) for set PUNCH and time  t"
// followed by a line of three numbers, and "displacements (vx,vy,vz) for set
// NALL and time  t" followed by one line per node: node, ux, uy, uz.
void parse_dat(const std::string& text, Eigen::Index num_nodes, CcxRun& run) {
  std::istringstream in(text);
  std::string line;
  const auto time_of = [](const std::string& l) {
    const auto tpos = l.rfind("time");
    return std::strtod(l.c_str() + tpos + 4, nullptr);
  };
  while (std::getline(in, line)) {
    if (line.find("total force") != std::string::npos) {
      const double time = time_of(line);
      std::string values;
      while (std::getline(in, values)) {
        if (values.find_first_not_of(" \t\r") != std::string::npos) break;
      }
      std::istringstream v(values);
      double fx = 0.0;
      double fy = 0.0;
      double fz = 0.0;
      if (v >> fx >> fy >> fz) {
        run.times.push_back(time);
        run.force_y.push_back(fy);
      }
    } else if (line.find("displacements") != std::string::npos && num_nodes > 0) {
      const double time = time_of(line);
      Eigen::MatrixX2d u = Eigen::MatrixX2d::Zero(num_nodes, 2);
      std::string row;
      int read = 0;
      while (std::getline(in, row)) {
        std::istringstream v(row);
        long node = 0;
        double ux = 0.0;
        double uy = 0.0;
        if (!(v >> node >> ux >> uy)) {
          if (read > 0) break;  // the blank line after the block
          continue;             // the blank line before it
        }
        if (node >= 1 && node <= num_nodes) u.row(node - 1) << ux, uy;
        ++read;
      }
      if (read == num_nodes) run.displacements.emplace_back(time, u);
    }
  }
}

// .sta: one line per increment attempt, STEP INC ATT ITRS TOT-TIME STEP-TIME
// INC-TIME; an attempt that did not converge has its ATT marked "U".
void parse_sta(const std::string& text, CcxRun& run) {
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream l(line);
    int step = 0;
    int inc = 0;
    std::string att;
    int itrs = 0;
    double total = 0.0;
    double step_time = 0.0;
    if (!(l >> step >> inc >> att >> itrs >> total >> step_time)) continue;
    if (att.find('U') != std::string::npos) {
      ++run.attempts_failed;
      continue;
    }
    ++run.increments;
    run.last_converged_time = std::max(run.last_converged_time, step_time);
  }
}

// .cvg: one line per equilibrium iteration of every attempt.
void parse_cvg(const std::string& text, CcxRun& run) {
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream l(line);
    int step = 0;
    int inc = 0;
    int att = 0;
    int iter = 0;
    if (l >> step >> inc >> att >> iter) ++run.iterations;
  }
}

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r");
  const auto e = s.find_last_not_of(" \t\r");
  return b == std::string::npos ? std::string() : s.substr(b, e - b + 1);
}

void parse_log(const std::string& text, CcxRun& run) {
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    if (run.solver.empty() && line.find("solver") != std::string::npos) run.solver = trim(line);
    if (run.threads.empty() && line.find("cpu(s)") != std::string::npos) run.threads = trim(line);
    if (run.error.empty() && line.find("*ERROR") != std::string::npos) run.error = trim(line);
    const auto t = line.find("Total CalculiX Time:");
    if (t != std::string::npos) run.reported_seconds = std::strtod(line.c_str() + t + 20, nullptr);
    if (line.find("Job finished") != std::string::npos) run.finished = true;
  }
}

// Writes the deck into a fresh folder, runs ccx there and parses its output.
// omp_threads 0: OMP_NUM_THREADS unset (ccx's default). num_nodes: for
// parsing printed displacements (0: none).
CcxRun run_ccx(const fs::path& ccx, const std::string& deck, int omp_threads, const std::string& tag,
               Eigen::Index num_nodes = 0) {
  CcxRun run;
  run.folder = make_work_folder(tag);
  {
    std::ofstream f(run.folder / "poke.inp");
    f << deck;
  }
  const std::string env = omp_threads > 0 ? "OMP_NUM_THREADS=" + std::to_string(omp_threads)
                                          : std::string("-u OMP_NUM_THREADS");
  const std::string cmd = "cd '" + run.folder.string() + "' && env " + env + " '" + ccx.string() +
                          "' -i poke > ccx.log 2>&1";
  const auto t0 = Clock::now();
  const int rc = std::system(cmd.c_str());
  run.seconds = seconds_since(t0);
  parse_log(read_text(run.folder / "ccx.log"), run);
  parse_dat(read_text(run.folder / "poke.dat"), num_nodes, run);
  parse_sta(read_text(run.folder / "poke.sta"), run);
  parse_cvg(read_text(run.folder / "poke.cvg"), run);
  if (rc != 0 && run.error.empty()) run.error = "ccx exited with status " + std::to_string(rc);
  run.finished = run.finished && rc == 0 && run.last_converged_time > 1.0 - 1e-9;
  return run;
}

// `reps` runs of the same deck; returns the one with the median wall time
// (the others' folders are removed).
CcxRun run_ccx_median(const fs::path& ccx, const std::string& deck, int omp_threads, const std::string& tag,
                      int reps) {
  std::vector<CcxRun> runs;
  for (int k = 0; k < reps; ++k) runs.push_back(run_ccx(ccx, deck, omp_threads, tag));
  std::sort(runs.begin(), runs.end(), [](const CcxRun& a, const CcxRun& b) { return a.seconds < b.seconds; });
  const std::size_t mid = runs.size() / 2;
  for (std::size_t k = 0; k < runs.size(); ++k) {
    if (k != mid) fs::remove_all(runs[k].folder);
  }
  return runs[mid];
}

// The 2° convention, checked in the same run: a cylinder of radius 1 and
// height 1 (two CAX4, E = 1000, ν = 0, axial strain −0.001, lateral faces
// free) carries σ π R² = π in the full circle. Returns printed total / π.
double run_ccx_unit_check(const fs::path& ccx, bool keep) {
  std::ostringstream d;
  d << "*NODE, NSET=NALL\n1, 0, 0\n2, 0.5, 0\n3, 1, 0\n4, 0, 1\n5, 0.5, 1\n6, 1, 1\n";
  d << "*ELEMENT, TYPE=CAX4, ELSET=EALL\n1, 1, 2, 5, 4\n2, 2, 3, 6, 5\n";
  d << "*NSET, NSET=BASE\n1, 2, 3\n*NSET, NSET=TOP\n4, 5, 6\n";
  d << "*MATERIAL, NAME=M\n*ELASTIC\n1000.0, 0.0\n*SOLID SECTION, ELSET=EALL, MATERIAL=M\n";
  d << "*BOUNDARY\nBASE, 2, 2\n1, 1, 1\n4, 1, 1\n";
  d << "*STEP\n*STATIC\n*BOUNDARY\nTOP, 2, 2, -0.001\n";
  d << "*NODE PRINT, NSET=TOP, TOTALS=ONLY\nRF\n*END STEP\n";
  const CcxRun r = run_ccx(ccx, d.str(), 1, "unit");
  if (!keep) fs::remove_all(r.folder);
  if (r.force_y.empty()) return std::nan("");
  return -r.force_y.back() / M_PI;
}

constexpr double kCcxSegment = 180.0;  // full circle / the 2° segment CalculiX prints

// det F of a bilinear axisymmetric quad at (ξ, η) ∈ [−1, 1]²: rest (r, z) and
// displacements (u_r, u_z) of its four nodes as columns. det F = det F2 · F_θθ,
// F_θθ = 1 + u_r/r (→ F_rr on the axis).
double det_f(const Eigen::Matrix<double, 2, 4>& rest, const Eigen::Matrix<double, 2, 4>& u, double xi, double eta) {
  const Eigen::Vector4d n(0.25 * (1 - xi) * (1 - eta), 0.25 * (1 + xi) * (1 - eta), 0.25 * (1 + xi) * (1 + eta),
                          0.25 * (1 - xi) * (1 + eta));
  Eigen::Matrix<double, 4, 2> dn;
  dn << -0.25 * (1 - eta), -0.25 * (1 - xi), 0.25 * (1 - eta), -0.25 * (1 + xi), 0.25 * (1 + eta),
      0.25 * (1 + xi), -0.25 * (1 + eta), 0.25 * (1 - xi);
  const Eigen::Matrix2d jac = rest * dn;
  const Eigen::Matrix<double, 4, 2> dndx = dn * jac.inverse();
  const Eigen::Matrix2d f2 = Eigen::Matrix2d::Identity() + u * dndx;
  const double r = rest.row(0).dot(n);
  const double hoop = r > 1e-12 * rest.row(0).cwiseAbs().maxCoeff() ? 1.0 + u.row(0).dot(n) / r : f2(0, 0);
  return f2.determinant() * hoop;
}

struct DetFSummary {
  double gauss_2x2 = 0.0;  // smallest det F at the 2×2 Gauss points (CalculiX's C3D8 in the (r, z) plane)
  double gauss_3x3 = 0.0;  // … at palpa's 3×3 Gauss points
  double corners = 0.0;    // … at the element corners
  int elements_inverted_2x2 = 0;  // elements with det F <= 0 at one of CalculiX's points
  int elements_inverted_3x3 = 0;  // … at one of palpa's points
};

// Smallest det F over all elements for nodal displacements u (#N × 2, [m]).
DetFSummary det_f_summary(const AxisymMesh& mesh, const Eigen::MatrixX2d& u) {
  const double g2 = 1.0 / std::sqrt(3.0);
  const double g3 = std::sqrt(0.6);
  DetFSummary s;
  s.gauss_2x2 = s.gauss_3x3 = s.corners = std::numeric_limits<double>::infinity();
  for (Eigen::Index e = 0; e < mesh.num_elements(); ++e) {
    Eigen::Matrix<double, 2, 4> rest;
    Eigen::Matrix<double, 2, 4> ue;
    for (int k = 0; k < 4; ++k) {
      rest.col(k) = mesh.nodes.row(mesh.quads(e, k)).transpose();
      ue.col(k) = u.row(mesh.quads(e, k)).transpose();
    }
    double m2 = std::numeric_limits<double>::infinity();
    double m3 = std::numeric_limits<double>::infinity();
    for (double xi : {-1.0, 1.0})
      for (double eta : {-1.0, 1.0}) {
        s.corners = std::min(s.corners, det_f(rest, ue, xi, eta));
        m2 = std::min(m2, det_f(rest, ue, xi * g2, eta * g2));
      }
    s.gauss_2x2 = std::min(s.gauss_2x2, m2);
    if (m2 <= 0.0) ++s.elements_inverted_2x2;
    for (double xi : {-g3, 0.0, g3})
      for (double eta : {-g3, 0.0, g3}) m3 = std::min(m3, det_f(rest, ue, xi, eta));
    s.gauss_3x3 = std::min(s.gauss_3x3, m3);
    if (m3 <= 0.0) ++s.elements_inverted_3x3;
  }
  return s;
}

json ccx_run_json(const CcxRun& r, double depth) {
  json j = {{"wall_seconds", r.seconds},
            {"log_total_calculix_time_s", std::isfinite(r.reported_seconds) ? json(r.reported_seconds) : json(nullptr)},
            {"finished_schedule", r.finished},
            {"deepest_converged_depth_mm", r.last_converged_time * depth * 1e3},
            {"converged_increments", r.increments},
            {"failed_attempts", r.attempts_failed},
            {"equilibrium_iterations", r.iterations},
            {"log_solver", r.solver},
            {"log_threads", r.threads}};
  if (!r.error.empty()) j["log_error"] = r.error;
  return j;
}

// palpa on the CalculiX problem: Standard element, stick, the same mesh. With
// `contact` false the rigid punch acts only through the prescribed face nodes
// (the penalty is made negligible), which is exactly CalculiX's model; with
// `contact` true the punch also keeps the free surface out (palpa's default).
PokeSetup ccx_like_setup(int level, bool contact, double punch_radius = kPunchRadius) {
  PokeSetup s = make_setup(level, ElementFormulation::Standard, punch_radius);
  s.extrapolate = false;  // the same mesh as CalculiX's
  if (!contact) s.penalty_factor = 1e-12;
  return s;
}

struct PalpaRuns {
  CurveResult all;  // all cores
  CurveResult one;  // one thread
};

PalpaRuns run_palpa_both(const PokeSetup& setup, double depth, int steps) {
  PalpaRuns r;
  r.all = run_curve(setup, depth, steps, true);
  {
    const tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    r.one = run_curve(setup, depth, steps, true);
  }
  return r;
}

json palpa_run_json(const CurveResult& r, const CurveResult* one_thread) {
  json j = {{"finished_schedule", r.ok}, {"deepest_schedule_depth_mm", r.deepest_depth() * 1e3}};
  if (!r.ok) j["error"] = r.error;
  double max_pen = 0.0;
  int iterations = 0;
  for (const PokeSample& s : r.samples) {
    max_pen = std::max(max_pen, s.max_penetration);
    iterations += s.newton_iterations;
  }
  j["seconds"] = r.seconds;
  if (one_thread != nullptr) j["seconds_1_thread"] = one_thread->seconds;
  j["newton_iterations"] = iterations;
  if (r.ok) j["factorizations"] = r.curve.factorizations;
  j["max_contact_nodes"] = r.max_contact_nodes;
  j["max_penetration_into_punch_um"] = max_pen * 1e6;
  if (!r.samples.empty()) j["min_jacobian_deepest"] = r.samples.back().min_jacobian;
  return j;
}

// Forces at the depths both reached: palpa's samples against CalculiX's
// printed totals (full circle = −180 × RF_y).
json force_table(const std::vector<PokeSample>& samples, const CcxRun& ccx, double depth, double& max_abs_rel) {
  json t = {{"depth_mm", json::array()},
            {"palpa_N", json::array()},
            {"ccx_N", json::array()},
            {"rel_diff", json::array()},
            {"palpa_nodes_in_punch", json::array()}};
  max_abs_rel = 0.0;
  for (const PokeSample& s : samples) {
    for (std::size_t i = 0; i < ccx.times.size(); ++i) {
      if (std::abs(ccx.times[i] * depth - s.depth) > 1e-6 * depth) continue;
      const double f_ccx = -kCcxSegment * ccx.force_y[i];
      const double rel = (s.force - f_ccx) / f_ccx;
      t["depth_mm"].push_back(sig(s.depth * 1e3, 6));
      t["palpa_N"].push_back(sig(s.force, 7));
      t["ccx_N"].push_back(sig(f_ccx, 7));
      t["rel_diff"].push_back(sig(rel, 3));
      t["palpa_nodes_in_punch"].push_back(s.contact_nodes);
      max_abs_rel = std::max(max_abs_rel, std::abs(rel));
      break;
    }
  }
  return t;
}

// The deepest sampled depth up to which no surface node had reached the punch.
double contact_free_depth(const std::vector<PokeSample>& samples) {
  double d = 0.0;
  for (const PokeSample& s : samples) {
    if (s.contact_nodes > 0) break;
    d = s.depth;
  }
  return d;
}

void bench_ccx(bool keep) {
  const auto ccx = find_on_path("ccx");
  if (!ccx) {
    palpa::bench::emit({{"bench", "poke"},
                        {"figure", "ccx_comparison"},
                        {"skipped", true},
                        {"reason", "ccx (CalculiX, Debian package calculix-ccx) is not on PATH"}});
    return;
  }
  const double unit_ratio = run_ccx_unit_check(*ccx, keep);
  palpa::bench::emit(
      {{"bench", "poke"},
       {"figure", "ccx_force_convention"},
       {"check", "CAX4 cylinder R = 1, H = 1, E = 1000, nu = 0, strain -0.001: printed total RF_y / (sigma pi R^2)"},
       {"printed_over_full_circle", unit_ratio},
       {"per_radian_would_be", 1.0 / (2.0 * M_PI)},
       {"two_degree_segment_would_be", 1.0 / kCcxSegment},
       {"printed_times_180_over_full_circle", unit_ratio * kCcxSegment},
       {"chord_factor_sin2deg_over_2deg", std::sin(M_PI / 90.0) / (M_PI / 90.0)},
       {"conversion", "full-circle force = 180 x printed total: CalculiX expands each CAX4 into a C3D8 over a "
                      "2 degree wedge and prints that segment's forces (not per radian); the wedge's straight "
                      "chords make it sin(2 deg)/(2 deg) = 0.99980 of the exact ring"}});
  std::fflush(stdout);

  const int level = 2;
  const int steps = 20;
  const int hw = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  const IsochoricInvariant material = tissue_material();

  // The schedules of the default curves: 20 steps to 2 mm and to d = a.
  // Timings on the 2 mm schedule are medians of three CalculiX runs.
  for (double depth : {2e-3, kPunchRadius}) {
    const int reps = depth < 2.5e-3 ? 3 : 1;
    const PokeSetup exact = ccx_like_setup(level, false);
    const PokeModel model(material, exact);
    const std::string deck = ccx_deck(model.mesh(), model.face_nodes(), depth, steps);
    const std::string tag = fmt::format("d{}um", static_cast<int>(std::lround(depth * 1e6)));

    const PalpaRuns same = run_palpa_both(exact, depth, steps);
    const PalpaRuns with_contact = run_palpa_both(ccx_like_setup(level, true), depth, steps);
    const PalpaRuns fbar = run_palpa_both(make_setup(level, ElementFormulation::FBar), depth, steps);
    const CcxRun ccx_unset = run_ccx_median(*ccx, deck, 0, tag + "_ompunset", reps);
    const CcxRun ccx_one = run_ccx_median(*ccx, deck, 1, tag + "_omp1", reps);
    std::optional<CcxRun> ccx_all;
    if (hw > 1) ccx_all = run_ccx_median(*ccx, deck, hw, tag + "_omp" + std::to_string(hw), reps);

    json j = {{"bench", "poke"}, {"figure", "ccx_comparison"}};
    j["problem"] = problem_json(level, ElementFormulation::Standard, depth, steps);
    j["problem"]["punch"] = "prescribed face nodes r <= a: u_z = -d, u_r = 0; base fixed; axis u_r = 0";
    j["mesh_nodes"] = model.mesh().num_nodes();
    j["mesh_elements"] = model.mesh().num_elements();
    j["face_nodes"] = model.face_nodes().size();
    j["palpa_dofs"] = model.num_dofs();
    j["ccx_element"] =
        "CAX4 = one layer of C3D8 (8-node brick, full 2x2x2 Gauss, no volumetric-locking treatment) over a "
        "2 degree wedge tied by MPCs; palpa Standard = bilinear quad, 3x3 Gauss, exact 2 pi r weight";
    j["ccx_increments"] = "automatic: initial = max = one depth step, cut back on failure, *TIME POINTS on the schedule";
    j["ccx_tolerance"] = "CalculiX defaults (residual 0.5% of the average force); palpa: 1e-9 of 4 mu a d";
    j["ccx_force_conversion"] = "full circle = -180 x printed total RF_y of the punch nodes";
    j["ccx_runs_per_configuration"] = reps;
    j["ccx_omp_unset"] = ccx_run_json(ccx_unset, depth);
    j["ccx_omp_1"] = ccx_run_json(ccx_one, depth);
    if (ccx_all) j["ccx_omp_" + std::to_string(hw)] = ccx_run_json(*ccx_all, depth);
    j["ccx_peak_rss_mib"] = peak_child_rss_mib();
    j["palpa_times"] = "run() wall time, median of >= 3 runs; all cores (TBB) and 1 thread";
    j["palpa_same_model"] = palpa_run_json(same.all, &same.one);
    j["palpa_same_model"]["what"] =
        "Standard element; punch only through the face nodes (contact penalty 1e-12): CalculiX's model";
    j["palpa_with_punch_contact"] = palpa_run_json(with_contact.all, &with_contact.one);
    j["palpa_with_punch_contact"]["what"] = "Standard element; free surface nodes also kept out of the punch";
    j["palpa_default_element"] = palpa_run_json(fbar.all, &fbar.one);
    j["palpa_default_element"]["what"] = "palpa as shipped: F-bar element and punch contact (a different element)";

    double max_rel = 0.0;
    j["forces_same_model"] = force_table(same.all.samples, ccx_unset, depth, max_rel);
    j["max_abs_rel_diff_same_model"] = max_rel;
    j["common_depths_same_model"] = j["forces_same_model"]["depth_mm"].size();
    j["forces_with_punch_contact"] = force_table(with_contact.all.samples, ccx_unset, depth, max_rel);
    j["max_abs_rel_diff_with_punch_contact"] = max_rel;
    j["punch_contact_free_up_to_mm"] = contact_free_depth(with_contact.all.samples) * 1e3;
    j["forces_default_element"] = force_table(fbar.all.samples, ccx_unset, depth, max_rel);
    j["max_abs_rel_diff_default_element"] = max_rel;

    const bool same_work = same.all.ok && ccx_unset.finished;
    j["timing_same_model_comparable"] = same_work;
    if (same_work) {
      j["ratio_palpa_to_ccx_as_shipped"] = same.all.seconds / ccx_unset.seconds;
      j["ratio_palpa_to_ccx_1_thread"] = same.one.seconds / ccx_one.seconds;
      if (ccx_all) j["ratio_palpa_to_ccx_all_cores"] = same.all.seconds / ccx_all->seconds;
      j["speedup_palpa_over_ccx_as_shipped"] = ccx_unset.seconds / same.all.seconds;
    } else {
      j["timing_note"] = "palpa's Standard element or CalculiX did not solve the whole schedule: no same-model ratio";
    }
    if (fbar.all.ok && ccx_unset.finished) {
      j["ratio_palpa_default_element_to_ccx_as_shipped"] = fbar.all.seconds / ccx_unset.seconds;
      j["ratio_palpa_default_element_to_ccx_1_thread"] = fbar.one.seconds / ccx_one.seconds;
    }
    if (keep) {
      j["ccx_folders"] = {ccx_unset.folder.string(), ccx_one.folder.string()};
      if (ccx_all) j["ccx_folders"].push_back(ccx_all->folder.string());
    }
    palpa::bench::emit(j);
    std::fflush(stdout);
    if (!keep) {
      fs::remove_all(ccx_unset.folder);
      fs::remove_all(ccx_one.folder);
      if (ccx_all) fs::remove_all(ccx_all->folder);
    }
  }

  // Where each stops converging: 20 steps to 5 mm (half the layer) for
  // punches of 1, 3 and 5 mm. CalculiX (OMP_NUM_THREADS unset) also prints
  // its displacements, so det F of the states it accepted is checked at its
  // own 2×2 Gauss points, at palpa's 3×3 points and at the element corners.
  for (double a : {1e-3, kPunchRadius, 5e-3}) {
    const double depth = 5e-3;
    const PokeSetup exact = ccx_like_setup(level, false, a);
    const PokeModel model(material, exact);
    const AxisymMesh& mesh = model.mesh();
    const std::string deck = ccx_deck(mesh, model.face_nodes(), depth, steps, true);
    const std::string tag = fmt::format("limit_a{}um", static_cast<int>(std::lround(a * 1e6)));
    const CcxRun run = run_ccx(*ccx, deck, 0, tag, mesh.num_nodes());
    const CurveResult same = run_curve(exact, depth, steps, false);
    const CurveResult contact = run_curve(ccx_like_setup(level, true, a), depth, steps, false);
    const CurveResult fbar = run_curve(make_setup(level, ElementFormulation::FBar, a), depth, steps, false);
    json j = {{"bench", "poke"}, {"figure", "convergence_limit"}};
    j["problem"] = problem_json(level, ElementFormulation::Standard, depth, steps, a);
    j["ccx"] = ccx_run_json(run, depth);
    j["ccx_deepest_converged_depth_mm"] = run.last_converged_time * depth * 1e3;
    j["ccx_deepest_over_punch_radius"] = run.last_converged_time * depth / a;
    json states = {{"depth_mm", json::array()},
                   {"min_det_f_ccx_2x2_points", json::array()},
                   {"min_det_f_palpa_3x3_points", json::array()},
                   {"min_det_f_corners", json::array()},
                   {"elements_inverted_at_2x2_points", json::array()},
                   {"elements_inverted_at_3x3_points", json::array()}};
    double first_inverted_2x2 = -1.0;
    double first_inverted_3x3 = -1.0;
    for (const auto& [time, u_mm] : run.displacements) {
      const DetFSummary d = det_f_summary(mesh, u_mm / kMm);
      const double at = time * depth * 1e3;
      states["depth_mm"].push_back(sig(at, 6));
      states["min_det_f_ccx_2x2_points"].push_back(sig(d.gauss_2x2, 4));
      states["min_det_f_palpa_3x3_points"].push_back(sig(d.gauss_3x3, 4));
      states["min_det_f_corners"].push_back(sig(d.corners, 4));
      states["elements_inverted_at_2x2_points"].push_back(d.elements_inverted_2x2);
      states["elements_inverted_at_3x3_points"].push_back(d.elements_inverted_3x3);
      if (first_inverted_2x2 < 0.0 && d.elements_inverted_2x2 > 0) first_inverted_2x2 = at;
      if (first_inverted_3x3 < 0.0 && d.elements_inverted_3x3 > 0) first_inverted_3x3 = at;
    }
    j["ccx_printed_states"] = states;
    const auto depth_or_null = [](double v) { return v >= 0.0 ? json(v) : json(nullptr); };
    j["ccx_first_printed_state_inverted_at_its_2x2_points_mm"] = depth_or_null(first_inverted_2x2);
    j["ccx_first_printed_state_inverted_at_3x3_points_mm"] = depth_or_null(first_inverted_3x3);
    j["palpa_standard_same_model"] = palpa_run_json(same, nullptr);
    j["palpa_standard_with_punch_contact"] = palpa_run_json(contact, nullptr);
    j["palpa_fbar_with_punch_contact"] = palpa_run_json(fbar, nullptr);
    if (fbar.ok) j["palpa_fbar_with_punch_contact"]["force_final_N"] = fbar.curve.samples.back().force;
    j["note"] =
        "palpa treats a state with det F <= 0 at any of its Gauss points as inadmissible and cuts the step; "
        "the CalculiX states printed on the schedule are checked with the same test (null: none inverted). "
        "palpa's deepest depth is the last schedule depth reached; its error names the last converged sub-step";
    if (keep) j["ccx_folder"] = run.folder.string();
    palpa::bench::emit(j);
    std::fflush(stdout);
    if (!keep) fs::remove_all(run.folder);
  }
}

// ------------------------------------------------------------ figure 3

void bench_scaling(bool quick) {
  const double depth = 2e-3;
  const int steps = 10;
  std::vector<double> dofs;
  std::vector<double> secs;
  std::vector<double> per_iteration;
  std::vector<double> forces;
  std::vector<int> levels_done;
  const std::vector<int> levels = quick ? std::vector<int>{1, 2} : std::vector<int>{1, 2, 3, 4};
  for (int level : levels) {
    PokeSetup setup = make_setup(level, ElementFormulation::FBar);
    setup.extrapolate = false;  // time against the size of one mesh
    const CurveResult r = run_curve(setup, depth, steps, level <= 2);
    json j = {{"bench", "poke"}, {"figure", "scaling_curve"}};
    j["problem"] = problem_json(level, ElementFormulation::FBar, depth, steps);
    j["dofs"] = r.dofs;
    j["runs"] = level <= 2 ? "median of >= 3" : "1";
    if (!r.ok) {
      j["error"] = r.error;
      palpa::bench::emit(j);
      continue;
    }
    const FactorReference f = factorization_reference(setup, depth, r.x_final);
    j["seconds"] = r.seconds;
    j["setup_seconds"] = r.setup_seconds;
    j["newton_iterations"] = r.curve.newton_iterations;
    j["factorizations"] = r.curve.factorizations;
    j["seconds_per_newton_iteration"] = r.seconds / r.curve.newton_iterations;
    j["reference"] = "one CHOLMOD numeric factorization of the true Hessian at the final depth";
    j["reference_seconds"] = f.seconds;
    j["reference_supernodal"] = f.supernodal;
    j["ratio_curve_to_factorization"] = r.seconds / f.seconds;
    j["force_final_N"] = r.curve.samples.back().force;
    j["residual_final_N"] = r.final_residual;
    j["peak_rss_mib"] = peak_rss_mib();
    palpa::bench::emit(j);
    std::fflush(stdout);
    levels_done.push_back(level);
    dofs.push_back(static_cast<double>(r.dofs));
    secs.push_back(r.seconds);
    per_iteration.push_back(r.seconds / r.curve.newton_iterations);
    forces.push_back(r.curve.samples.back().force);
  }
  if (dofs.size() >= 2) {
    json rel = json::array();
    for (double f : forces) rel.push_back(sig((f - forces.back()) / forces.back(), 4));
    palpa::bench::emit({{"bench", "poke"},
                        {"figure", "scaling_exponent"},
                        {"curve", "2 mm in 10 steps at every level, F-bar, stick (the whole benchmark stays "
                                  "under 6 minutes without fewer steps at the finest level)"},
                        {"levels", levels_done},
                        {"dofs", dofs},
                        {"seconds", secs},
                        {"exponent_time_vs_dofs", fitted_exponent(dofs, secs)},
                        {"exponent_time_per_newton_iteration_vs_dofs", fitted_exponent(dofs, per_iteration)},
                        {"force_2mm_N", forces},
                        {"force_rel_diff_vs_finest", rel}});
  }
}

// ------------------------------------------------------------ figure 4

struct AccuracyPoint {
  int level = 0;
  double error = 0.0;    // relative to the analytic stiffness
  double seconds = 0.0;  // run() and construction, median of repetitions
};

void bench_accuracy(bool quick) {
  constexpr double kNu = 0.45;
  const double a = kPunchRadius;
  const double thickness = a;  // a/D = 1
  const double depth = 1e-4 * a;
  const palpa::material::NeoHookean material(kYoung, kNu);
  const double reference = palpa::test::layer_stiffness(a, thickness, kYoung, kNu) * depth;
  const int top = quick ? 3 : 5;
  std::vector<std::pair<std::string, std::vector<AccuracyPoint>>> all;
  for (const bool extrapolate : {false, true}) {
    std::vector<AccuracyPoint> points;
    for (int level = 1; level <= top; ++level) {
      PokeSetup s = make_setup(level, ElementFormulation::FBar, a);
      s.geometry.thickness = thickness;
      s.contact = PunchContact::Frictionless;
      s.extrapolate = extrapolate;
      PokeOptions o;
      o.max_depth = depth;
      o.steps = 1;
      double force = 0.0;
      std::unique_ptr<PokeSimulator> sim;
      const double secs = median_seconds([] {},
                                         [&] {
                                           sim = std::make_unique<PokeSimulator>(material, s);
                                           force = sim->run(o).samples.back().force;
                                         },
                                         kLongRun);
      points.push_back({level, force / reference - 1.0, secs});
      palpa::bench::emit({{"bench", "poke"},
                          {"figure", "accuracy_point"},
                          {"variant", extrapolate ? "extrapolated" : "one mesh"},
                          {"level", level},
                          {"dofs", sim->model().num_dofs()},
                          {"error_percent", sig(100.0 * points.back().error, 3)},
                          {"seconds", sig(secs, 3)}});
      std::fflush(stdout);
    }
    all.emplace_back(extrapolate ? "extrapolated" : "one mesh", std::move(points));
  }
  // CalculiX CAX8 on the same meshes (quadratic elements on palpa's grid),
  // the same case and material; wall time of the ccx process (median of 3).
  if (const auto ccx = find_on_path("ccx")) {
    std::vector<AccuracyPoint> points;
    for (int level = 0; level <= (quick ? 2 : 4); ++level) {
      PokeSetup s = make_setup(level, ElementFormulation::Standard, a);
      s.geometry.thickness = thickness;
      s.contact = PunchContact::Frictionless;
      s.extrapolate = false;
      const PokeModel model(material, s);
      const std::string deck = ccx_deck_cax8(model.mesh(), model.face_nodes(), depth, false, material);
      const CcxRun run = run_ccx_median(*ccx, deck, 0, fmt::format("cax8-l{}", level), level < 4 ? 3 : 1);
      if (run.force_y.empty()) {
        palpa::bench::emit({{"bench", "poke"},
                            {"figure", "accuracy_point"},
                            {"variant", "ccx CAX8"},
                            {"level", level},
                            {"error", run.error.empty() ? std::string("no force printed") : run.error}});
        fs::remove_all(run.folder);
        continue;
      }
      const double force = -kCcxSegment * run.force_y.back();
      points.push_back({level, force / reference - 1.0, run.seconds});
      palpa::bench::emit({{"bench", "poke"},
                          {"figure", "accuracy_point"},
                          {"variant", "ccx CAX8"},
                          {"level", level},
                          {"elements", model.mesh().num_elements()},
                          {"error_percent", sig(100.0 * points.back().error, 3)},
                          {"seconds", sig(run.seconds, 3)}});
      std::fflush(stdout);
      fs::remove_all(run.folder);
    }
    all.emplace_back("ccx CAX8", std::move(points));
  }
  // The cheapest level of each variant within each tolerance.
  json summary = {{"bench", "poke"},
                  {"figure", "accuracy_per_second"},
                  {"case", "Hayes et al. 1972: a/D = 1, nu = 0.45, frictionless, neo-Hookean, d = 1e-4 a"},
                  {"reference", "analytic layer stiffness (tests/axisym/layer_reference, Nystrom, 1e-9)"}};
  for (const double tolerance : {0.01, 0.003}) {
    json row = json::object();
    std::vector<double> times;
    for (const auto& [name, points] : all) {
      const auto hit = std::find_if(points.begin(), points.end(),
                                    [&](const AccuracyPoint& p) { return std::abs(p.error) <= tolerance; });
      if (hit == points.end()) {
        row[name] = {{"level", nullptr},
                     {"note", fmt::format("not within {}% by level {}", 100 * tolerance,
                                          points.empty() ? top : points.back().level)}};
        times.push_back(std::nan(""));
      } else {
        row[name] = {{"level", hit->level}, {"error_percent", sig(100 * hit->error, 3)}, {"seconds", sig(hit->seconds, 3)}};
        times.push_back(hit->seconds);
      }
    }
    if (std::isfinite(times[0]) && std::isfinite(times[1])) row["ratio_one_mesh_to_extrapolated"] = sig(times[0] / times[1], 3);
    if (times.size() > 2 && std::isfinite(times[2]) && std::isfinite(times[1])) {
      row["ratio_ccx_cax8_to_extrapolated"] = sig(times[2] / times[1], 3);
    }
    summary[fmt::format("within_{}_percent", 100 * tolerance)] = row;
  }
  palpa::bench::emit(summary);
}

}  // namespace

int main(int argc, char** argv) {
  bool quick = false;
  bool keep = false;
  std::string only;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--quick") == 0) {
      quick = true;
    } else if (std::strcmp(argv[i], "--keep") == 0) {
      keep = true;
    } else if (std::strcmp(argv[i], "--only") == 0 && i + 1 < argc) {
      only = argv[++i];
    } else {
      fmt::print(stderr, "usage: palpa_bench_poke [--quick] [--keep] [--only curves|ccx|scaling|accuracy|foam]\n");
      return 2;
    }
  }
  const auto wanted = [&](const char* part) { return only.empty() || only == part; };
  try {
    if (wanted("curves")) bench_default_curves();
    if (wanted("ccx")) {
      if (quick) {
        palpa::bench::emit({{"bench", "poke"},
                            {"figure", "ccx_comparison"},
                            {"skipped", true},
                            {"reason", "--quick"}});
      } else {
        bench_ccx(keep);
      }
    }
    if (wanted("scaling")) bench_scaling(quick);
    if (wanted("accuracy")) bench_accuracy(quick);
    if (wanted("foam")) bench_foam();
  } catch (const std::exception& e) {
    fmt::print(stderr, "palpa_bench_poke: {}\n", e.what());
    return 1;
  }
  return 0;
}
