#include "key_block.hpp"

#include <algorithm>

namespace grainbank::lookup {

KeyBlock::KeyBlock(std::vector<IndexedRecord> records) : records_(std::move(records)) {
  // Leaves of ~16 keys: measured faster than nanoflann's default 10 for 7-D keys and k = 4.
  tree_ = std::make_unique<Tree>(static_cast<int>(db::kKeySize), *this, nanoflann::KDTreeSingleIndexAdaptorParams(16));
}

void KeyBlock::nearest(const db::StateKey& key, std::size_t k, std::vector<Candidate>& out) const {
  const std::size_t n = std::min(k, records_.size());
  if (n == 0) return;
  std::uint32_t rows[64];
  double distances2[64];
  std::vector<std::uint32_t> many_rows;
  std::vector<double> many_distances2;
  std::uint32_t* r = rows;
  double* d = distances2;
  if (n > 64) {  // rare: large k
    many_rows.resize(n);
    many_distances2.resize(n);
    r = many_rows.data();
    d = many_distances2.data();
  }
  nanoflann::KNNResultSet<double, std::uint32_t> result(n);
  result.init(r, d);
  tree_->findNeighbors(result, key.data(), nanoflann::SearchParams());
  for (std::size_t i = 0; i < result.size(); ++i) out.push_back({d[i], this, r[i]});
}

void KeyBlock::nearest_brute_force(const db::StateKey& key, std::size_t k, std::vector<Candidate>& out) const {
  const std::size_t first = out.size();
  for (std::uint32_t row = 0; row < records_.size(); ++row) {
    double d2 = 0;
    for (std::size_t c = 0; c < db::kKeySize; ++c) {
      const double diff = records_[row].key[c] - key[c];
      d2 += diff * diff;
    }
    out.push_back({d2, this, row});
    // Keep the scan's memory bounded: trim to the k best whenever the buffer doubles.
    if (out.size() - first >= 2 * k + 64) {
      std::nth_element(out.begin() + first, out.begin() + first + k, out.end(),
                       [](const Candidate& a, const Candidate& b) { return a.distance2 < b.distance2; });
      out.resize(first + k);
    }
  }
}

}  // namespace grainbank::lookup
