// End to end: the built dem_sampler binary prepares a tiny cohesive cell, shears it, writes a CSV
// table; and turns input errors into one "dem_sampler: " line with exit code 1.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <sys/wait.h>

#include "dem_sampler/app/record_table.hpp"
#include "tests/app/temp_dir.hpp"

namespace grainbank {
namespace {

const char* const kCell = R"({
  "material": {"density": 920, "k_n": 2000, "k_t": 600, "restitution": 0.3, "friction": 0.2,
               "bond": {"tensile_strength": 8e-4, "shear_strength": 9.6e-4, "bonding_distance": 0.05}},
  "effects": {"cohesion": true},
  "preparation": {"spheres": 40, "diameter": {"min": 3.4e-4, "max": 4.0e-4}, "pressure": 1000, "seed": 3,
                  "inertial_number": 0.01}
})";
const char* const kPath = R"({"segments": [{"L": [[0, 1], [0, 0]], "duration": 0.02}], "record_interval": 0.005})";

struct Outcome {
  int exit_code = -1;
  std::string out, err;
};

std::string slurp(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

Outcome run_dem_sampler(const testing::TempDir& dir, const std::string& arguments) {
  const auto out = dir.path() / "stdout.txt", err = dir.path() / "stderr.txt";
  const std::string command =
      std::string("'") + DEM_SAMPLER_BINARY + "' " + arguments + " > '" + out.string() + "' 2> '" + err.string() + "'";
  const int status = std::system(command.c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(out), slurp(err)};
}

TEST(RunCli, WritesCsvWithHeaderAndFiniteRows) {
  const testing::TempDir dir;
  const auto cell = dir.write("cell.json", kCell), path = dir.write("path.json", kPath);
  const auto csv = dir.path() / "out.csv";
  const Outcome r = run_dem_sampler(dir, "run '" + cell.string() + "' --path '" + path.string() + "' --out '" +
                                             csv.string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::ifstream in(csv);
  ASSERT_TRUE(in) << "no CSV written";
  std::string header;
  std::getline(in, header);
  std::string expected_header;
  for (const auto& c : app::record_columns()) expected_header += (expected_header.empty() ? "" : ",") + c;
  EXPECT_EQ(header, expected_header);
  int rows = 0;
  for (std::string line; std::getline(in, line); ++rows) {
    std::stringstream fields(line);
    std::size_t count = 0;
    for (std::string field; std::getline(fields, field, ','); ++count)
      EXPECT_TRUE(std::isfinite(std::stod(field))) << "row " << rows << ": " << line;
    EXPECT_EQ(count, app::record_columns().size()) << line;
  }
  EXPECT_EQ(rows, 1 + 4) << "the initial state and one row per record interval";
}

TEST(RunCli, WarnsOfLargeOverlapsOnlyWhenKnIsTooSoftForThePressure) {
  const testing::TempDir dir;
  const auto path = dir.write("path.json", kPath);
  std::string squeezed = kCell;  // k_n = 2000 N/m at 400 kPa: overlaps of ~8 % of the radius sum
  squeezed.replace(squeezed.find("\"pressure\": 1000"), 16, "\"pressure\": 4e5");
  const auto soft = dir.write("soft.json", squeezed), normal = dir.write("cell.json", kCell);
  const Outcome warned = run_dem_sampler(dir, "run '" + soft.string() + "' --path '" + path.string() + "'");
  ASSERT_EQ(warned.exit_code, 0) << warned.err;
  EXPECT_NE(warned.err.find("warning: large overlaps"), std::string::npos) << warned.err;
  EXPECT_NE(warned.err.find("raise contact.k_n"), std::string::npos) << warned.err;
  const Outcome quiet = run_dem_sampler(dir, "run '" + normal.string() + "' --path '" + path.string() + "'");
  ASSERT_EQ(quiet.exit_code, 0) << quiet.err;
  EXPECT_EQ(quiet.err.find("large overlaps"), std::string::npos) << quiet.err;
}

TEST(RunCli, InputErrorIsOneLineAndExitCodeOne) {
  const testing::TempDir dir;
  std::string bad = kCell;
  bad.replace(bad.find("\"k_n\": 2000"), 11, "\"k_n\": -5");
  const auto cell = dir.write("cell.json", bad), path = dir.write("path.json", kPath);
  const Outcome r = run_dem_sampler(dir, "run '" + cell.string() + "' --path '" + path.string() + "'");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(r.err, "dem_sampler: " + cell.string() + ": /material/k_n: expected a positive number, got -5\n");
}

TEST(RunCli, ACellThatDivergesStopsWithOneLineAndLeavesTheLibraryEmpty) {
  const testing::TempDir dir;
  std::string crushed = kCell;
  crushed.replace(crushed.find("\"pressure\": 1000"), 16, "\"pressure\": 1e308");
  const auto cell = dir.write("cell.json", crushed);
  const auto library = dir.path() / "lib";
  const Outcome r = run_dem_sampler(dir, "prepare '" + cell.string() + "' --library '" + library.string() + "'");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_EQ(r.err.rfind("dem_sampler: " + cell.string() + ": DEM cell diverged at t = ", 0), 0u) << r.err;
  EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << r.err;
  const Outcome healthy = run_dem_sampler(dir, "prepare '" + dir.write("ok.json", kCell).string() + "' --library '" +
                                                  library.string() + "'");
  ASSERT_EQ(healthy.exit_code, 0) << healthy.err;
  EXPECT_NE(healthy.out.find("template 1 (prepared)"), std::string::npos)
      << "the failed preparation stored no template: " << healthy.out;
}

TEST(RunCli, UsageErrorIsOneLineAndExitCodeOne) {
  const testing::TempDir dir;
  const Outcome r = run_dem_sampler(dir, "run --no-such-option");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(r.err.rfind("dem_sampler: ", 0), 0u) << r.err;
  EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << r.err;
}

TEST(RunCli, HelpOnEverySubcommand) {
  const testing::TempDir dir;
  for (const char* sub : {"run", "bench"}) {
    const Outcome r = run_dem_sampler(dir, std::string(sub) + " --help");
    EXPECT_EQ(r.exit_code, 0) << sub;
    EXPECT_NE(r.out.find("--"), std::string::npos) << sub << ": " << r.out;
  }
}

}  // namespace
}  // namespace grainbank
