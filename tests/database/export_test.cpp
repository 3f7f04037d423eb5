// `celldb export --csv`: one CSV per path whose numbers read back to the stored doubles.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "database/celldb/export_command.hpp"
#include "tests/database/lookup_test_util.hpp"

namespace grainbank::db::test {
namespace {

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> fields;
  std::stringstream in(line);
  for (std::string field; std::getline(in, field, ',');) fields.push_back(field);
  return fields;
}

TEST(Export, CsvRoundTripsEveryRecordExactly) {
  TempDir tmp;
  Library library = Library::create(tmp.path() / "LIB", small_material());
  std::vector<Record> records;
  for (int k = 0; k < 12; ++k) records.push_back(sample_record(k));
  const std::int64_t path = add_done_path(library, "rank0", records);
  library.add_path(library.catalogue().path(path).template_id, {{"p", 2}}, library.material());  // pending: no file

  std::ostringstream out;
  ASSERT_EQ(celldb::run_export({tmp.path() / "LIB", tmp.path() / "csv"}, out), 0);
  EXPECT_NE(out.str().find("exported 12 records of 1 paths"), std::string::npos) << out.str();

  std::ifstream csv(tmp.path() / "csv" / ("path_" + std::to_string(path) + ".csv"));
  std::string line;
  ASSERT_TRUE(std::getline(csv, line));
  EXPECT_EQ(split(line), record_column_names());
  std::vector<Record> read;
  while (std::getline(csv, line)) {
    std::vector<double> row;
    for (const std::string& field : split(line)) row.push_back(std::stod(field));
    ASSERT_EQ(row.size(), kRecordColumns);
    read.push_back(record_from_row(row.data()));
  }
  EXPECT_EQ(read, records);

  std::ifstream index(tmp.path() / "csv" / "paths.csv");
  std::vector<std::string> lines;
  while (std::getline(index, line)) lines.push_back(line);
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_EQ(lines[0], "path,template,status,records,wall_time,spec_hash,file");
  EXPECT_NE(lines[1].find(",done,12,1.5,"), std::string::npos) << lines[1];
  EXPECT_NE(lines[2].find(",pending,0,"), std::string::npos) << lines[2];
  EXPECT_TRUE(std::filesystem::exists(tmp.path() / "csv" / "columns.csv"));
}

}  // namespace
}  // namespace grainbank::db::test
