// Shared helpers of the sampler tests: temporary directories, a small cohesive cell and path sets,
// the dem_sampler binary run as a child process, and reading a library's committed records.
#pragma once
#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "database/store/library.hpp"
#include "common/temporary_directory.hpp"

namespace grainbank::sampler::test {

using TempDir = grainbank::TemporaryDirectory;

// 64 spheres, soft contacts: a record interval of 2e-4 s is ~180 DEM steps.
inline const char* const kCell = R"({
  "material": {"density": 920, "k_n": 2000, "k_t": 600, "restitution": 0.3, "friction": 0.2,
               "bond": {"tensile_strength": 8e-4, "shear_strength": 9.6e-4, "bonding_distance": 0.05}},
  "effects": {"cohesion": true},
  "preparation": {"spheres": 64, "diameter": {"min": 3.4e-4, "max": 4.0e-4}, "pressure": 1000, "seed": 3,
                  "inertial_number": 0.01}
})";

// An explicit shear, a replay and four generated two-segment paths; snapshots every 10 records.
inline const char* const kPaths = R"({
  "record_interval": 2e-4, "snapshot_interval": 10,
  "paths": [{"segments": [{"L": [[0, 1], [0, 0]], "duration": 0.004}]},
            {"replay": [[[0.5, 0], [0, -0.5]], [[0.5, 0], [0, -0.5]], [[0, 1], [0, 0]]]}],
  "generators": [{"count": 4, "rate": {"min": 0.5, "max": 5}, "strain": 0.004, "segments": 2}]
})";

inline std::string slurp(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

struct Outcome {
  int exit_code = -1;
  std::string out, err;
};

// Starts `program args...` with stdout/stderr in files under `dir` and `environment` ("NAME=value")
// added to this process's; returns its pid.
inline pid_t spawn(const std::vector<std::string>& argv, const std::filesystem::path& dir,
                   const std::vector<std::string>& environment = {}) {
  std::vector<char*> args, env;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  for (char** e = environ; *e; ++e) env.push_back(*e);
  for (const std::string& e : environment) env.push_back(const_cast<char*>(e.c_str()));
  env.push_back(nullptr);
  const pid_t pid = fork();
  if (pid < 0) throw std::runtime_error("fork failed");
  if (pid == 0) {
    const int out = open((dir / "stdout.txt").c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int err = open((dir / "stderr.txt").c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    dup2(out, 1);
    dup2(err, 2);
    execve(args[0], args.data(), env.data());
    _exit(127);
  }
  return pid;
}

// Starts `dem_sampler sample ...` so that it stops itself once it holds the library's sampler lock and
// has committed `records` records (dem_sampler/app/test_stop_point.hpp), and waits for that stop. The
// caller then acts while the run is certainly unfinished, and sends SIGCONT or SIGKILL. Throws if
// the sampler ended instead of stopping (its stderr is in `dir`).
inline pid_t spawn_stopped_after(const std::vector<std::string>& argv, const std::filesystem::path& dir,
                                 long records) {
  const pid_t pid = spawn(argv, dir, {"GRAINBANK_TEST_STOP_AFTER_RECORDS=" + std::to_string(records)});
  int status = 0;
  if (waitpid(pid, &status, WUNTRACED) != pid || !WIFSTOPPED(status))
    throw std::runtime_error("the sampler ended before it stopped after " + std::to_string(records) +
                             " records; its stderr: " + slurp(dir / "stderr.txt"));
  return pid;
}

inline Outcome wait_for(pid_t pid, const std::filesystem::path& dir) {
  int status = 0;
  waitpid(pid, &status, 0);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(dir / "stdout.txt"), slurp(dir / "stderr.txt")};
}

inline Outcome run(const std::vector<std::string>& argv, const std::filesystem::path& dir) {
  return wait_for(spawn(argv, dir), dir);
}

inline std::vector<std::string> dem_sampler(std::vector<std::string> args) {
  args.insert(args.begin(), DEM_SAMPLER_BINARY);
  return args;
}

// Committed records of every path, by path id.
inline std::map<std::int64_t, std::vector<db::Record>> all_records(const std::filesystem::path& library) {
  db::Library lib = db::Library::open(library);
  std::map<std::int64_t, std::vector<db::Record>> out;
  for (const db::PathRow& row : lib.catalogue().paths()) out[row.id] = lib.records(row.id);
  return out;
}

inline std::vector<db::PathRow> path_rows(const std::filesystem::path& library) {
  return db::Library::open(library).catalogue().paths();
}

}  // namespace grainbank::sampler::test
