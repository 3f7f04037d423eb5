// Damage done to a library from outside (bit rot, a bad copy): `celldb verify` names exactly what is
// damaged — the shard file and the records table of the one path whose chunk was hit, or the
// catalogue — and leaves everything else readable and equal to what was committed. `--repair`
// removes orphans only: it never changes or hides damaged committed data (it still reports it).
// An orphan HDF5 cannot unlink (its own header damaged, as a kill in mid-write leaves it) is removed
// by rewriting the shard without it.
#include <gtest/gtest.h>

#include <hdf5.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <iterator>
#include <map>
#include <set>

#include "database/store/path_queue.hpp"
#include "tests/faults/library_fault_util.hpp"

namespace grainbank::faults {
namespace {

// Overwrites the 8 bytes of `value` in `file` (it must occur exactly once) with garbage.
void corrupt_double(const fs::path& file, double value) {
  std::string bytes = sampler::test::slurp(file);
  char pattern[sizeof value];
  std::memcpy(pattern, &value, sizeof value);
  const std::size_t at = bytes.find(std::string_view(pattern, sizeof value));
  ASSERT_NE(at, std::string::npos);
  ASSERT_EQ(bytes.find(std::string_view(pattern, sizeof value), at + 1), std::string::npos);
  std::fstream f(file, std::ios::in | std::ios::out | std::ios::binary);
  f.seekp(static_cast<std::streamoff>(at));
  f.write("\xde\xad\xbe\xef\xde\xad\xbe\xef", 8);
}

TEST_F(LibraryFaults, CorruptedRecordChunkIsReportedPreciselyAndNothingElse) {
  const fs::path lib = fresh_library("lib", true);
  const fs::path shard = lib / "shards" / "rank0.h5";
  corrupt_double(shard, reference_->at(2)[5].stress[0]);

  for (const bool repair : {false, true}) {
    const Verification v = celldb_verify(lib, repair, here_.path());
    EXPECT_EQ(v.exit_code, 1);
    ASSERT_EQ(v.report["findings"].size(), 1u) << v.report.dump(1);
    const auto& f = v.report["findings"][0];
    EXPECT_EQ(f["kind"], "inconsistency");
    EXPECT_EQ(f["file"], shard.string());
    EXPECT_EQ(f["object"], "/paths/2/records");
    EXPECT_NE(f["message"].get<std::string>().find("checksum"), std::string::npos) << f.dump();
    EXPECT_FALSE(f["repaired"].get<bool>());
    EXPECT_EQ(v.report["checked"]["paths"], 3);
  }
  // The other paths, the template and the snapshots read back exactly as committed.
  db::Library opened = db::Library::open(lib);
  for (const std::int64_t id : {1, 3}) EXPECT_EQ(opened.records(id), reference_->at(id)) << "path " << id;
  EXPECT_NO_THROW(opened.template_cell(1));
}

// A template's arrays carry a checksum (since stop 59): one flipped byte of its sphere positions is
// reported by verify, naming the file and the template, and the template is refused on reading
// instead of starting paths from another packing. Before, verify called such a library clean.
TEST_F(LibraryFaults, AFlippedByteOfATemplateIsReportedAndRefused) {
  const fs::path lib = fresh_library("lib", true);
  const fs::path shard = lib / "shards" / "templates.h5";
  std::string object;
  haddr_t start = HADDR_UNDEF;
  {
    const hid_t file = H5Fopen(shard.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    ASSERT_GE(file, 0);
    char token[64] = {};
    ASSERT_GE(H5Lget_name_by_idx(file, "/templates", H5_INDEX_NAME, H5_ITER_INC, 0, token, sizeof token,
                                 H5P_DEFAULT),
              0);
    object = std::string("/templates/") + token;
    const hid_t positions = H5Dopen2(file, (object + "/reduced_position").c_str(), H5P_DEFAULT);
    ASSERT_GE(positions, 0);
    const hsize_t first[2] = {0, 0};
    ASSERT_GE(H5Dget_chunk_info_by_coord(positions, first, nullptr, &start, nullptr), 0) << "a chunked, checked array";
    H5Dclose(positions);
    H5Fclose(file);
  }
  {
    std::fstream f(shard, std::ios::in | std::ios::out | std::ios::binary);
    f.seekg(static_cast<std::streamoff>(start + 21));
    char byte = 0;
    f.read(&byte, 1);
    byte = static_cast<char>(byte ^ 0xFF);
    f.seekp(static_cast<std::streamoff>(start + 21));
    f.write(&byte, 1);
  }
  const Verification v = celldb_verify(lib, false, here_.path());
  EXPECT_EQ(v.exit_code, 1);
  ASSERT_EQ(v.report["findings"].size(), 1u) << v.report.dump(1);
  const auto& finding = v.report["findings"][0];
  EXPECT_EQ(finding["file"], shard.string());
  EXPECT_NE(finding.dump().find(object), std::string::npos) << finding.dump();
  EXPECT_NE(finding["message"].get<std::string>().find("checksum"), std::string::npos) << finding.dump();
  db::Library opened = db::Library::open(lib);
  EXPECT_THROW(opened.template_cell(1), db::StoreError);
  for (const auto& [id, records] : *reference_) EXPECT_EQ(opened.records(id), records) << "path " << id;
}

TEST_F(LibraryFaults, CorruptedCataloguePageIsReportedNamingTheCatalogue) {
  const fs::path lib = fresh_library("lib", true);
  const fs::path catalogue = lib / "catalogue.sqlite";
  for (const char* suffix : {"-wal", "-shm"}) fs::remove(lib / (std::string("catalogue.sqlite") + suffix));
  {  // garbage over the second half of the file: table pages, not the header
    std::fstream f(catalogue, std::ios::in | std::ios::out | std::ios::binary);
    const auto size = fs::file_size(catalogue);
    f.seekp(static_cast<std::streamoff>(size / 2));
    f.write(std::string(size - size / 2, '\x5a').data(), static_cast<std::streamsize>(size - size / 2));
  }
  const Outcome o = sampler::test::run({CELLDB_BINARY, "verify", lib.string()}, here_.path());
  EXPECT_EQ(o.exit_code, 2) << "celldb's exit code for an error";
  EXPECT_NE((o.out + o.err).find(catalogue.string()), std::string::npos) << o.out << o.err;
  // Nothing is reported clean: either the catalogue cannot be read, or its check lists the damage.
  EXPECT_EQ(o.out.find("0 orphans, 0 inconsistencies"), std::string::npos) << o.out;
}

// Overwrites the signature of the object header of `object` in the HDF5 `file` (no handle open).
void corrupt_object_header(const fs::path& file, const std::string& object) {
  H5O_info_t info{};
  const hid_t id = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(id, 0);
  const herr_t got = H5Oget_info_by_name2(id, object.c_str(), &info, H5O_INFO_BASIC, H5P_DEFAULT);
  H5Fclose(id);
  ASSERT_GE(got, 0);
  std::fstream f(file, std::ios::in | std::ios::out | std::ios::binary);
  f.seekp(static_cast<std::streamoff>(info.addr));
  f.write("XXXX", 4);
}

// `lib` holds exactly one orphan, at `object`, that only a rewrite of its shard removes: verify finds
// it (exit 1), repair removes it (exit 0, marked repaired) leaving a clean library with every
// snapshot and committed record and no stray copy.
void expect_one_orphan_removed_by_rewrite(const fs::path& lib, const std::string& object, const fs::path& scratch,
                                          const std::map<std::int64_t, std::vector<db::Record>>& reference) {
  const Verification found = celldb_verify(lib, false, scratch);
  EXPECT_EQ(found.exit_code, 1);
  ASSERT_EQ(found.report["findings"].size(), 1u) << found.report.dump(1);
  EXPECT_EQ(found.report["findings"][0]["kind"], "orphan");
  EXPECT_EQ(found.report["findings"][0]["object"], object);

  const Verification repaired = celldb_verify(lib, true, scratch);
  EXPECT_EQ(repaired.exit_code, 0) << repaired.report.dump(1);
  EXPECT_TRUE(repaired.report["findings"][0]["repaired"].get<bool>()) << repaired.report.dump(1);
  const Verification after = celldb_verify(lib, false, scratch);
  EXPECT_TRUE(after.report["findings"].empty()) << after.report.dump(1);
  EXPECT_EQ(after.report["checked"]["snapshots"], found.report["checked"]["snapshots"]);
  EXPECT_FALSE(fs::exists(lib / "shards" / "rank0.repair.h5"));
  db::Library opened = db::Library::open(lib);
  for (const auto& [id, records] : reference) EXPECT_EQ(opened.records(id), records) << "path " << id;
  EXPECT_NO_THROW(opened.template_cell(1));
}

TEST_F(LibraryFaults, OrphanGroupWithDamagedHeaderIsRemovedByRewritingTheShard) {
  const fs::path lib = fresh_library("lib", true);
  const fs::path shard = lib / "shards" / "rank0.h5";
  std::int64_t pending = 0;
  {  // a registered path whose start a kill interrupted: its group linked, its header garbage
    db::Library opened = db::Library::open(lib);
    pending = opened.catalogue().insert_path(1, R"({"segments": []})", opened.parameter_hash());
    db::ShardWriter writer(opened, "rank0");
    writer.shard().create_path(pending);
    writer.shard().flush();
  }
  corrupt_object_header(shard, db::Shard::path_group(pending));

  {  // the writer cannot remove it in place: it names the repair and loses nothing
    db::Library opened = db::Library::open(lib);
    db::ShardWriter writer(opened, "rank0");
    try {
      writer.start_path(pending);
      ADD_FAILURE() << "a damaged leftover group was removed in place";
    } catch (const db::StoreError& e) {
      EXPECT_NE(std::string(e.what()).find("celldb verify " + lib.string() + " --repair"), std::string::npos) << e.what();
    }
  }
  expect_one_orphan_removed_by_rewrite(lib, db::Shard::path_group(pending), here_.path(), *reference_);
  db::Library opened = db::Library::open(lib);
  db::ShardWriter writer(opened, "rank0");
  EXPECT_NO_THROW(writer.start_path(pending));
}

// Offsets of HDF5 extensible-array headers ("EAHD", the chunk index of a records table) in `file`.
std::set<std::size_t> extensible_array_headers(const fs::path& file) {
  const std::string bytes = sampler::test::slurp(file);
  std::set<std::size_t> at;
  for (std::size_t k = bytes.find("EAHD"); k != std::string::npos; k = bytes.find("EAHD", k + 1)) at.insert(k);
  return at;
}

// Seen in a trial of SigkillAtRandomMomentsLosesNothingCommitted: a kill inside the flush that wrote
// a new path's first rows left the chunk index of its records table unreadable ("incorrect metadata
// checksum"), so HDF5 can neither shrink the table nor unlink it. Nothing in it was committed:
// repair rewrites the shard with the table cut to its committed rows, and the path can start again.
TEST_F(LibraryFaults, UncommittedRowsBehindADamagedChunkIndexAreRemovedByRewritingTheShard) {
  const fs::path lib = fresh_library("lib", true);
  const fs::path shard = lib / "shards" / "rank0.h5";
  std::int64_t interrupted = 0;
  const std::set<std::size_t> before = extensible_array_headers(shard);
  {  // a path whose first two rows were flushed, not committed
    db::Library opened = db::Library::open(lib);
    interrupted = opened.catalogue().insert_path(1, R"({"segments": []})", opened.parameter_hash());
    db::ShardWriter writer(opened, "rank0");
    writer.start_path(interrupted);
    writer.shard().append_records(interrupted, {reference_->at(1)[0], reference_->at(1)[1]});
    writer.shard().flush();
  }
  std::vector<std::size_t> added;
  std::ranges::set_difference(extensible_array_headers(shard), before, std::back_inserter(added));
  ASSERT_EQ(added.size(), 1u) << "the new table's chunk index";
  {
    std::fstream f(shard, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(static_cast<std::streamoff>(added[0] + 6));
    f.write("\xff\xff", 2);
  }
  const std::string table = db::Shard::path_group(interrupted) + "/records";

  expect_one_orphan_removed_by_rewrite(lib, table, here_.path(), *reference_);
  db::Library opened = db::Library::open(lib);
  EXPECT_TRUE(opened.records(interrupted).empty());
  db::reset_running_paths(opened.catalogue());
  db::ShardWriter writer(opened, "rank0");
  writer.start_path(interrupted);
  writer.append_records(interrupted, {reference_->at(1)[0]});
  EXPECT_EQ(writer.shard().record_rows(interrupted), 1u);
}

}  // namespace
}  // namespace grainbank::faults
