#include "database/celldb/merge_command.hpp"

#include "database/store/merge.hpp"

namespace grainbank::celldb {

int run_merge(const MergeOptions& options, std::ostream& out) {
  db::Library library = db::Library::open(options.library);
  for (const std::filesystem::path& source : options.sources) {
    const db::MergeReport r = db::merge_into(library, source);
    out << source.string() << ": " << r.paths << " paths (" << r.records << " records, " << r.snapshots
        << " snapshots), " << r.templates << " templates added from " << r.shards << " shards; " << r.already_merged
        << " paths already merged, " << r.skipped << " not done (skipped)\n";
  }
  return 0;
}

}  // namespace grainbank::celldb
