// Damaged or foreign files and mismatched physics give errors that name the file and the problem.
#include <gtest/gtest.h>

#include <fstream>

#include "store/sqlite_handle.hpp"
#include "store_test_util.hpp"

namespace grainbank::db::test {
namespace {

// Asserts that `call` throws an E whose message contains every fragment.
template <class E = StoreError, class Call>
void expect_error(Call call, std::initializer_list<std::string> fragments) {
  try {
    call();
    ADD_FAILURE() << "no exception";
  } catch (const E& e) {
    for (const std::string& f : fragments) EXPECT_NE(std::string(e.what()).find(f), std::string::npos) << e.what();
  }
}

class StoreErrors : public ::testing::Test {
 protected:
  void SetUp() override {
    const dem::DemCell c = small_cell();
    Library library = Library::create(lib(), material_);
    ShardWriter writer(library, "rank0");
    template_id_ = writer.add_template(material_, {}, {c.state(), c.skin()});
    path_id_ = library.add_path(template_id_, {}, material_);
    writer.start_path(path_id_);
    std::vector<Record> records;
    for (int k = 0; k < 50; ++k) records.push_back(sample_record(k));
    writer.append_records(path_id_, records);
  }
  std::filesystem::path lib() const { return tmp_.path() / "LIB"; }
  std::filesystem::path shard_file() const { return lib() / "shards" / "rank0.h5"; }

  TempDir tmp_;
  dem::Material material_ = small_material();
  std::int64_t template_id_ = 0, path_id_ = 0;
};

TEST_F(StoreErrors, TruncatedShardNamesTheFile) {
  std::filesystem::resize_file(shard_file(), std::filesystem::file_size(shard_file()) / 2);
  Library library = Library::open(lib());
  expect_error([&] { library.records(path_id_); }, {shard_file().string(), "truncated"});
  expect_error([&] { library.template_cell(template_id_); }, {shard_file().string()});
}

TEST_F(StoreErrors, OverwrittenShardHeaderNamesTheFile) {
  {
    std::fstream f(shard_file(), std::ios::in | std::ios::out | std::ios::binary);
    const std::string garbage(64, 'x');
    f.write(garbage.data(), garbage.size());
  }
  Library library = Library::open(lib());
  expect_error([&] { library.records(path_id_); }, {shard_file().string(), "not a readable HDF5 shard"});
}

TEST_F(StoreErrors, MissingShardNamesTheFile) {
  std::filesystem::remove(shard_file());
  Library library = Library::open(lib());
  expect_error([&] { library.records(path_id_); }, {shard_file().string(), "missing"});
}

TEST_F(StoreErrors, MissingCatalogue) {
  std::filesystem::remove(lib() / "catalogue.sqlite");
  expect_error([&] { Library::open(lib()); }, {"catalogue.sqlite", "missing"});
  expect_error([&] { Library::open(tmp_.path() / "nowhere"); }, {"nowhere", "library directory is missing"});
}

TEST_F(StoreErrors, CorruptCatalogueNamesTheFile) {
  for (const char* suffix : {"-wal", "-shm"}) std::filesystem::remove(lib() / (std::string("catalogue.sqlite") + suffix));
  {
    std::ofstream f(lib() / "catalogue.sqlite", std::ios::binary | std::ios::trunc);
    f << std::string(4096, 'z');
  }
  expect_error([&] { Library::open(lib()); }, {"catalogue.sqlite", "not a database"});
}

TEST_F(StoreErrors, NewerSchemaIsRefused) {
  {
    SqliteConnection db(lib() / "catalogue.sqlite", false);
    db.execute("UPDATE meta SET value = '99' WHERE name = 'schema_version'");
  }
  expect_error([&] { Library::open(lib()); }, {"catalogue.sqlite", "schema version 99 is newer", "(1)"});
}

TEST_F(StoreErrors, MismatchedMaterialIsRefusedNamingTheParameter) {
  dem::Material other = material_;
  other.contact.friction = 0.4;
  other.effects.kinetic_stress = false;
  expect_error<MaterialMismatch>([&] { Library::open(lib(), other); },
                                 {"catalogue.sqlite", "contact.friction: library 0.5, given 0.4",
                                  "effects.kinetic_stress: library true, given false"});
  Library library = Library::open(lib());
  expect_error<MaterialMismatch>([&] { library.add_path(template_id_, {}, other); }, {"contact.friction"});
  ShardWriter writer(library, "rank0");
  const dem::DemCell c = small_cell();
  expect_error<MaterialMismatch>([&] { writer.add_template(other, {}, {c.state(), c.skin()}); },
                                 {"the template", "contact.friction"});
}

TEST_F(StoreErrors, CreatingOverAnExistingLibraryIsRefused) {
  expect_error([&] { Library::create(lib(), material_); }, {lib().string(), "not empty"});
}

}  // namespace
}  // namespace grainbank::db::test
