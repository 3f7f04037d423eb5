// `celldb bench [--records N] [--k K] [--queries Q] [--brute-queries B] [--far-share S] [--uniform] [--json]`:
// builds a synthetic library in a temporary directory (N records along random constant-L
// plane-strain paths of 1000 records, or N uniformly random states with --uniform), then measures
// insert records/s, open time (catalogue, index build) and lookup µs per query with the kd-tree
// index against a brute-force scan of the same index, single thread. Queries: 1 - S near sampled
// paths (as an MPM asks), S anywhere in the sampled region, each class also timed on its own. Prints
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
  double far_share = 0.2;  // share of queries anywhere in the sampled region (0: none)
  bool uniform = false;
  bool json = false;
};

int run_bench(const BenchOptions& options, std::ostream& out);

}  // namespace grainbank::celldb
