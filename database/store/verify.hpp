// Consistency of a library between its catalogue and its shards (`celldb verify`).
//  - orphan: HDF5 data no committed row refers to (a crash between the flush and the commit):
//    a template or snapshot group, a path group, records beyond a path's committed count, or a
//    shard file with no catalogue row. Harmless; repair removes it.
//  - inconsistency: a committed row whose data is missing, short or unreadable, or a damaged
//    catalogue. Never produced by a crash of a grainbank writer; repair does not touch it.
// Repair needs every writer of the library to be stopped (a shard open for writing elsewhere cannot
// be opened and is reported).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "database/store/library.hpp"

namespace grainbank::db {

struct Finding {
  enum class Kind { orphan, inconsistency };
  Kind kind = Kind::orphan;
  std::string file;    // shard or catalogue
  std::string object;  // HDF5 group / dataset, or table row
  std::string message;
  bool repaired = false;
};

struct VerifyReport {
  std::vector<Finding> findings;
  std::int64_t shards = 0, templates = 0, paths = 0, records = 0, snapshots = 0;  // committed, checked
  std::size_t orphans() const;
  std::size_t inconsistencies() const;
  // No inconsistency and no orphan left unrepaired.
  bool clean() const;
};

// Reads every committed object once (so checksums are verified) and lists every HDF5 object.
VerifyReport verify_library(Library& library, bool repair);

}  // namespace grainbank::db
