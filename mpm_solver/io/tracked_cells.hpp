// DEM cell states of tracked material points, written at every output step of a run:
//   cells/point_<id>_<NNNNNN>.csv  the packing: cell matrix h (3 rows) and one `x, y, z, radius` line
//                                  per sphere, the packing CSV format that dem_sampler reads
//                                  (dem_sampler/driver/packing_csv.hpp), so a cell can be re-run alone;
//   cells/point_<id>_<NNNNNN>.vtk  legacy VTK polydata for ParaView: sphere centres as vertices with
//                                  a `radius` field (Glyph → Sphere, scale by radius) and intact bonds
//                                  as lines (bond ends outside the cell are periodic images, radius 0).
// NNNNNN is the index of the output step, as in points_NNNNNN.vtu. Points without a DEM cell at that
// step write nothing: analytic laws, and cache/hybrid points the library answers (a hybrid point
// writes while it is live).
#pragma once
#include <cstdint>
#include <filesystem>
#include <vector>

#include "dem_sampler/cell/dem_cell.hpp"
#include "mpm_solver/core/solver.hpp"

namespace grainbank::mpm::io {

// The DEM cell behind material point `id` now, or nullptr when it has none. Throws
// std::invalid_argument when the solver has no point with that id.
const dem::DemCell* cell_of_point(const Solver& solver, std::uint32_t id);

// Sphere positions are wrapped into the cell; full precision. Throw std::runtime_error naming the
// file when it cannot be written.
void write_packing_csv(const std::filesystem::path& file, const dem::DemCell& cell);
void write_cell_vtk(const std::filesystem::path& file, const dem::DemCell& cell);

class TrackedCells {
 public:
  // Files go to `folder` (created on the first write).
  TrackedCells(std::filesystem::path folder, std::vector<std::uint32_t> ids);
  void write(const Solver& solver, long output_index);

 private:
  std::filesystem::path folder_;
  std::vector<std::uint32_t> ids_;
};

}  // namespace grainbank::mpm::io
