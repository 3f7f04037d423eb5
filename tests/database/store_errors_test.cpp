// Damaged or foreign files and mismatched physics give errors that name the file and the problem.
#include <gtest/gtest.h>

#include <fstream>

#include "database/store/hdf5_handle.hpp"
#include "database/store/sqlite_handle.hpp"
#include "tests/database/store_test_util.hpp"

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

// Where the chunk holding `row` of `dataset` starts in its file.
haddr_t chunk_address(const h5::Object& dataset, hsize_t row) {
  haddr_t address = HADDR_UNDEF;
  const hsize_t at[2] = {row, 0};
  EXPECT_GE(H5Dget_chunk_info_by_coord(dataset.id(), at, nullptr, &address, nullptr), 0) << dataset.name();
  return address;
}

// Readers accept a file shorter than the space HDF5 allocated (a writer killed in its flush leaves
// it so), but data beyond its end reads as zeros, which neither a contiguous array nor Fletcher-32 (its
// checksum of zeros is zero) rejects: such a read fails, naming the truncation, instead of returning
// zeros. The file ends with the data read: an array's chunk, then a table's last chunk.
TEST(CutShortFile, DataBeyondTheEndIsRefusedNotReadAsZeros) {
  TempDir tmp;
  const std::filesystem::path file = tmp.path() / "cut.h5";
  const std::vector<double> values(2048, 1.5);
  hsize_t array_start = 0, chunk_start = 0;
  {
    const h5::Object root = h5::create_file(file);
    const h5::Object table = h5::create_table(root, "table", 4, 1);
    h5::append_rows(table, std::vector<double>(8, 2.5));
    h5::flush(root);
    h5::write_array(root, "array", values, 0);
    h5::flush(root);
    array_start = chunk_address(h5::open_dataset(root, "array"), 0);
    h5::append_rows(table, std::vector<double>(4, 3.5));
    h5::flush(root);
    chunk_start = chunk_address(table, 2);
  }
  ASSERT_GT(chunk_start, array_start + values.size() * sizeof(double) - 1) << "the last chunk is not after the array";
  std::filesystem::resize_file(file, chunk_start);  // the last chunk is lost
  {
    const h5::Object root = h5::open_file(file, false);
    const h5::Object table = h5::open_dataset(root, "table");
    EXPECT_EQ(h5::read_rows(table, 0, 2), std::vector<double>(8, 2.5));  // before the cut: read
    expect_error([&] { h5::read_rows(table, 0, 3); }, {file.string(), "/table", "truncated"});
  }
  std::filesystem::resize_file(file, array_start + 8);  // the array is cut
  const h5::Object root = h5::open_file(file, false);
  expect_error([&] { h5::read_array<double>(root, "array", 0); }, {file.string(), "/array", "truncated"});
}

// A stored cell's arrays carry a checksum: one damaged byte fails the read, naming the file and
// the array, instead of returning another state (before stop 59 a restart with a byte of a live
// cell's velocity flipped resumed without a word, and ran differently).
TEST(DamagedArray, AFlippedByteIsRefusedNotRead) {
  TempDir tmp;
  const std::filesystem::path file = tmp.path() / "cell.h5";
  const std::vector<double> values(750, 0.25);
  hsize_t start = 0;
  {
    const h5::Object root = h5::create_file(file);
    h5::write_array(root, "velocity", values, 3);
    h5::flush(root);
    start = chunk_address(h5::open_dataset(root, "velocity"), 0);
  }
  {
    const h5::Object root = h5::open_file(file, false);
    EXPECT_EQ(h5::read_array<double>(root, "velocity", 3), values);
  }
  {
    std::fstream f(file, std::ios::in | std::ios::out | std::ios::binary);
    f.seekg(static_cast<std::streamoff>(start + 3005));  // a mantissa byte of one of the doubles
    char byte = 0;
    f.read(&byte, 1);
    byte = static_cast<char>(byte ^ 0xFF);
    f.seekp(static_cast<std::streamoff>(start + 3005));
    f.write(&byte, 1);
  }
  const h5::Object root = h5::open_file(file, false);
  expect_error([&] { h5::read_array<double>(root, "velocity", 3); }, {file.string(), "/velocity", "cannot read"});
}

// Arrays written by older builds, contiguous and without a checksum, read as before.
TEST(DamagedArray, AContiguousArrayOfAnOlderBuildStillReads) {
  TempDir tmp;
  const std::filesystem::path file = tmp.path() / "old.h5";
  const std::vector<double> values{1.5, -2.5, 3.25, 4.0, 5.5, 6.75};
  {
    const h5::Object root = h5::create_file(file);
    const hsize_t dims[2] = {2, 3};
    const hid_t space = H5Screate_simple(2, dims, nullptr);
    const hid_t data = H5Dcreate2(root.id(), "h", H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    ASSERT_GE(H5Dwrite(data, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()), 0);
    H5Dclose(data);
    H5Sclose(space);
  }
  const h5::Object root = h5::open_file(file, false);
  EXPECT_EQ(h5::read_array<double>(root, "h", 3), values);
}

TEST_F(StoreErrors, OverwrittenShardHeaderNamesTheFile) {
  {
    std::fstream f(shard_file(), std::ios::in | std::ios::out | std::ios::binary);
    const std::string garbage(64, 'x');
    f.write(garbage.data(), garbage.size());
  }
  Library library = Library::open(lib());
  expect_error([&] { library.records(path_id_); }, {shard_file().string(), "not a readable HDF5 file"});
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
