// SPDX-License-Identifier: AGPL-3.0-or-later
#include "targets.hpp"

#include <unistd.h>

#include <fstream>

#include "palpa/core/error.hpp"
#include "palpa/fit/dataset.hpp"
#include "palpa/io/csv.hpp"
#include "palpa/io/mesh.hpp"
#include "palpa/io/ply.hpp"
#include "palpa/io/vtu.hpp"
#include "palpa/material/material_file.hpp"
#include "palpa/sim3d/scene.hpp"

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

void read_csv_table(const std::filesystem::path& p) { (void)read_csv(p); }
void read_ply_scalars(const std::filesystem::path& p) { (void)read_ply_with_scalars(p); }
void read_vtu_grid(const std::filesystem::path& p) { (void)read_vtu(p); }
void read_material(const std::filesystem::path& p) { (void)material::read_material_file(p); }
void read_fit_dataset(const std::filesystem::path& p) { (void)fit::read_dataset(p); }
void read_sim3d_scene(const std::filesystem::path& p) { (void)sim3d::read_scene(p); }

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
    return d;
  }();
  const auto path = dir / file_name;
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(static_cast<const char*>(data), static_cast<std::streamsize>(size));
  return path;
}

bool run_target(const Target& t, const void* data, std::size_t size) {
  const auto path = write_input(t.file_name, data, size);
  try {
    t.read(path);
    return true;
  } catch (const Error&) {
    return false;
  }
}

}  // namespace palpa::fuzz
