#include "database/lookup/key_block.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>

namespace grainbank::lookup {

namespace {

int leaf_size() {
  // Tuning hook for the benchmark (GRAINBANK_KD_LEAF); the default was measured best for 7-D, k = 4.
  static const int size = [] {
    const char* text = std::getenv("GRAINBANK_KD_LEAF");
    const int value = text ? std::atoi(text) : 0;
    return value > 0 ? value : KeyBlock::kLeafSize;
  }();
  return size;
}

}  // namespace

KeyBlock::KeyBlock(std::vector<IndexedRecord> records) : records_(std::move(records)) {
  if (records_.empty()) return;
  keys_.resize(records_.size() * db::kKeySize);
  for (std::size_t i = 0; i < records_.size(); ++i)
    std::copy(records_[i].key.begin(), records_[i].key.end(), keys_.begin() + static_cast<std::ptrdiff_t>(i * db::kKeySize));
  const Tree tree(static_cast<int>(db::kKeySize), *this, nanoflann::KDTreeSingleIndexAdaptorParams(leaf_size()));
  // Permute records and keys into leaf order.
  const std::vector<std::uint32_t>& order = tree.vAcc;
  std::vector<IndexedRecord> sorted_records;
  std::vector<double> sorted_keys(keys_.size());
  sorted_records.reserve(records_.size());
  for (std::size_t i = 0; i < order.size(); ++i) {
    sorted_records.push_back(records_[order[i]]);
    std::copy_n(keys_.begin() + static_cast<std::ptrdiff_t>(order[i] * db::kKeySize), db::kKeySize,
                sorted_keys.begin() + static_cast<std::ptrdiff_t>(i * db::kKeySize));
  }
  records_ = std::move(sorted_records);
  keys_ = std::move(sorted_keys);
  nodes_.reserve(2 * (records_.size() / static_cast<std::size_t>(leaf_size()) + 1));
  flatten(tree.root_node);
}

std::uint32_t KeyBlock::flatten(const Tree::Node* node) {
  const auto index = static_cast<std::uint32_t>(nodes_.size());
  nodes_.emplace_back();
  if (node->child1 == nullptr && node->child2 == nullptr) {
    Node& leaf = nodes_[index];
    leaf.first = static_cast<std::uint32_t>(node->node_type.lr.left);
    leaf.last = static_cast<std::uint32_t>(node->node_type.lr.right);
    leaf.second_child = 0;
    for (std::size_t c = 0; c < db::kKeySize; ++c) {
      double low = std::numeric_limits<double>::infinity(), high = -low;
      for (std::uint32_t row = leaf.first; row < leaf.last; ++row) {
        low = std::min(low, keys_[row * db::kKeySize + c]);
        high = std::max(high, keys_[row * db::kKeySize + c]);
      }
      leaf.low[c] = low;
      leaf.high[c] = high;
    }
    return index;
  }
  const std::uint32_t first = flatten(node->child1);
  const std::uint32_t second = flatten(node->child2);
  Node& inner = nodes_[index];  // after the children: emplace_back may have moved it
  inner.second_child = second;
  inner.first = nodes_[first].first;
  inner.last = nodes_[second].last;
  for (std::size_t c = 0; c < db::kKeySize; ++c) {
    inner.low[c] = std::min(nodes_[first].low[c], nodes_[second].low[c]);
    inner.high[c] = std::max(nodes_[first].high[c], nodes_[second].high[c]);
  }
  return index;
}

double KeyBlock::box_distance2(const Node& node, const double* key) const {
  double d2 = 0;
  for (std::size_t c = 0; c < db::kKeySize; ++c) {
    const double below = node.low[c] - key[c], above = key[c] - node.high[c];
    const double gap = below > 0 ? below : (above > 0 ? above : 0.0);
    d2 += gap * gap;
  }
  return d2;
}

void KeyBlock::search(std::uint32_t index, const double* key, NearestSet& best) const {
  const Node& node = nodes_[index];
  if (node.second_child == 0) {
    const double* p = keys_.data() + static_cast<std::size_t>(node.first) * db::kKeySize;
    for (std::uint32_t row = node.first; row < node.last; ++row, p += db::kKeySize) {
      double d2 = 0;
      for (std::size_t c = 0; c < db::kKeySize; ++c) {
        const double diff = key[c] - p[c];
        d2 += diff * diff;
      }
      if (d2 < best.worstDist()) best.addPoint(d2, row);
    }
    return;
  }
  std::uint32_t near = index + 1, far = node.second_child;
  double near_d2 = box_distance2(nodes_[near], key), far_d2 = box_distance2(nodes_[far], key);
  if (far_d2 < near_d2) {
    std::swap(near, far);
    std::swap(near_d2, far_d2);
  }
  if (near_d2 < best.worstDist()) search(near, key, best);
  if (far_d2 < best.worstDist()) search(far, key, best);
}

void KeyBlock::nearest(const db::StateKey& key, NearestSet& best) const {
  if (nodes_.empty() || !(box_distance2(nodes_[0], key.data()) < best.worstDist())) return;
  best.set_block(this);
  search(0, key.data(), best);
}

void KeyBlock::nearest(const db::StateKey& key, std::size_t k, std::vector<Candidate>& out) const {
  std::vector<Candidate> storage(std::max<std::size_t>(k, 1));
  NearestSet best(k, storage.data());
  if (k > 0) nearest(key, best);
  out.insert(out.end(), best.begin(), best.end());
}

void KeyBlock::nearest_brute_force(const db::StateKey& key, std::size_t k, std::vector<Candidate>& out) const {
  const std::size_t first = out.size();
  double worst = std::numeric_limits<double>::infinity();  // k-th best so far, once k are kept
  const double* p = keys_.data();
  for (std::uint32_t row = 0; row < records_.size(); ++row, p += db::kKeySize) {
    double d2 = 0;
    for (std::size_t c = 0; c < db::kKeySize; ++c) {
      const double diff = key[c] - p[c];
      d2 += diff * diff;
    }
    if (d2 > worst) continue;
    out.push_back({d2, this, row});
    // Keep the scan's memory bounded: trim to the k best whenever the buffer doubles.
    if (out.size() - first >= 2 * k + 64) {
      std::nth_element(out.begin() + first, out.begin() + first + k, out.end(),
                       [](const Candidate& a, const Candidate& b) { return a.distance2 < b.distance2; });
      out.resize(first + k);
      worst = 0;
      for (std::size_t i = first; i < out.size(); ++i) worst = std::max(worst, out[i].distance2);
    }
  }
}

}  // namespace grainbank::lookup
