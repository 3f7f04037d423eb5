// An immutable block of indexed records: their keys, material-frame stresses and origins, and a
// nanoflann kd-tree over the keys. Built once, then only read, so any number of threads may search
// it at the same time. Internal to lookup_index.cpp.
#pragma once
#include <cstdint>
#include <memory>
#include <vector>

#include <nanoflann.hpp>

#include "lookup_types.hpp"
#include "store/record.hpp"

namespace grainbank::lookup {

struct IndexedRecord {
  db::StateKey key;
  db::Stress6 material_stress;  // Rᵀ σ R of the record, tension-positive [Pa]
  RecordRef origin;
};

class KeyBlock;
// One candidate neighbour: squared key distance and where it lives.
struct Candidate {
  double distance2;
  const KeyBlock* block;
  std::uint32_t row;
};

class KeyBlock {
 public:
  explicit KeyBlock(std::vector<IndexedRecord> records);
  KeyBlock(const KeyBlock&) = delete;
  KeyBlock& operator=(const KeyBlock&) = delete;

  std::size_t size() const { return records_.size(); }
  const IndexedRecord& record(std::uint32_t row) const { return records_[row]; }
  const std::vector<IndexedRecord>& records() const { return records_; }

  // Appends the k nearest of this block to `out` (fewer when the block is smaller).
  void nearest(const db::StateKey& key, std::size_t k, std::vector<Candidate>& out) const;
  // The same by scanning every record (reference for tests and the benchmark).
  void nearest_brute_force(const db::StateKey& key, std::size_t k, std::vector<Candidate>& out) const;

  // nanoflann dataset interface.
  std::size_t kdtree_get_point_count() const { return records_.size(); }
  double kdtree_get_pt(std::size_t row, std::size_t dim) const { return records_[row].key[dim]; }
  template <class Box>
  bool kdtree_get_bbox(Box&) const {
    return false;
  }

 private:
  using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, KeyBlock>, KeyBlock,
                                                   static_cast<int>(db::kKeySize), std::uint32_t>;
  std::vector<IndexedRecord> records_;
  std::unique_ptr<Tree> tree_;  // refers to records_: built after them, never moved
};

}  // namespace grainbank::lookup
