// ParaView output without a VTK library: one VTU file (UnstructuredGrid of vertices, binary appended
// raw data) per snapshot of the material points, and a PVD collection listing them with their times.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "mpm_solver/core/solver.hpp"

namespace grainbank::mpm::io {

// Point fields: velocity, stress (3×3, tension-positive), pressure, deviatoric_stress (q),
// strain_rate_q (ε̇_q, seed Eq. 5), damage (seed Eq. 6; 0 for analytic laws), density, law
// (material index), id. Throws std::runtime_error naming the file when it cannot be written.
void write_vtu(const std::filesystem::path& file, const Solver& solver);

class PvdCollection {
 public:
  explicit PvdCollection(std::filesystem::path file) : file_(std::move(file)) {}
  // Records a snapshot (path relative to the PVD's folder) and rewrites the collection, so that a
  // run stopped early still leaves a valid file.
  void add(double time, const std::string& relative_path);

 private:
  std::filesystem::path file_;
  std::vector<std::pair<double, std::string>> entries_;
};

}  // namespace grainbank::mpm::io
