// Nearest-state lookup over a cell library (DESIGN.md, "Nearest-state lookup"). What the MPM's
// `cache` and `hybrid` laws call.
//
// Promises:
// - query() answers from the k records nearest in key space (state_key.hpp; Euclidean distance,
//   kd-tree): their material-frame stresses and cell measures blended with weights 1/d² (blend.hpp;
//   a record at distance 0 answers alone, so a library state is answered exactly), the
//   stress turned into the query's frame with the query's own rotation, σ = R σ̂ Rᵀ.
//   hit = (nearest distance <= tolerance). The estimated error is the weighted RMS deviation of the
//   k stresses from the blend (Frobenius norm, Pa): 0 for an exact match, large where neighbours
//   disagree.
// - query(), query_brute_force() and size() may be called from any number of threads at
//   once, also while another thread inserts or refreshes: a query sees the index as it was when it
//   started (an immutable snapshot behind an atomic pointer) and never waits for a writer.
// - insert() and refresh() are serialised among themselves. Inserted records become visible to
//   queries that start after the call returns. Cost: new records form a new kd-tree block; blocks
//   of similar size are merged (rebuilt), so a query searches O(log N) trees and each record is
//   rebuilt O(log N) times over the index's life. A query searches the largest block first and
//   carries its k-th best distance into the smaller blocks, which are then mostly pruned at their
//   root; within a block, nodes are pruned by the tight bounding box of their keys (key_block.hpp).
//   The search is exact (the same neighbours and distances as query_brute_force); measured with
//   `celldb bench`. The index keeps no counts: hits and misses are the callers' (each answer says).
#pragma once
#include <atomic>
#include <memory>
#include <mutex>
#include <set>
#include <vector>

#include "database/lookup/lookup_types.hpp"
#include "database/store/key_definition.hpp"
#include "database/store/record.hpp"

namespace grainbank::db {
class Library;
}

namespace grainbank::lookup {

struct IndexSnapshot;

class LookupIndex {
 public:
  explicit LookupIndex(const db::KeyScales& scales);
  ~LookupIndex();
  LookupIndex(const LookupIndex&) = delete;
  LookupIndex& operator=(const LookupIndex&) = delete;

  const db::KeyScales& scales() const { return scales_; }
  std::size_t size() const;

  // Indexes records [first_index, first_index + records.size()) of `path_id`; their keys and
  // material-frame stresses are computed from F, L, damage and σ with this index's scales.
  void insert(std::int64_t path_id, std::int64_t first_index, const std::vector<db::Record>& records);
  // Indexes the committed records of every `done` path of the library not indexed yet; returns how
  // many records were added. Call it again to pick up paths finished since (by other processes too).
  std::size_t refresh(db::Library& library);

  // Throws std::invalid_argument for options.k == 0 or a state whose F has det F <= 0.
  LookupAnswer query(const LookupState& state, const LookupOptions& options = {}) const;
  // The same answer from a scan of every record. For tests and benchmarks.
  LookupAnswer query_brute_force(const LookupState& state, const LookupOptions& options = {}) const;

 private:
  LookupAnswer answer(const LookupState& state, const LookupOptions& options, bool brute_force) const;

  db::KeyScales scales_;
  std::atomic<std::shared_ptr<const IndexSnapshot>> snapshot_;
  std::mutex writer_;                    // serialises insert/refresh
  std::set<std::int64_t> indexed_paths_;  // guarded by writer_
};

}  // namespace grainbank::lookup
