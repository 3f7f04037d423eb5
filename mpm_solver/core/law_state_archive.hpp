// Where a law saves what its points carry between steps (ConstitutiveLaw::save_state), without
// knowing the file format: named tables of doubles and whole DEM cells. The restart file backs it
// with HDF5 (io/restart.cpp) and keeps the names of different laws apart, so a law chooses its names
// freely.
#pragma once
#include <cstddef>
#include <string>
#include <vector>

#include "dem_sampler/cell/cell_state.hpp"

namespace grainbank::dem {
class DemCell;
}

namespace grainbank::mpm {

class LawStateWriter {
 public:
  virtual ~LawStateWriter() = default;
  // `rows` holds rows of `columns` doubles each (possibly none).
  virtual void write_table(const std::string& name, const std::vector<double>& rows, std::size_t columns) = 0;
  // Everything needed to continue the cell bit for bit.
  virtual void write_cell(const std::string& name, const dem::DemCell& cell) = 0;
};

class LawStateReader {
 public:
  virtual ~LawStateReader() = default;
  // Throw with the file and name when the entry is missing or has another number of columns.
  virtual std::vector<double> read_table(const std::string& name, std::size_t columns) = 0;
  // Whether the file holds the entry: a law reads what an older build did not write, or not.
  virtual bool has_table(const std::string& name) = 0;
  virtual dem::CellState read_cell(const std::string& name) = 0;
};

}  // namespace grainbank::mpm
