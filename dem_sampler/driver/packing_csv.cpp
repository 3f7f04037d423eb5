#include "dem_sampler/driver/packing_csv.hpp"

#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

#include "common/json_input.hpp"

namespace grainbank::app {
namespace {

using common::InputError;

class LineError {
 public:
  LineError(std::string file, long line) : prefix_(std::move(file) + ":" + std::to_string(line) + ": ") {}
  [[noreturn]] void operator()(const std::string& message) const { throw InputError(prefix_ + message); }

 private:
  std::string prefix_;
};

std::vector<double> parse_fields(const std::string& text, std::size_t expected, const char* names,
                                 const LineError& fail) {
  std::vector<double> values;
  std::size_t pos = 0;
  while (true) {
    pos = text.find_first_not_of(" \t\r,", pos);
    if (pos == std::string::npos) break;
    const std::size_t end = std::min(text.find_first_of(" \t\r,", pos), text.size());
    const std::string field = text.substr(pos, end - pos);
    double v = 0;
    const auto [ptr, ec] = std::from_chars(field.data(), field.data() + field.size(), v);
    if (ec != std::errc() || ptr != field.data() + field.size() || !std::isfinite(v))
      fail("field " + std::to_string(values.size() + 1) + ": expected a finite number, got \"" + field + "\"");
    values.push_back(v);
    pos = end;
  }
  if (values.size() != expected)
    fail("expected " + std::to_string(expected) + " numbers (" + names + "), got " + std::to_string(values.size()));
  return values;
}

}  // namespace

Packing read_packing_csv(const std::filesystem::path& file) {
  const std::string name = file.string();
  std::ifstream in(file);
  if (!in) throw InputError(name + ": cannot open the packing file");
  Packing packing;
  int h_rows = 0;
  long line_number = 0, last_h_line = 0;
  std::string line;
  while (std::getline(in, line)) {
    ++line_number;
    const std::size_t first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    const LineError fail(name, line_number);
    if (h_rows < 3) {
      const std::vector<double> row = parse_fields(line, 3, "a row of the cell matrix h", fail);
      for (int c = 0; c < 3; ++c) packing.h(h_rows, c) = row[static_cast<std::size_t>(c)];
      ++h_rows;
      last_h_line = line_number;
      continue;
    }
    const std::vector<double> sphere = parse_fields(line, 4, "x, y, z, radius", fail);
    if (!(sphere[3] > 0)) {
      std::ostringstream got;
      got << sphere[3];
      fail("radius: expected a positive number, got " + got.str());
    }
    packing.positions.emplace_back(sphere[0], sphere[1], sphere[2]);
    packing.radii.push_back(sphere[3]);
  }
  if (h_rows < 3)
    throw InputError(name + ": expected 3 rows of the cell matrix h before the spheres, got " + std::to_string(h_rows));
  if (const double det = packing.h.determinant(); !(det > 0)) {
    std::ostringstream got;
    got << det;
    LineError(name, last_h_line)("cell matrix h: expected a positive determinant (right-handed cell vectors), got " +
                                 got.str());
  }
  if (packing.radii.size() < 2)
    throw InputError(name + ": expected at least 2 spheres (x, y, z, radius lines), got " +
                     std::to_string(packing.radii.size()));
  return packing;
}

}  // namespace grainbank::app
