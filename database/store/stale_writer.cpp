#include "stale_writer.hpp"

#include <hdf5.h>

namespace grainbank::db {

void clear_stale_writer_flags(Library& library) {
  for (const ShardRow& row : library.catalogue().shards()) {
    const std::filesystem::path file = library.shard_path(row);
    if (!std::filesystem::exists(file)) continue;
    const hid_t fapl = H5Pcreate(H5P_FILE_ACCESS);
    H5Pset_libver_bounds(fapl, H5F_LIBVER_LATEST, H5F_LIBVER_LATEST);
    hbool_t clear = true;  // the private property h5clear uses
    H5Pset(fapl, "clear_status_flags", &clear);
    hid_t id = -1;
    H5E_BEGIN_TRY { id = H5Fopen(file.c_str(), H5F_ACC_RDWR, fapl); }
    H5E_END_TRY;
    H5Pclose(fapl);
    if (id < 0) throw StoreError(file, "cannot open the shard to clear a killed writer's flag (damaged? run celldb verify)");
    H5Fclose(id);  // writes the superblock back with the flags cleared
  }
}

}  // namespace grainbank::db
