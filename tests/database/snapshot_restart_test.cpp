// A snapshot restores a DemCell bit for bit, and the restored cell continues exactly like the
// original: the warm start of the MPM fallback loses nothing.
#include <gtest/gtest.h>

#include "tests/database/store_test_util.hpp"

namespace grainbank::db::test {
namespace {

TEST(SnapshotRestart, RestoredCellIsBitIdenticalAndContinuesBitIdentically) {
  TempDir tmp;
  const dem::Material material = small_material();
  dem::DemCell original = small_cell();
  for (int k = 0; k < 3; ++k) original.advance(shear_increment(), increment_duration(original), substepping());
  ASSERT_GT(original.contact_count(), 0u);
  ASSERT_GT(original.measures().bonds, 0);

  std::int64_t path_id = 0;
  {
    Library library = Library::create(tmp.path() / "LIB", material);
    ShardWriter writer(library, "rank0");
    const std::int64_t t = writer.add_template(material, {}, {original.state(), original.skin()});
    path_id = library.add_path(t, {{"L", "shear"}}, material);
    writer.start_path(path_id);
    writer.append_records(path_id, {sample_record(0)});
    writer.add_snapshot(path_id, 0, {original.state(), original.skin()});
  }
  Library library = Library::open(tmp.path() / "LIB", material);
  dem::DemCell restored = library.restore(library.snapshot_cell(path_id, 0));
  EXPECT_EQ(first_difference(restored.state(), original.state()), "");

  for (int k = 0; k < 4; ++k) {
    const auto a = original.advance(shear_increment(), increment_duration(original), substepping());
    const auto b = restored.advance(shear_increment(), increment_duration(restored), substepping());
    EXPECT_TRUE(same_bits(a.stress, b.stress)) << "increment " << k;
    ASSERT_EQ(first_difference(restored.state(), original.state()), "") << "after increment " << k;
  }
  EXPECT_GT(original.state().time, 0);
}

}  // namespace
}  // namespace grainbank::db::test
