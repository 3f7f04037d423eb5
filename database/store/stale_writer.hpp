// After a writer was killed (SIGKILL, power loss), its shard still carries HDF5's "open for write"
// superblock flag, and HDF5 then refuses to open it for writing again. Whoever holds the library's
// sampler lock (sampler_lock.hpp) knows that no writer is alive and may clear the flags, as h5clear -s
// does; the data is untouched (committed rows were flushed before their commit). A writer stopped
// by a full disk may also leave its shard shorter than its superblock says: the file is extended
// back (h5::clear_stale_writer_state).
#pragma once
#include "database/store/library.hpp"

namespace grainbank::db {

// Clears the flag of every shard of the catalogue whose file exists. Throws StoreError naming a file
// that cannot be opened even so (then it is damaged: see celldb verify).
void clear_stale_writer_flags(Library& library);

}  // namespace grainbank::db
