// Exclusive right to start writers on a library: LIB/sampler.lock, held with flock(2) for the life of
// the object, so the kernel releases it when the holder dies, even by SIGKILL. Whoever holds it knows
// that no other sampler job is running, so `running` paths it does not own are stale (path_queue.hpp)
// and shard names such as "rank0" are free to reuse. Not for network file systems without flock.
#pragma once
#include <filesystem>

namespace grainbank::db {

class SamplerLock {
 public:
  // Throws StoreError naming the lock file and the holder (host:pid) when another process holds it.
  explicit SamplerLock(const std::filesystem::path& library_dir);
  ~SamplerLock();
  SamplerLock(const SamplerLock&) = delete;
  SamplerLock& operator=(const SamplerLock&) = delete;

 private:
  int fd_ = -1;
};

}  // namespace grainbank::db
