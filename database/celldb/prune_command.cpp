#include "database/celldb/prune_command.hpp"

#include "database/store/prune.hpp"

namespace grainbank::celldb {

int run_prune(const PruneOptions& options, std::ostream& out) {
  db::Library library = db::Library::open(options.library);
  const db::PruneReport r = db::prune_snapshots(library, options.keep_per_path, options.dry_run);
  out << (options.dry_run ? "would remove " : "removed ") << r.snapshots_removed << " of " << r.snapshots_before
      << " snapshots (at most " << options.keep_per_path << " per path) from " << r.shards_rewritten.size()
      << " shard(s); shard bytes " << r.bytes_before << " -> " << r.bytes_after << "\n";
  return 0;
}

}  // namespace grainbank::celldb
