// `celldb bench [--records N] [--k K] [--queries Q] [--brute-queries B] [--uniform] [--json]`:
// builds a synthetic library in a temporary directory (N records along random constant-L
// plane-strain paths of 1000 records, or N uniformly random states with --uniform), then measures
// insert records/s, open time (catalogue, index build) and lookup µs per query with the kd-tree
// index against a brute-force scan of the same index, single thread. Prints
// `lookup us/query: X (brute force: Y)` next to the DESIGN.md baseline.
#pragma once
#include <cstddef>
#include <ostream>

namespace grainbank::celldb {

struct BenchOptions {
  std::size_t records = 1'000'000;
  std::size_t k = 4;
  std::size_t queries = 20'000;
  std::size_t brute_queries = 200;
  bool uniform = false;
  bool json = false;
};

int run_bench(const BenchOptions& options, std::ostream& out);

}  // namespace grainbank::celldb
