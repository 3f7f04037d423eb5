// The table printed and written by `dem_sampler run`: one row per path record. Column names and
// meanings are listed in README.md; stress is tension-positive, p = -tr σ / 3, q = sqrt(3/2 s:s).
#pragma once
#include <ostream>
#include <string>
#include <vector>

#include "dem_sampler/driver/path_driver.hpp"

namespace grainbank::app {

const std::vector<std::string>& record_columns();
std::vector<double> record_values(const PathRecord& record);

// CSV with full precision (for files), or blank-aligned columns (for terminals).
enum class TableStyle { csv, aligned };

class RecordTable {
 public:
  RecordTable(std::ostream& out, TableStyle style);
  void write_header();
  void write(const PathRecord& record);

 private:
  std::ostream& out_;
  TableStyle style_;
};

}  // namespace grainbank::app
