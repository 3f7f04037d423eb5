// `celldb merge LIB SHARD_OR_LIB...`: adds the done paths of other libraries (or of single shards
// of them) to LIB; see store/merge.hpp for what is merged and what is refused.
#pragma once
#include <filesystem>
#include <ostream>
#include <vector>

namespace grainbank::celldb {

struct MergeOptions {
  std::filesystem::path library;
  std::vector<std::filesystem::path> sources;
};

// Merges the sources in order; the first refused source stops the command (earlier ones stay merged).
int run_merge(const MergeOptions& options, std::ostream& out);

}  // namespace grainbank::celldb
