// Readers never block the writer: a second process reads the library (catalogue, records, lookup
// index) while the first appends records, and never fails nor sees uncommitted or half-written data.
// The writer waits after its first batch until the reader has read it: the reader certainly reads
// while a writer is alive and finds committed records, however fast either runs.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include "database/lookup/lookup_index.hpp"
#include "tests/database/lookup_test_util.hpp"

namespace grainbank::db::test {
namespace {

constexpr int kPaths = 12, kAppends = 15, kBatch = 6;

Record expected_record(std::int64_t path, std::int64_t index) {
  Record r = sample_record(static_cast<int>(index % 50));
  r.time = 1e4 * static_cast<double>(path) + static_cast<double>(index);
  r.F = dem::Mat3::Identity();  // a valid state for the lookup index
  r.F(0, 1) = 1e-3 * static_cast<double>(index);
  return r;
}

// The writer process: appends in small batches, each flushed and committed. After its first batch it
// says so on `ready` and waits for a byte on `go`, so the reader certainly reads while it writes.
[[noreturn]] void write_library(const std::filesystem::path& dir, const std::vector<std::int64_t>& paths, int ready,
                                int go) {
  int status = 0;
  try {
    Library library = Library::open(dir);
    ShardWriter writer(library, "writer");
    for (std::int64_t path : paths) {
      writer.start_path(path);
      for (int a = 0; a < kAppends; ++a) {
        std::vector<Record> batch;
        for (int k = 0; k < kBatch; ++k) batch.push_back(expected_record(path, a * kBatch + k));
        writer.append_records(path, batch);
        char byte = 0;
        if (path == paths.front() && a == 0 && (write(ready, &byte, 1) != 1 || read(go, &byte, 1) != 1))
          throw std::runtime_error("lost the reader");
      }
      writer.finish_path(path, PathStatus::done, 0.1);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "writer process: %s\n", e.what());
    status = 1;
  }
  _exit(status);
}

TEST(ConcurrentReader, ReadsWhileAnotherProcessAppends) {
  TempDir tmp;
  const std::filesystem::path dir = tmp.path() / "LIB";
  std::vector<std::int64_t> paths;
  {
    Library library = Library::create(dir, small_material());
    ShardWriter setup(library, "setup");
    const std::int64_t t = add_gas_template(library, setup);
    for (int p = 0; p < kPaths; ++p) paths.push_back(library.add_path(t, {{"p", p}}, library.material()));
  }
  int ready[2], go[2];
  ASSERT_EQ(pipe(ready), 0);
  ASSERT_EQ(pipe(go), 0);
  const pid_t writer = fork();
  ASSERT_GE(writer, 0);
  if (writer == 0) write_library(dir, paths, ready[1], go[0]);
  close(ready[1]);  // so a writer that dies before its first batch gives end-of-file, not a hang

  std::int64_t seen_records = 0;
  lookup::LookupIndex index(KeyScales{});
  const auto read_all = [&] {
    Library library = Library::open(dir);
    for (const PathRow& path : library.catalogue().paths()) {
      const std::vector<Record> records = library.records(path.id);  // committed rows only
      ASSERT_GE(static_cast<std::int64_t>(records.size()), path.record_count);
      ASSERT_EQ(records.size() % kBatch, 0u) << "a half-written append was visible";
      for (std::size_t k = 0; k < records.size(); ++k)
        ASSERT_EQ(records[k], expected_record(path.id, static_cast<std::int64_t>(k))) << "path " << path.id;
      seen_records += static_cast<std::int64_t>(records.size());
    }
    index.refresh(library);
  };
  // One read while the writer waits with its first batch committed, then reads while it writes.
  char byte = 0;
  const bool first_batch = read(ready[0], &byte, 1) == 1;
  if (first_batch) read_all();
  EXPECT_EQ(write(go[1], &byte, 1), 1);
  int waited = 0;
  while (waitpid(writer, &waited, WNOHANG) == 0) read_all();
  for (const int end : {ready[0], go[0], go[1]}) close(end);
  ASSERT_TRUE(WIFEXITED(waited));
  ASSERT_EQ(WEXITSTATUS(waited), 0) << "the writer failed (see its message above)";
  ASSERT_TRUE(first_batch);
  EXPECT_GE(seen_records, kBatch);

  Library library = Library::open(dir);
  index.refresh(library);
  EXPECT_EQ(index.size(), static_cast<std::size_t>(kPaths * kAppends * kBatch));
  for (std::int64_t path : paths) EXPECT_EQ(library.records(path).size(), static_cast<std::size_t>(kAppends * kBatch));
}

}  // namespace
}  // namespace grainbank::db::test
