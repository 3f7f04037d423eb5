// `celldb verify LIB [--repair]`: finds orphans and inconsistencies (store/verify.hpp) and removes
// the orphans on request. Exit code 0 when the library is clean afterwards, 1 otherwise.
#pragma once
#include <filesystem>
#include <ostream>

namespace grainbank::celldb {

struct VerifyOptions {
  std::filesystem::path library;
  bool repair = false;
  bool json = false;
};

int run_verify(const VerifyOptions& options, std::ostream& out);

}  // namespace grainbank::celldb
