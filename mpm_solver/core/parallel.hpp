// When a pass over points or nodes is worth an OpenMP team: below this many items the fork/join and
// barrier costs exceed the work (and on a loaded machine spinning threads make it far worse).
#pragma once

namespace grainbank::mpm {

constexpr long kMinParallelItems = 4096;

}  // namespace grainbank::mpm
