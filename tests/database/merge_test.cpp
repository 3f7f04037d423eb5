// `celldb merge`: compatible sources add up, incompatible ones are refused, merging is idempotent.
#include <gtest/gtest.h>

#include <sstream>

#include "database/celldb/merge_command.hpp"
#include "tests/database/lookup_test_util.hpp"
#include "database/store/merge.hpp"

namespace grainbank::db::test {
namespace {

std::int64_t done_records(Library& library) {
  return library.catalogue().paths_by_status()[PathStatus::done].records;
}

TEST(Merge, AcceptsACompatibleLibraryAndIsIdempotent) {
  TempDir tmp;
  Library target = Library::create(tmp.path() / "LIB", small_material());
  add_done_path(target, "rank0", shear_path(7));
  {
    Library source = Library::create(tmp.path() / "RUN", small_material());
    add_done_path(source, "rank0", shear_path(5));
    ShardWriter writer(source, "rank1");
    const std::int64_t t = add_gas_template(source, writer);
    const std::int64_t second = source.add_path(t, {{"p", 2}}, source.material());
    writer.start_path(second);
    writer.append_records(second, shear_path(9, -1.0));
    writer.add_snapshot(second, 4, source.template_cell(t));
    writer.finish_path(second, PathStatus::done, 2.0);
    source.add_path(t, {{"p", 3}}, source.material());  // pending: not merged
  }
  std::ostringstream out;
  ASSERT_EQ(celldb::run_merge({tmp.path() / "LIB", {tmp.path() / "RUN"}}, out), 0);
  EXPECT_NE(out.str().find("2 paths (14 records, 1 snapshots), 2 templates added from 2 shards"), std::string::npos)
      << out.str();
  EXPECT_EQ(done_records(target), 7 + 5 + 9);
  EXPECT_EQ(target.catalogue().table_counts()["paths"], 3);
  EXPECT_EQ(target.catalogue().table_counts()["snapshots"], 1);

  const MergeReport again = merge_into(target, tmp.path() / "RUN");
  EXPECT_EQ(again.paths, 0);
  EXPECT_EQ(again.templates, 0);
  EXPECT_EQ(again.already_merged, 2);
  EXPECT_EQ(again.skipped, 1);  // the pending path
  EXPECT_EQ(done_records(target), 21);

  // The merged records are the source's, bit for bit.
  const std::vector<Record> expected = shear_path(9, -1.0);
  bool found = false;
  for (const PathRow& path : target.catalogue().paths())
    if (path.record_count == 9) {
      EXPECT_EQ(target.records(path.id), expected);
      found = true;
    }
  EXPECT_TRUE(found);
}

TEST(Merge, OneShardOfALibrary) {
  TempDir tmp;
  Library target = Library::create(tmp.path() / "LIB", small_material());
  {
    Library source = Library::create(tmp.path() / "RUN", small_material());
    add_done_path(source, "rank0", shear_path(5));
    add_done_path(source, "rank1", shear_path(3));
  }
  const MergeReport report = merge_into(target, tmp.path() / "RUN" / "shards" / "rank1.h5");
  EXPECT_EQ(report.shards, 1);
  EXPECT_EQ(report.records, 3);
  EXPECT_EQ(done_records(target), 3);
}

TEST(Merge, RefusesIncompatibleSources) {
  TempDir tmp;
  Library target = Library::create(tmp.path() / "LIB", small_material());
  dem::Material other = small_material();
  other.contact.friction = 0.4;
  {
    Library source = Library::create(tmp.path() / "OTHER", other);
    add_done_path(source, "rank0", shear_path(5));
  }
  try {
    merge_into(target, tmp.path() / "OTHER");
    FAIL() << "an incompatible library was merged";
  } catch (const MaterialMismatch& e) {
    EXPECT_NE(std::string(e.what()).find("contact.friction"), std::string::npos) << e.what();
  }
  EXPECT_EQ(target.catalogue().table_counts()["paths"], 0);
  EXPECT_EQ(target.catalogue().table_counts()["shards"], 0);

  // A shard file without its catalogue, and the library itself.
  std::filesystem::create_directories(tmp.path() / "loose");
  std::filesystem::copy_file(tmp.path() / "OTHER" / "shards" / "rank0.h5", tmp.path() / "loose" / "rank0.h5");
  EXPECT_THROW(merge_into(target, tmp.path() / "loose" / "rank0.h5"), StoreError);
  EXPECT_THROW(merge_into(target, tmp.path() / "LIB"), StoreError);
}

}  // namespace
}  // namespace grainbank::db::test
