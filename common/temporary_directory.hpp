// A fresh directory under the system temporary directory, removed with its contents when the object
// goes away: benchmarks and tests work on real files, as users do.
#pragma once
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

namespace grainbank {

class TemporaryDirectory {
 public:
  explicit TemporaryDirectory(const std::string& prefix = "grainbank") {
    std::string pattern = (std::filesystem::temp_directory_path() / (prefix + "-XXXXXX")).string();
    if (!mkdtemp(pattern.data())) throw std::runtime_error("cannot create a temporary directory for " + prefix);
    path_ = pattern;
  }
  ~TemporaryDirectory() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  TemporaryDirectory(const TemporaryDirectory&) = delete;
  TemporaryDirectory& operator=(const TemporaryDirectory&) = delete;

  const std::filesystem::path& path() const { return path_; }

  // Writes `text` to a file of this directory and returns its path.
  std::filesystem::path write(const std::string& name, const std::string& text) const {
    const std::filesystem::path file = path_ / name;
    // Replaced rather than truncated: ext4 flushes a truncated file to disk when it is closed
    // (auto_da_alloc), which costs milliseconds per write in tests that rewrite a file thousands of times.
    std::filesystem::remove(file);
    std::ofstream(file) << text;
    return file;
  }

 private:
  std::filesystem::path path_;
};

}  // namespace grainbank
