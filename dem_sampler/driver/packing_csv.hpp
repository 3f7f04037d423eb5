// Packing files: a periodic packing made by this or another DEM code, as plain text (SI units).
//
//   # comment lines (starting with '#') and blank lines are ignored anywhere
//   hxx, hxy, hxz        <- three lines: the rows of the cell matrix h,
//   hyx, hyy, hyz           whose columns are the cell vectors
//   hzx, hzy, hzz
//   x, y, z, radius      <- then one line per sphere (real coordinates, wrapped into the cell)
//
// Fields are separated by commas and/or blanks.
#pragma once
#include <filesystem>
#include <vector>

#include "dem_sampler/cell/types.hpp"

namespace grainbank::app {

struct Packing {
  dem::Mat3 h = dem::Mat3::Identity();
  std::vector<dem::Vec3> positions;
  std::vector<double> radii;
};

// Throws common::InputError naming the file and the line of the first problem: wrong field count,
// a field that is not a finite number, a non-positive radius, a cell with non-positive volume,
// fewer than two spheres.
Packing read_packing_csv(const std::filesystem::path& file);

}  // namespace grainbank::app
