#include "mpm_solver/io/tracked_cells.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <stdexcept>

#include "mpm_solver/core/dem_backed_law.hpp"

namespace grainbank::mpm::io {

namespace {

std::ofstream open_for_writing(const std::filesystem::path& file) {
  std::ofstream out(file);
  if (!out) throw std::runtime_error(file.string() + ": cannot open for writing");
  out.precision(17);
  return out;
}

void check_written(const std::ofstream& out, const std::filesystem::path& file) {
  if (!out) throw std::runtime_error(file.string() + ": write failed");
}

dem::Vec3 wrapped(const dem::Vec3& s) { return s.array() - s.array().floor(); }

// Sphere centres x = h s with s wrapped into [0, 1)³.
std::vector<dem::Vec3> wrapped_positions(const dem::CellState& state) {
  std::vector<dem::Vec3> x;
  x.reserve(state.reduced_position.size());
  for (const dem::Vec3& s : state.reduced_position) x.push_back(state.h * wrapped(s));
  return x;
}

}  // namespace

const dem::DemCell* cell_of_point(const Solver& solver, std::uint32_t id) {
  for (const MaterialPoint& mp : solver.points()) {
    if (mp.id != id) continue;
    const DemBackedLaw* dem = solver.law(mp.law).dem_backed();
    return dem ? dem->live_cell(mp.slot) : nullptr;
  }
  throw std::invalid_argument("tracked cells: no material point with id " + std::to_string(id));
}

void write_packing_csv(const std::filesystem::path& file, const dem::DemCell& cell) {
  const dem::CellState state = cell.state();
  std::ofstream out = open_for_writing(file);
  out << "# DEM cell at t = " << state.time << " s: cell matrix h (rows; columns are the cell vectors), then x, y, z, "
      << "radius per sphere [m]\n";
  for (int r = 0; r < 3; ++r) out << state.h(r, 0) << ", " << state.h(r, 1) << ", " << state.h(r, 2) << '\n';
  const std::vector<dem::Vec3> x = wrapped_positions(state);
  for (std::size_t k = 0; k < x.size(); ++k)
    out << x[k].x() << ", " << x[k].y() << ", " << x[k].z() << ", " << state.radius[k] << '\n';
  check_written(out, file);
}

void write_cell_vtk(const std::filesystem::path& file, const dem::DemCell& cell) {
  const dem::CellState state = cell.state();
  std::vector<dem::Vec3> points = wrapped_positions(state);
  std::vector<double> radius = state.radius;
  const std::size_t spheres = points.size();
  // A bond runs from sphere i to the nearest periodic image of j, which may lie outside the cell:
  // that end is an extra point.
  std::vector<std::pair<std::size_t, std::size_t>> lines;
  for (std::size_t b = 0; b < state.bonds.size(); ++b) {
    if (!state.bonds[b].intact()) continue;
    const dem::Pair& pair = state.pairs[b];
    const dem::Vec3 si = wrapped(state.reduced_position[pair.i]);
    dem::Vec3 d = wrapped(state.reduced_position[pair.j]) - si;
    d = d.array() - d.array().round();  // nearest image
    points.push_back(state.h * (si + d));
    radius.push_back(0);
    lines.emplace_back(pair.i, points.size() - 1);
  }
  std::ofstream out = open_for_writing(file);
  out << "# vtk DataFile Version 3.0\nDEM cell at t = " << state.time << " s\nASCII\nDATASET POLYDATA\n";
  out << "POINTS " << points.size() << " double\n";
  for (const dem::Vec3& p : points) out << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
  out << "VERTICES " << spheres << ' ' << 2 * spheres << '\n';
  for (std::size_t k = 0; k < spheres; ++k) out << "1 " << k << '\n';
  out << "LINES " << lines.size() << ' ' << 3 * lines.size() << '\n';
  for (const auto& [a, b] : lines) out << "2 " << a << ' ' << b << '\n';
  out << "POINT_DATA " << points.size() << "\nSCALARS radius double 1\nLOOKUP_TABLE default\n";
  for (double r : radius) out << r << '\n';
  check_written(out, file);
}

TrackedCells::TrackedCells(std::filesystem::path folder, std::vector<std::uint32_t> ids)
    : folder_(std::move(folder)), ids_(std::move(ids)) {}

void TrackedCells::write(const Solver& solver, long output_index) {
  for (std::uint32_t id : ids_) {
    const dem::DemCell* cell = cell_of_point(solver, id);
    if (!cell) continue;
    std::filesystem::create_directories(folder_);
    char stem[64];
    std::snprintf(stem, sizeof stem, "point_%u_%06ld", id, output_index);
    write_packing_csv(folder_ / (std::string(stem) + ".csv"), *cell);
    write_cell_vtk(folder_ / (std::string(stem) + ".vtk"), *cell);
  }
}

}  // namespace grainbank::mpm::io
