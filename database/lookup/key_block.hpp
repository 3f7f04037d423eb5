// An immutable block of indexed records: their keys, material-frame stresses and origins, and a
// nanoflann kd-tree over the keys. Built once, then only read, so any number of threads may search
// it at the same time. Internal to lookup_index.cpp.
//
// Layout and search, for speed (DESIGN.md: 7-D key, k = 4, 10^6 records):
// - nanoflann builds the tree (its sliding-midpoint splits); then records and keys are permuted into
//   the tree's leaf order, so a leaf's keys are contiguous (7 doubles each, apart from the stresses
//   and origins), and the tree is flattened into an array of nodes in depth-first order.
// - Each flattened node keeps the tight bounding box of the keys below it (nanoflann only bounds a
//   node by its ancestors' cuts). Library keys lie along strain-rate paths (1-D curves in 7-D), so
//   tight boxes are far smaller than the cut cells and prune most of the tree.
// - The search is exact: a node is skipped only when its box is not closer than the current k-th
//   best distance (box distance <= distance of every key inside, also in floating point).
#pragma once
#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

#include <nanoflann.hpp>

#include "database/lookup/lookup_types.hpp"
#include "database/store/record.hpp"

namespace grainbank::lookup {

struct IndexedRecord {
  db::StateKey key;
  RecordResponse response;  // material-frame stress and the cell measures
  RecordRef origin;
};

class KeyBlock;
// One candidate neighbour: squared key distance and where it lives.
struct Candidate {
  double distance2;
  const KeyBlock* block;
  std::uint32_t row;
};

// The k best candidates over several blocks, kept sorted by distance (a nanoflann result set).
// Searching block after block with the same set carries the current k-th best distance into the
// next search as its radius: a later (smaller) block is pruned at its root unless it holds a closer
// record. Exact: a record is only skipped when it cannot be closer than the current k-th best.
class NearestSet {
 public:
  using DistanceType = double;
  using IndexType = std::uint32_t;
  using CountType = std::size_t;

  // Uses `storage` (at least k elements) for the candidates.
  NearestSet(std::size_t k, Candidate* storage) : items_(storage), capacity_(k) {}

  void set_block(const KeyBlock* block) { block_ = block; }
  std::size_t size() const { return count_; }
  const Candidate* begin() const { return items_; }
  const Candidate* end() const { return items_ + count_; }

  // nanoflann result-set interface.
  bool full() const { return count_ == capacity_; }
  double worstDist() const { return count_ == capacity_ ? items_[capacity_ - 1].distance2 : std::numeric_limits<double>::max(); }
  bool addPoint(double distance2, std::uint32_t row) {
    std::size_t i;
    if (count_ < capacity_) {
      i = count_++;
    } else {
      if (!(distance2 < items_[capacity_ - 1].distance2)) return true;
      i = capacity_ - 1;
    }
    while (i > 0 && items_[i - 1].distance2 > distance2) {
      items_[i] = items_[i - 1];
      --i;
    }
    items_[i] = {distance2, block_, row};
    return true;
  }

 private:
  Candidate* items_;
  std::size_t capacity_;
  std::size_t count_ = 0;
  const KeyBlock* block_ = nullptr;
};

class KeyBlock {
 public:
  explicit KeyBlock(std::vector<IndexedRecord> records);
  KeyBlock(const KeyBlock&) = delete;
  KeyBlock& operator=(const KeyBlock&) = delete;

  std::size_t size() const { return records_.size(); }
  // Rows are in the block's own (tree) order, not in insertion order.
  const IndexedRecord& record(std::uint32_t row) const { return records_[row]; }
  const std::vector<IndexedRecord>& records() const { return records_; }

  // Offers this block's records to `best` (the exact k nearest of everything offered so far).
  void nearest(const db::StateKey& key, NearestSet& best) const;
  // Appends the k nearest of this block to `out` (fewer when the block is smaller).
  void nearest(const db::StateKey& key, std::size_t k, std::vector<Candidate>& out) const;
  // The same by scanning every key (reference for tests and the benchmark).
  void nearest_brute_force(const db::StateKey& key, std::size_t k, std::vector<Candidate>& out) const;

  // nanoflann dataset interface (used while building).
  std::size_t kdtree_get_point_count() const { return records_.size(); }
  double kdtree_get_pt(std::size_t row, std::size_t dim) const { return keys_[row * db::kKeySize + dim]; }
  template <class Box>
  bool kdtree_get_bbox(Box&) const {
    return false;
  }

  // Keys per kd-tree leaf (at most); measured best for 7-D path-like keys, k = 4 (celldb bench).
  static constexpr int kLeafSize = 32;

 private:
  using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, KeyBlock>, KeyBlock,
                                                   static_cast<int>(db::kKeySize), std::uint32_t>;
  struct Node {
    std::array<double, db::kKeySize> low, high;  // tight bounding box of the keys below
    std::uint32_t first, last;                     // rows [first, last) below this node
    std::uint32_t second_child;                    // 0 for a leaf; the first child is the next node
  };
  std::uint32_t flatten(const Tree::Node* node);
  double box_distance2(const Node& node, const double* key) const;
  void search(std::uint32_t node, const double* key, NearestSet& best) const;

  std::vector<IndexedRecord> records_;
  std::vector<double> keys_;  // records_[i].key at [7 i, 7 i + 7), contiguous
  std::vector<Node> nodes_;   // nodes_[0] is the root (empty for an empty block)
};

}  // namespace grainbank::lookup
