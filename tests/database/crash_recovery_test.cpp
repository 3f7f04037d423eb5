// A writer process killed between its HDF5 flush and its catalogue commit leaves orphans only:
// the library opens, verify finds them, repair removes them, committed data is untouched and the
// writer can resume. The crash is real: a child process that _exit()s without any cleanup.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <hdf5.h>

#include <fstream>
#include <functional>
#include <iterator>

#include "database/store/verify.hpp"
#include "tests/database/store_test_util.hpp"

namespace grainbank::db::test {
namespace {

// Runs `work` in a child process that then dies abruptly (no destructors, no HDF5/SQLite close).
void crash_after(const std::function<void()>& work) {
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    try {
      work();
    } catch (...) {
      _exit(3);
    }
    _exit(0);
  }
  int status = 0;
  waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFEXITED(status));
  ASSERT_EQ(WEXITSTATUS(status), 0) << "the child failed before its simulated crash";
}

class CrashRecovery : public ::testing::Test {
 protected:
  void SetUp() override {
    const dem::DemCell c = small_cell();
    cell_ = {c.state(), c.skin()};
    Library library = Library::create(lib(), material_);
    ShardWriter writer(library, "rank0");
    template_id_ = writer.add_template(material_, {}, cell_);
    path_id_ = library.add_path(template_id_, {}, material_);
    writer.start_path(path_id_);
    for (int k = 0; k < 10; ++k) committed_.push_back(sample_record(k));
    writer.append_records(path_id_, committed_);
    writer.add_snapshot(path_id_, 4, cell_);
  }

  std::filesystem::path lib() const { return tmp_.path() / "LIB"; }

  void expect_committed_data_intact() {
    Library library = Library::open(lib(), material_);
    EXPECT_EQ(library.records(path_id_), committed_);
    EXPECT_EQ(first_difference(library.snapshot_cell(path_id_, 4).state, cell_.state), "");
    EXPECT_EQ(first_difference(library.template_cell(template_id_).state, cell_.state), "");
  }

  TempDir tmp_;
  dem::Material material_ = small_material();
  StoredCell cell_;
  std::int64_t template_id_ = 0, path_id_ = 0;
  std::vector<Record> committed_;
};

TEST_F(CrashRecovery, CrashBetweenFlushAndCommitLeavesOrphansThatRepairRemoves) {
  crash_after([&] {
    Library library = Library::open(lib(), material_);
    ShardWriter writer(library, "rank0");
    // The first half of append_records / add_snapshot / add_template, then death before the commit.
    writer.shard().append_records(path_id_, {sample_record(10), sample_record(11), sample_record(12)});
    writer.shard().write_snapshot(path_id_, 9, cell_);
    writer.shard().write_template("deadbeef00000000", cell_);
    writer.shard().flush();
    // A second writer that died between creating its shard file and committing the shard row.
    Shard::create(lib() / "shards" / "rank1.h5", "rank1", library.parameter_hash());
  });

  {
    Library library = Library::open(lib(), material_);
    const VerifyReport report = verify_library(library, false);
    EXPECT_EQ(report.inconsistencies(), 0u);
    EXPECT_EQ(report.orphans(), 4u);
    EXPECT_FALSE(report.clean());
    EXPECT_EQ(report.records, 10);
    for (const Finding& f : report.findings) EXPECT_FALSE(f.repaired) << f.message;
  }
  expect_committed_data_intact();
  {
    Library library = Library::open(lib(), material_);
    const VerifyReport repaired = verify_library(library, true);
    EXPECT_EQ(repaired.orphans(), 4u);
    EXPECT_TRUE(repaired.clean());
    EXPECT_TRUE(verify_library(library, false).findings.empty());
  }
  expect_committed_data_intact();
  EXPECT_FALSE(std::filesystem::exists(lib() / "shards" / "rank1.h5"));

  // The writer resumes after the committed records.
  Library library = Library::open(lib(), material_);
  ShardWriter writer(library, "rank0");
  writer.append_records(path_id_, {sample_record(20)});
  std::vector<Record> expected = committed_;
  expected.push_back(sample_record(20));
  EXPECT_EQ(library.records(path_id_), expected);
}

TEST_F(CrashRecovery, CrashBeforeFlushLeavesTheLastFlushedState) {
  crash_after([&] {
    Library library = Library::open(lib(), material_);
    ShardWriter writer(library, "rank0");
    writer.shard().append_records(path_id_, {sample_record(10)});
    writer.shard().write_snapshot(path_id_, 9, cell_);
  });
  Library library = Library::open(lib(), material_);
  EXPECT_EQ(verify_library(library, true).inconsistencies(), 0u);
  EXPECT_TRUE(verify_library(library, false).findings.empty());
  expect_committed_data_intact();
}

TEST_F(CrashRecovery, ResumingWriterDropsUncommittedRowsItself) {
  crash_after([&] {
    Library library = Library::open(lib(), material_);
    ShardWriter writer(library, "rank0");
    writer.shard().append_records(path_id_, {sample_record(10), sample_record(11)});
    writer.shard().flush();
  });
  Library library = Library::open(lib(), material_);
  ShardWriter writer(library, "rank0");
  writer.append_records(path_id_, {sample_record(30)});
  std::vector<Record> expected = committed_;
  expected.push_back(sample_record(30));
  EXPECT_EQ(library.records(path_id_), expected);
  EXPECT_TRUE(verify_library(library, false).findings.empty());
}

TEST_F(CrashRecovery, VerifyReportsMissingCommittedDataAsInconsistency) {
  {
    Shard shard = Shard::open(lib() / "shards" / "rank0.h5", true);
    shard.truncate_records(path_id_, 7);
    shard.remove_group(Shard::snapshot_group(path_id_, 4));
  }
  Library library = Library::open(lib(), material_);
  const VerifyReport report = verify_library(library, true);
  EXPECT_EQ(report.inconsistencies(), 2u);
  EXPECT_FALSE(report.clean());
  bool mentions_rows = false;
  for (const Finding& f : report.findings) mentions_rows |= f.message.find("7 rows but 10 committed") != std::string::npos;
  EXPECT_TRUE(mentions_rows);
}

// File address, size and bytes of the chunk holding row `row` of a path's records table.
struct StoredChunk {
  haddr_t address = 0;
  hsize_t size = 0;
  std::string bytes;
  bool operator==(const StoredChunk&) const = default;
};

StoredChunk stored_chunk(const std::filesystem::path& file, std::int64_t path_id, hsize_t row) {
  StoredChunk chunk;
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const hid_t d = H5Dopen2(f, (Shard::path_group(path_id) + "/records").c_str(), H5P_DEFAULT);
  const hsize_t offset[2] = {row, 0};
  unsigned filter_mask = 0;
  EXPECT_GE(H5Dget_chunk_info_by_coord(d, offset, &filter_mask, &chunk.address, &chunk.size), 0);
  H5Dclose(d);
  H5Fclose(f);
  std::ifstream in(file, std::ios::binary);
  in.seekg(static_cast<std::streamoff>(chunk.address));
  chunk.bytes.resize(chunk.size);
  in.read(chunk.bytes.data(), static_cast<std::streamsize>(chunk.size));
  return chunk;
}

// A writer killed while it writes can tear that write (the kernel stops a large write between pages
// on SIGKILL). Appends therefore never write to a chunk that holds committed records: their chunks
// keep their place and their bytes, checksum included.
TEST_F(CrashRecovery, AppendsNeverRewriteTheChunksOfCommittedRecords) {
  const std::filesystem::path shard = lib() / "shards" / "rank0.h5";
  const auto rows = static_cast<hsize_t>(committed_.size());
  std::vector<StoredChunk> before;
  for (hsize_t row = 0; row < rows; ++row) before.push_back(stored_chunk(shard, path_id_, row));
  {
    Library library = Library::open(lib(), material_);
    ShardWriter writer(library, "rank0");
    writer.append_records(path_id_, {sample_record(30)});
    writer.append_records(path_id_, {sample_record(31), sample_record(32)});
  }
  for (hsize_t row = 0; row < rows; ++row) EXPECT_EQ(stored_chunk(shard, path_id_, row), before[row]) << "row " << row;
  EXPECT_NE(stored_chunk(shard, path_id_, rows).address, before.back().address);
}

}  // namespace
}  // namespace grainbank::db::test
