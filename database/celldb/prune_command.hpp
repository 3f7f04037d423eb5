// `celldb prune LIB --keep-per-path N [--dry-run]`: cuts the library's snapshots to N per path
// (store/prune.hpp) and prints what it removed and the shard bytes before and after.
#pragma once
#include <cstdint>
#include <filesystem>
#include <ostream>

namespace grainbank::celldb {

struct PruneOptions {
  std::filesystem::path library;
  std::int64_t keep_per_path = 0;
  bool dry_run = false;
};

int run_prune(const PruneOptions& options, std::ostream& out);

}  // namespace grainbank::celldb
