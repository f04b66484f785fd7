// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// VTK XML unstructured grids (.vtu) for ParaView, and .pvd series of them.
//
// Written files: one Piece, byte_order LittleEndian, header_type UInt64, every
// array in one appended block of raw binary (the layout ParaView writes itself):
// Points Float64×3, connectivity and offsets Int64, types UInt8, point and cell
// data Float64 with 1 or 3 components. Cell types: vertex, triangle, quad,
// tetra. Planar meshes (the axisymmetric (r, z) solver) are written as 3D points
// with a third coordinate of 0 (see embed_planar).
//
// The reader reads what palpa writes and what ParaView or meshio write without
// compression: appended raw, inline base64 or ascii arrays, UInt32 or UInt64
// headers, either byte order, any numeric array type.

#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "palpa/geometry/mesh.hpp"

namespace palpa {

// VTK's cell type numbers for the cells palpa writes.
enum class VtkCellType : std::uint8_t { Vertex = 1, Triangle = 5, Quad = 9, Tetra = 10 };

// Corners per cell: 1, 3, 4, 4.
int vtk_cell_size(VtkCellType type) noexcept;

// Cells of one type.
struct CellBlock {
  VtkCellType type = VtkCellType::Triangle;
  // #C×k corners as 0-based point rows, k = vtk_cell_size(type), in VTK's corner
  // order (quads counter-clockwise around the cell).
  Eigen::MatrixXi nodes;
};

// A named array over points or cells.
struct DataArray {
  std::string name;
  // #rows×components: 1 column for a scalar, 3 for a vector; rows are points
  // (point data) or cells (cell data, over the blocks in order). Units are the
  // caller's (palpa writes SI).
  Eigen::MatrixXd values;
};

struct UnstructuredGrid {
  // #P×3 point positions [m].
  Eigen::MatrixX3d points;
  // Cells, block after block; cell data rows follow this order.
  std::vector<CellBlock> cells;
  std::vector<DataArray> point_data;  // each #P rows
  std::vector<DataArray> cell_data;   // each cell_count() rows

  // Total cells over all blocks.
  Eigen::Index cell_count() const noexcept;
  // The point (cell) data array `name`, or nullptr.
  const DataArray* find_point_data(const std::string& name) const noexcept;
  const DataArray* find_cell_data(const std::string& name) const noexcept;
};

// (r, z) rows -> (r, z, 0) rows: #P×2 -> #P×3, for planar (axisymmetric) meshes.
Eigen::MatrixX3d embed_planar(const Eigen::MatrixX2d& rz);

// A grid holding the triangles of a surface (no data arrays).
UnstructuredGrid grid_of(const SurfaceMesh& mesh);
// A grid holding the tets of a tet mesh, with cell data "region" (as Float64)
// when mesh.region is set. Boundary triangles are not included.
UnstructuredGrid grid_of(const TetMesh& mesh);

// Writes `grid` atomically. Throws palpa::Error (Internal) when arrays do not
// match the grid (wrong row count, bad cell index, empty or duplicate names) and
// (Input) when the folder cannot be written.
void write_vtu(const std::filesystem::path& path, const UnstructuredGrid& grid);

// Reads a .vtu with one Piece and cells of the four types above. Integer arrays
// are returned as doubles. Throws palpa::Error (Input) naming the file and the
// line or array: missing or empty file, not an UnstructuredGrid, compressed
// data (not supported), several pieces, an array shorter than its header or
// declared size, a cell type palpa does not handle, an index out of range.
UnstructuredGrid read_vtu(const std::filesystem::path& path);

// One time step of a .pvd collection.
struct PvdEntry {
  double time = 0.0;           // the step's time or load parameter (any unit)
  std::filesystem::path file;  // the .vtu, relative to the .pvd's folder
};

// Writes a ParaView collection listing `entries` in order, atomically.
void write_pvd(const std::filesystem::path& path, const std::vector<PvdEntry>& entries);
// Reads the DataSet entries of a .pvd (timestep and file attributes).
std::vector<PvdEntry> read_pvd(const std::filesystem::path& path);

// A time series written step by step: add() writes `<stem>_<step>.vtu` beside
// the .pvd and rewrites the .pvd, so an interrupted run leaves a valid series of
// the steps done so far.
class PvdSeries {
 public:
  explicit PvdSeries(std::filesystem::path pvd_path);
  // Writes one step; returns the path of its .vtu. `time` must increase from
  // step to step (programmer error otherwise, asserted).
  std::filesystem::path add(double time, const UnstructuredGrid& grid);
  const std::vector<PvdEntry>& entries() const noexcept { return entries_; }

 private:
  std::filesystem::path pvd_path_;
  std::vector<PvdEntry> entries_;
};

}  // namespace palpa
