#include "database/store/stale_writer.hpp"

#include "database/store/hdf5_handle.hpp"

namespace grainbank::db {

void clear_stale_writer_flags(Library& library) {
  for (const ShardRow& row : library.catalogue().shards()) {
    const std::filesystem::path file = library.shard_path(row);
    if (std::filesystem::exists(file)) h5::clear_stale_writer_state(file);
  }
}

}  // namespace grainbank::db
