// Errors of the cell library. Every message starts with the file it concerns (catalogue, shard or
// library directory) and says what is wrong, so a user can act on it without a debugger.
#pragma once
#include <filesystem>
#include <stdexcept>
#include <string>

namespace grainbank::db {

class StoreError : public std::runtime_error {
 public:
  StoreError(const std::filesystem::path& file, const std::string& what)
      : std::runtime_error(file.string() + ": " + what), file_(file) {}
  const std::filesystem::path& file() const { return file_; }

 private:
  std::filesystem::path file_;
};

// The library was built for other physics (material parameters or effects): mixing its records with
// this material's would silently produce wrong stresses.
class MaterialMismatch : public StoreError {
 public:
  using StoreError::StoreError;
};

}  // namespace grainbank::db
