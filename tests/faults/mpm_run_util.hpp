// What the tests of whole `mpm_solver` runs share (interrupts, MPI ranks): the points of a restart
// file as written, and a snapshot file that holds the run inside its write until the test lets go.
#pragma once
#include <fcntl.h>
#include <gtest/gtest.h>
#include <poll.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <vector>

#include "database/store/hdf5_handle.hpp"
#include "mpm_solver/io/restart.hpp"

namespace grainbank::faults {

struct RestartContents {
  double time = 0;
  std::int64_t steps = 0;
  std::vector<double> points;  // one row of mpm::io::kRestartPointColumns per point (io/restart.cpp)
};

inline RestartContents read_restart_file(const std::filesystem::path& file) {
  const db::h5::Object root = db::h5::open_file(file, false);
  return {db::h5::read_double_attribute(root, "time"), db::h5::read_int_attribute(root, "steps"),
          db::h5::read_array<double>(root, "points", mpm::io::kRestartPointColumns)};
}

// A snapshot file made a FIFO whose pipe holds less than a snapshot: the run that reaches it waits
// inside the write until the test drains the pipe (or kills the run).
class BlockingSnapshot {
 public:
  explicit BlockingSnapshot(const std::filesystem::path& file) {
    std::filesystem::create_directories(file.parent_path());
    EXPECT_EQ(mkfifo(file.c_str(), 0644), 0);
    fifo_ = open(file.c_str(), O_RDONLY | O_NONBLOCK);
    EXPECT_GE(fifo_, 0);
    capacity_ = fcntl(fifo_, F_SETPIPE_SZ, 4096);
    EXPECT_GT(capacity_, 0);
  }
  ~BlockingSnapshot() { close(fifo_); }
  // Waits until the child writes into the snapshot (true) or ends first (false).
  bool wait_until_written(pid_t child) const {
    const int exited = static_cast<int>(syscall(SYS_pidfd_open, child, 0));  // readable once the run ends
    EXPECT_GE(exited, 0);
    pollfd events[2] = {{fifo_, POLLIN, 0}, {exited, POLLIN, 0}};
    EXPECT_GT(poll(events, 2, -1), 0);
    close(exited);
    return events[0].revents & POLLIN;
  }
  // Reads the pipe to its end; returns the bytes read.
  std::size_t drain() const {
    fcntl(fifo_, F_SETFL, 0);
    std::size_t drained = 0;
    char buffer[1 << 16];
    for (ssize_t n; (n = read(fifo_, buffer, sizeof buffer)) > 0;) drained += static_cast<std::size_t>(n);
    return drained;
  }
  std::size_t capacity() const { return static_cast<std::size_t>(capacity_); }

 private:
  int fifo_ = -1;
  int capacity_ = 0;
};

}  // namespace grainbank::faults
