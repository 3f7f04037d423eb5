// The run's CSV files are on disk row by row, while the run goes on: a long run can be watched (its
// series was empty for hours when the rows stayed in the stream's buffer) and a killed one keeps them.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "common/temporary_directory.hpp"
#include "mpm_solver/io/series_csv.hpp"
#include "tests/mpm/mpm_test_util.hpp"

namespace grainbank::mpm {
namespace {

int lines_on_disk(const std::filesystem::path& file) {
  std::ifstream in(file);
  int n = 0;
  for (std::string line; std::getline(in, line);) ++n;
  return n;
}

TEST(SeriesCsv, EveryRowIsOnDiskWhileTheWriterIsOpen) {
  const TemporaryDirectory dir("gb_series_csv");
  Solver solver = testing::elastic_solver(Grid(Vec2(0, 0), 0.1, 4, 4), 1000, 1e5, 0.3);
  solver.add_point(0, Vec2(0.2, 0.2), 0.01, 0.05);
  io::SeriesCsv series(dir.path() / "series.csv");
  io::TrackedCsv tracked(dir.path() / "tracked.csv", {solver.points()[0].id});
  for (int row = 1; row <= 3; ++row) {
    solver.step(1e-4);
    series.write(solver, 1e-4, solver.time_step_limits());
    tracked.write(solver);
    EXPECT_EQ(lines_on_disk(dir.path() / "series.csv"), 1 + row);
    EXPECT_EQ(lines_on_disk(dir.path() / "tracked.csv"), 1 + row);
  }
}

}  // namespace
}  // namespace grainbank::mpm
