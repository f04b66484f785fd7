// SPDX-License-Identifier: AGPL-3.0-or-later
#include "targets.hpp"

#include <unistd.h>

#include <fstream>

#include "palpa/core/atomic_file.hpp"
#include "palpa/core/error.hpp"
#include "palpa/core/input_file.hpp"
#include "palpa/design/checkpoint.hpp"
#include "palpa/design/scene.hpp"
#include "palpa/fit/checkpoint.hpp"
#include "palpa/fit/dataset.hpp"
#include "palpa/fit/optimize.hpp"
#include "palpa/io/csv.hpp"
#include "palpa/io/mesh.hpp"
#include "palpa/io/ply.hpp"
#include "palpa/io/vtu.hpp"
#include "palpa/material/material_file.hpp"
#include "palpa/material/models.hpp"
#include "palpa/pipeline/subject.hpp"
#include "palpa/rest/scene.hpp"
#include "palpa/sim3d/scene.hpp"
#include "palpa/sim3d/shapes.hpp"

namespace palpa::fuzz {

namespace {

void read_surface(const std::filesystem::path& p) { (void)read_surface_mesh(p); }
void read_tets(const std::filesystem::path& p) { (void)read_tet_mesh(p); }

// TetGen's three files from one input: the bytes up to the first "\n--ele\n"
// are the .node file, then the .ele file, then after "\n--face\n" the .face
// file (each part optional), so that the fuzzer mutates all three together.
void read_tetgen_files(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  const std::string all((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto cut = [&](std::size_t from, const std::string& mark) {
    const auto at = all.find(mark, from);
    return at == std::string::npos ? all.size() : at;
  };
  const std::size_t e = cut(0, "\n--ele\n");
  const std::size_t f = cut(e, "\n--face\n");
  const auto part = [&](std::size_t a, std::size_t b, std::size_t skip) {
    a = std::min(all.size(), a + skip);
    return all.substr(a, b > a ? b - a : 0);
  };
  const auto stem = p.parent_path() / "mesh";
  const auto write = [](const std::filesystem::path& f, const std::string& s) {
    std::ofstream(f, std::ios::binary | std::ios::trunc) << s;
  };
  write(stem.string() + ".node", all.substr(0, e));
  write(stem.string() + ".ele", part(e, f, 7));
  if (f < all.size()) {
    write(stem.string() + ".face", part(f, all.size(), 8));
  } else {
    std::error_code ec;
    std::filesystem::remove(stem.string() + ".face", ec);
  }
  (void)read_tet_mesh(stem.string() + ".node");
}

// Splits the input at the first `mark`: the part before it is returned, the
// part after it (if any) is written to `companion` beside the input (removed
// when there is no mark), so that the fuzzer mutates both files together.
std::string split_off(const std::filesystem::path& p, const std::string& mark, const std::filesystem::path& companion) {
  std::ifstream in(p, std::ios::binary);
  const std::string all((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto at = all.find(mark);
  std::error_code ec;
  std::filesystem::remove(companion, ec);
  if (at == std::string::npos) return all;
  std::ofstream(companion, std::ios::binary | std::ios::trunc) << all.substr(at + mark.size());
  return all.substr(0, at);
}

void read_csv_table(const std::filesystem::path& p) { (void)read_csv(p); }
void read_ply_scalars(const std::filesystem::path& p) { (void)read_ply_with_scalars(p); }
void read_vtu_grid(const std::filesystem::path& p) { (void)read_vtu(p); }
void read_material(const std::filesystem::path& p) { (void)material::read_material_file(p); }
void read_fit_dataset(const std::filesystem::path& p) { (void)fit::read_dataset(p); }
void read_sim3d_scene(const std::filesystem::path& p) { (void)sim3d::read_scene(p); }
void read_rest(const std::filesystem::path& p) { (void)rest::read_rest_scene(p); }
// Without the baselines' supports (each a mesh generation of its own), as
// `palpa design --resume` and the summary read them; their entries are read.
void read_design(const std::filesystem::path& p) { (void)design::read_design_scene(p, false); }

// A fit checkpoint against the companion dataset (fit.json, curve.csv) with
// the default options and a neo-Hookean start; the input's part after
// "\n--warm\n" is the warm-start file its first guess names.
void read_fit_checkpoint(const std::filesystem::path& p) {
  const auto dir = p.parent_path();
  const std::string text = split_off(p, "\n--warm\n", dir / "checkpoint.warm-0-1.bin");
  const auto path = dir / "checkpoint.json";
  std::ofstream(path, std::ios::binary | std::ios::trunc) << text;
  const fit::Dataset d = fit::read_dataset(dir / "fit.json");
  fit::FitOptions o;
  o.model = "neo-hookean";
  const material::NeoHookean initial(30e3, 0.45);
  fit::Checkpoint c(path, d, o, initial);
  c.load();
  for (std::size_t g = 0; g < 3; ++g) {
    fit::GuessResult r;
    fit::GuessState s;
    std::vector<axisym::WarmStart> warm;
    (void)c.done(g);
    (void)c.restore(g, r, s, &warm);
  }
}

// A design checkpoint against a run of per-vertex moves on 4 design
// variables and a body of 6 DOFs with 2 springs.
void read_design_checkpoint_file(const std::filesystem::path& p) {
  design::DesignCheckpoint like;
  like.method = design::DesignMethod::Lbfgs;
  like.gamma = 1.0;
  like.moves = {1e-6, 1e-5, 1e-4};
  like.theta = Eigen::VectorXd::Zero(4);
  like.bodies.resize(1);
  like.bodies[0].state.x = Eigen::VectorXd::Zero(6);
  like.bodies[0].state.spring_areas.assign(2, 0.0);
  (void)design::read_design_checkpoint(p, like);
}

// The files that seeds name beside the input: a curve of each kind, a fit
// dataset of one curve, a tet layer (a cube of five tets, attached at its
// base) and a support surface.
void write_companions(const std::filesystem::path& dir) {
  std::ofstream(dir / "curve.csv") << "indentation_mm,force_N\n0,0\n0.2,0.05\n0.4,0.11\n0.6,0.18\n0.8,0.26\n";
  std::ofstream(dir / "stress.csv") << "stretch,stress_kPa\n1,0\n0.95,-1.6\n0.9,-3.4\n0.85,-5.5\n0.8,-7.9\n";
  std::ofstream(dir / "fit.json")
      << R"({"palpa_dataset": 1, "test": "indentation", "layer_depth": "10 mm", "lateral_size": "100 mm",)"
         R"( "contact": "frictionless", "poisson": 0.45,)"
         R"( "curves": [{"file": "curve.csv", "radius": "3 mm", "role": "train"}]})";
  TetMesh cube;
  cube.V.resize(8, 3);
  for (int i = 0; i < 8; ++i) cube.V.row(i) << 0.05 * (i & 1), 0.05 * ((i >> 1) & 1), 0.05 * ((i >> 2) & 1);
  cube.T.resize(5, 4);
  cube.T << 0, 1, 2, 4, 1, 3, 2, 7, 1, 4, 5, 7, 2, 4, 7, 6, 1, 2, 4, 7;
  UnstructuredGrid g = grid_of(cube);
  g.point_data.push_back({"attached", (cube.V.col(2).array() == 0.0).cast<double>().matrix()});
  write_vtu(dir / "layer.vtu", g);
  write_surface_mesh(dir / "support.obj", sim3d::make_box_surface(Eigen::Vector3d(0.2, 0.2, 0.05), 2));
  // For subjects and cohorts: a design scene to name, and a subject a cohort lists.
  std::ofstream(dir / "seat.json") << R"({"palpa_design": 1})";
  std::ofstream(dir / "member.json")
      << R"({"palpa_subject": 1, "name": "m01", "body": {"generate": {"shape": "sphere", "length": "100 mm"}},)"
         R"( "locations": [{"name": "top", "position": ["0 mm", "0 mm", "50 mm"],)"
         R"( "pokes": [{"radius": "3 mm", "curve": "curve.csv"}], "depth_search": {"from": "5 mm", "to": "15 mm",)"
         R"( "count": 3}}], "design": "seat.json"})";
}

// A subject file or a cohort of them, as `palpa subject check` reads it.
void read_subject_or_cohort(const std::filesystem::path& p) { (void)pipeline::read_subjects(p); }

// An output folder's journal as anyone may have edited it, then a run that
// takes the folder over (--overwrite) and succeeds. The input is the journal
// of the run before; its part after "\n--previous\n" is a journal that run
// had set aside itself (a run that neither finished nor was resumed). The
// folder holds files of both, an input of this run, and links to a folder
// and a file beside it. Whatever the journals list: nothing outside the
// folder changes (no link is followed), and this run's input and output stay.
void take_over_output_folder(const std::filesystem::path& p) {
  const auto root = p.parent_path() / "journal-case";
  const auto out = root / "out", outside = root / "outside";
  std::error_code ec;
  std::filesystem::remove_all(root, ec);
  std::filesystem::create_directories(out / "sub" / "deeper");
  std::filesystem::create_directories(outside / "sub");
  const auto put = [](const std::filesystem::path& f, const std::string& text) {
    std::ofstream(f, std::ios::binary | std::ios::trunc) << text;
  };
  for (const char* f : {"keep.txt", "sub/b.txt", "a.txt"}) put(outside / f, "outside\n");
  for (const char* f : {"a.txt", "sub/b.txt", "sub/deeper/c.txt", "input.json", "result.txt"}) put(out / f, "earlier\n");
  std::filesystem::create_directory_symlink("../outside", out / "lnk");
  std::filesystem::create_directory_symlink("../../outside/sub", out / "sub" / "lnk");
  std::filesystem::create_symlink("../outside/keep.txt", out / "keep-link.txt");
  const std::string journal = split_off(p, "\n--previous\n", out / kPreviousJournalName);
  put(out / kOutputJournalName, journal);
  guard_inputs(true);  // as the CLI does
  remember_input(out / "input.json");
  {
    OutputFolder folder(out);
    write_file_atomic(out / "result.txt", [](std::ostream& o) { o << "this run\n"; });
    folder.keep();
  }
  guard_inputs(false);
  const auto holds = [](const std::filesystem::path& f, const std::string& text) {
    std::ifstream in(f, std::ios::binary);
    const std::string s((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    return s == text;
  };
  for (const char* f : {"keep.txt", "sub/b.txt", "a.txt"}) {
    if (!holds(outside / f, "outside\n")) throw std::logic_error(std::string("the journal reached outside/") + f);
  }
  if (!holds(out / "input.json", "earlier\n")) throw std::logic_error("the journal removed the run's input");
  if (!holds(out / "result.txt", "this run\n")) throw std::logic_error("the journal removed the run's output");
  const auto entries = std::distance(std::filesystem::recursive_directory_iterator(outside),
                                     std::filesystem::recursive_directory_iterator());
  if (entries != 4) throw std::logic_error("the folder beside the output changed");
}


}  // namespace

const std::vector<Target>& targets() {
  static const std::vector<Target> all{
      {"csv", "input.csv", read_csv_table},
      {"obj", "input.obj", read_surface},
      {"ply", "input.ply", read_ply_scalars},
      {"stl", "input.stl", read_surface},
      {"off", "input.off", read_surface},
      {"vtu", "input.vtu", read_vtu_grid},
      {"msh", "input.msh", read_tets},
      {"tetgen", "input.txt", read_tetgen_files},
      {"material", "material.json", read_material},
      {"dataset", "dataset.json", read_fit_dataset},
      {"scene", "scene.json", read_sim3d_scene},
      {"rest", "rest.json", read_rest},
      {"design", "design.json", read_design},
      {"fit_checkpoint", "fit-checkpoint.txt", read_fit_checkpoint},
      {"design_checkpoint", "design-checkpoint.json", read_design_checkpoint_file},
      {"subject", "subject.json", read_subject_or_cohort},
      {"journal", "journal.txt", take_over_output_folder},
  };
  return all;
}

const Target* find_target(const std::string& name) {
  for (const Target& t : targets()) {
    if (t.name == name) return &t;
  }
  return nullptr;
}

std::filesystem::path write_input(const std::string& file_name, const void* data, std::size_t size) {
  static const std::filesystem::path dir = [] {
    auto d = std::filesystem::temp_directory_path() / ("palpa-fuzz-" + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
    write_companions(d);
    return d;
  }();
  const auto path = dir / file_name;
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(static_cast<const char*>(data), static_cast<std::streamsize>(size));
  return path;
}

bool run_target(const Target& t, const void* data, std::size_t size, std::string* refusal) {
  const auto path = write_input(t.file_name, data, size);
  try {
    t.read(path);
    return true;
  } catch (const Error& e) {
    if (refusal != nullptr) *refusal = e.what();
    return false;
  }
}

}  // namespace palpa::fuzz
