// Everything written to a library reads back exactly: material, template, path, records, snapshot.
#include <gtest/gtest.h>

#include "database/store/cell_state_io.hpp"
#include "database/store/material_parameters.hpp"
#include "tests/database/store_test_util.hpp"

namespace grainbank::db::test {
namespace {

TEST(MaterialParameters, JsonRoundTripAndHash) {
  const dem::Material m = small_material();
  const dem::Material back = material_from_json(material_to_json(m));
  EXPECT_TRUE(material_differences(m, back).empty());
  EXPECT_EQ(parameter_hash(m), parameter_hash(back));
  dem::Material other = m;
  other.effects.rolling = false;
  EXPECT_NE(parameter_hash(m), parameter_hash(other));
  ASSERT_EQ(material_differences(m, other).size(), 1u);
  EXPECT_EQ(material_differences(m, other)[0], "effects.rolling: library true, given false");
}

TEST(MaterialParameters, BondSofteningIsZeroInOlderCataloguesAndTellsLibrariesApart) {
  const dem::Material brittle = small_material();
  const nlohmann::json older = material_to_json(brittle);
  EXPECT_FALSE(older.contains(nlohmann::json::json_pointer("/bond/softening")))
      << "a brittle material is written as before the parameter existed";
  EXPECT_EQ(material_from_json(older).bond.softening, 0);
  dem::Material softening = brittle;
  softening.bond.softening = 4;
  const nlohmann::json written = material_to_json(softening);
  EXPECT_EQ(written.at(nlohmann::json::json_pointer("/bond/softening")), 4);
  EXPECT_EQ(material_from_json(written).bond.softening, 4);
  EXPECT_NE(parameter_hash(brittle), parameter_hash(softening));
  ASSERT_EQ(material_differences(brittle, softening).size(), 1u);
  EXPECT_EQ(material_differences(brittle, softening)[0], "bond.softening: library 0, given 4");
}

TEST(CellState, APartlySoftenedBondsIntegrityRoundTrips) {
  TempDir tmp;
  const dem::DemCell cell = small_cell();
  StoredCell stored{cell.state(), cell.skin()};
  ASSERT_GE(stored.state.bonds.size(), 3u);
  stored.state.bonds[0].integrity = 0.25;
  stored.state.bonds[1].integrity = 0;
  stored.state.bonds[2].integrity = 1;
  {
    const h5::Object file = h5::create_file(tmp.path() / "state.h5");
    write_cell_state(h5::create_group(file, "cell"), stored);
  }
  const h5::Object file = h5::open_file(tmp.path() / "state.h5", false);
  const StoredCell back = read_cell_state(h5::open_group(file, "cell"));
  EXPECT_EQ(first_difference(stored.state, back.state), "");
  EXPECT_EQ(back.state.bonds[0].integrity, 0.25);
}

TEST(Record, RowRoundTripKeepsEveryColumn) {
  std::vector<double> row;
  append_record_row(sample_record(3), row);
  ASSERT_EQ(row.size(), kRecordColumns);
  ASSERT_EQ(record_column_names().size(), kRecordColumns);
  ASSERT_EQ(record_column_units().size(), kRecordColumns);
  EXPECT_EQ(record_from_row(row.data()), sample_record(3));
}

TEST(Record, StressIsStoredAsSymmetricPartInVoigtOrder) {
  dem::Mat3 s;
  s << 1, 2, 3, 4, 5, 6, 7, 8, 9;
  const Stress6 v = to_stress6(s);
  EXPECT_EQ(v, (Stress6{1, 5, 9, 3, 5, 7}));
  EXPECT_EQ(from_stress6(v), (0.5 * (s + s.transpose())).eval());
}

TEST(Library, TemplatePathRecordsAndSnapshotRoundTrip) {
  TempDir tmp;
  const dem::Material material = small_material();
  const dem::DemCell cell = small_cell();
  const StoredCell stored{cell.state(), cell.skin()};
  std::vector<Record> records;
  for (int k = 0; k < 300; ++k) records.push_back(sample_record(k));  // more than one HDF5 chunk
  const nlohmann::json spec = {{"segments", {{{"L", {{0, 1}, {0, 0}}}, {"duration", 0.1}}}}, {"record_interval", 1e-3}};
  std::int64_t template_id = 0, path_id = 0;
  {
    Library library = Library::create(tmp.path() / "LIB", material);
    ShardWriter writer(library, "rank0");
    template_id = writer.add_template(material, {{"seed", 7}}, stored);
    path_id = library.add_path(template_id, spec, material);
    EXPECT_EQ(library.catalogue().path(path_id).status, PathStatus::pending);
    writer.start_path(path_id);
    writer.append_records(path_id, {records.begin(), records.begin() + 100});
    // The writing process reads its own shard while it is open for writing.
    EXPECT_EQ(library.records(path_id), std::vector<Record>(records.begin(), records.begin() + 100));
    writer.append_records(path_id, {records.begin() + 100, records.end()});
    writer.add_snapshot(path_id, 120, stored);
    writer.finish_path(path_id, PathStatus::done, 1.25);
  }
  Library library = Library::open(tmp.path() / "LIB", material);
  EXPECT_EQ(library.records(path_id), records);
  const PathRow path = library.catalogue().path(path_id);
  EXPECT_EQ(path.status, PathStatus::done);
  EXPECT_EQ(path.record_count, 300);
  EXPECT_EQ(path.wall_time, 1.25);
  EXPECT_EQ(nlohmann::json::parse(path.spec), spec);
  EXPECT_EQ(path.spec_hash.size(), 16u);
  const TemplateRow t = library.catalogue().template_row(template_id);
  EXPECT_EQ(t.spheres, 40);
  EXPECT_EQ(t.parameter_hash, parameter_hash(material));
  EXPECT_EQ(nlohmann::json::parse(t.preparation)["seed"], 7);

  for (const StoredCell& back : {library.template_cell(template_id), library.snapshot_cell(path_id, 120)}) {
    EXPECT_EQ(first_difference(back.state, stored.state), "");
    EXPECT_EQ(back.skin, stored.skin);
  }
  EXPECT_EQ(library.catalogue().snapshots_of(path_id).at(0).hdf5_group, "/paths/" + std::to_string(path_id) + "/snapshots/120");
  EXPECT_THROW(library.snapshot_cell(path_id, 121), StoreError);
}

TEST(Library, KeyScalesAndUnitsAreInMeta) {
  TempDir tmp;
  const KeyScales scales{2e-2, 3.5, 0.1};
  Library library = Library::create(tmp.path() / "LIB", small_material(), scales);
  EXPECT_EQ(library.key_scales(), scales);
  EXPECT_EQ(library.catalogue().meta("schema_version"), std::to_string(kSchemaVersion));
  EXPECT_NE(library.catalogue().meta("units").find("tension-positive"), std::string::npos);
  EXPECT_EQ(nlohmann::json::parse(library.catalogue().meta("effects"))["rolling"], true);
}

TEST(Library, SnapshotMustFollowCommittedRecord) {
  TempDir tmp;
  const dem::Material material = small_material();
  Library library = Library::create(tmp.path() / "LIB", material);
  ShardWriter writer(library, "w");
  const dem::DemCell cell = small_cell();
  const std::int64_t t = writer.add_template(material, {}, {cell.state(), cell.skin()});
  const std::int64_t p = library.add_path(t, {}, material);
  writer.start_path(p);
  writer.append_records(p, {sample_record(0)});
  EXPECT_THROW(writer.add_snapshot(p, 1, {cell.state(), cell.skin()}), StoreError);
  writer.add_snapshot(p, 0, {cell.state(), cell.skin()});
  EXPECT_THROW(writer.add_snapshot(p, 0, {cell.state(), cell.skin()}), StoreError);
}

}  // namespace
}  // namespace grainbank::db::test
