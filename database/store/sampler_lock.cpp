#include "database/store/sampler_lock.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <string>

#include "database/store/error.hpp"

namespace grainbank::db {

SamplerLock::SamplerLock(const std::filesystem::path& library_dir) {
  const std::filesystem::path file = library_dir / "sampler.lock";
  fd_ = ::open(file.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0) throw StoreError(file, std::string("cannot open the lock file: ") + std::strerror(errno));
  if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    char holder[256] = {};
    const ssize_t n = ::pread(fd_, holder, sizeof holder - 1, 0);
    ::close(fd_);
    throw StoreError(file, "another sampler (" + std::string(holder, n > 0 ? static_cast<std::size_t>(n) : 0) +
                               ") is writing to this library; wait for it to finish or stop it");
  }
  char host[200] = "unknown-host";
  gethostname(host, sizeof host - 1);
  const std::string holder = std::string(host) + ":" + std::to_string(getpid());
  if (::ftruncate(fd_, 0) != 0 || ::pwrite(fd_, holder.data(), holder.size(), 0) < 0) {
    // The holder's name only improves the message of a refused sampler: the lock itself is held.
  }
}

SamplerLock::~SamplerLock() {
  if (fd_ >= 0) ::close(fd_);  // closing releases the flock
}

}  // namespace grainbank::db
