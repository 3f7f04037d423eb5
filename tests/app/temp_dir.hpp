// Loaders are tested on real files, in a temporary directory removed after the test.
#pragma once
#include "common/temporary_directory.hpp"

namespace grainbank::testing {
using TempDir = grainbank::TemporaryDirectory;
}  // namespace grainbank::testing
