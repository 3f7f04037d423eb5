#include "database/lookup/lookup_index.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "database/lookup/blend.hpp"
#include "database/lookup/key_block.hpp"
#include "database/lookup/state_key.hpp"
#include "database/store/library.hpp"

namespace grainbank::lookup {

// The index as queries see it: immutable blocks, shared between successive snapshots.
struct IndexSnapshot {
  std::vector<std::shared_ptr<const KeyBlock>> blocks;  // sizes non-increasing
  std::size_t size = 0;
};

namespace {

// Logarithmic method (Bentley-Saxe): a new block is merged with its predecessors while they are not
// more than twice its size, so block sizes roughly double from the newest to the oldest.
std::shared_ptr<const IndexSnapshot> with_block(const IndexSnapshot& old, std::vector<IndexedRecord> records) {
  auto next = std::make_shared<IndexSnapshot>(old);
  next->size += records.size();
  while (!next->blocks.empty() && next->blocks.back()->size() <= 2 * records.size()) {
    const auto& merged = next->blocks.back()->records();
    records.insert(records.end(), merged.begin(), merged.end());
    next->blocks.pop_back();
  }
  next->blocks.push_back(std::make_shared<const KeyBlock>(std::move(records)));
  return next;
}

IndexedRecord indexed_record(const db::Record& r, const RecordRef& origin, const db::KeyScales& scales) {
  const PolarDecomposition polar = polar_decomposition(r.F);
  const RecordResponse response{db::to_stress6(to_material_frame(db::from_stress6(r.stress), polar.R)), r.damage,
                                r.coordination, r.solid_fraction};
  return {state_key(polar, r.L, r.damage, scales), response, origin};
}

}  // namespace

LookupIndex::LookupIndex(const db::KeyScales& scales) : scales_(scales), snapshot_(std::make_shared<const IndexSnapshot>()) {
  if (!(scales.strain > 0 && scales.rate > 0 && scales.damage > 0))
    throw std::invalid_argument("lookup index: key scales must be positive");
}

LookupIndex::~LookupIndex() = default;

std::size_t LookupIndex::size() const { return snapshot_.load()->size; }

void LookupIndex::insert(std::int64_t path_id, std::int64_t first_index, const std::vector<db::Record>& records) {
  if (records.empty()) return;
  std::vector<IndexedRecord> indexed;
  indexed.reserve(records.size());
  for (std::size_t i = 0; i < records.size(); ++i)
    indexed.push_back(indexed_record(records[i], {path_id, first_index + static_cast<std::int64_t>(i)}, scales_));
  const std::lock_guard lock(writer_);
  snapshot_.store(with_block(*snapshot_.load(), std::move(indexed)));
}

std::size_t LookupIndex::refresh(db::Library& library) {
  // One block for everything new: a bulk load builds a single kd-tree, not one per path.
  std::vector<IndexedRecord> indexed;
  std::vector<std::int64_t> paths;
  {
    const std::lock_guard lock(writer_);
    for (const db::PathRow& path : library.catalogue().paths()) {
      if (path.status != db::PathStatus::done || path.record_count == 0 || indexed_paths_.contains(path.id)) continue;
      const std::vector<db::Record> records = library.records(path.id);
      for (std::size_t i = 0; i < records.size(); ++i) indexed.push_back(indexed_record(records[i], {path.id, static_cast<std::int64_t>(i)}, scales_));
      paths.push_back(path.id);
    }
  }
  const std::size_t added = indexed.size();
  const std::lock_guard lock(writer_);
  if (added > 0) snapshot_.store(with_block(*snapshot_.load(), std::move(indexed)));
  indexed_paths_.insert(paths.begin(), paths.end());
  return added;
}

LookupAnswer LookupIndex::query(const LookupState& state, const LookupOptions& options) const {
  return answer(state, options, false);
}

LookupAnswer LookupIndex::query_brute_force(const LookupState& state, const LookupOptions& options) const {
  return answer(state, options, true);
}

LookupAnswer LookupIndex::answer(const LookupState& state, const LookupOptions& options, bool brute_force) const {
  if (options.k == 0) throw std::invalid_argument("lookup query: k must be at least 1");
  const PolarDecomposition polar = polar_decomposition(state.F);
  const db::StateKey key = state_key(polar, state.L, state.damage, scales_);
  const std::shared_ptr<const IndexSnapshot> snapshot = snapshot_.load();

  // Largest block first (blocks are kept in non-increasing size): its k-th best distance then
  // bounds the search of every smaller block, which is usually pruned at its root.
  std::vector<Candidate> candidates;
  std::size_t n = 0;
  if (brute_force) {
    candidates.reserve(options.k * (snapshot->blocks.size() + 1) + 64);
    for (const auto& block : snapshot->blocks) block->nearest_brute_force(key, options.k, candidates);
    n = std::min(options.k, candidates.size());
    std::partial_sort(candidates.begin(), candidates.begin() + static_cast<std::ptrdiff_t>(n), candidates.end(),
                      [](const Candidate& a, const Candidate& b) { return a.distance2 < b.distance2; });
  } else {
    candidates.resize(std::min(options.k, snapshot->size));
    NearestSet best(candidates.size(), candidates.data());
    if (!candidates.empty())
      for (const auto& block : snapshot->blocks) block->nearest(key, best);
    n = best.size();
  }

  LookupAnswer result;
  result.neighbours = n;
  if (n == 0) return result;
  result.distance = std::sqrt(candidates[0].distance2);
  result.hit = result.distance <= options.tolerance;
  result.nearest = candidates[0].block->record(candidates[0].row).origin;

  std::vector<Neighbour> neighbours;
  neighbours.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    const IndexedRecord& r = candidates[i].block->record(candidates[i].row);
    neighbours.push_back({&r.response, std::sqrt(candidates[i].distance2)});
  }
  const Blended blended = blend(neighbours);
  result.estimated_error = blended.estimated_error;
  result.damage = blended.response.damage;
  result.coordination = blended.response.coordination;
  result.solid_fraction = blended.response.solid_fraction;
  result.stress = to_lab_frame(db::from_stress6(blended.response.material_stress), polar.R);
  return result;
}

}  // namespace grainbank::lookup
