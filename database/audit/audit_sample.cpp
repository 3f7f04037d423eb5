#include "database/audit/audit_sample.hpp"

#include <algorithm>
#include <random>

namespace grainbank::audit {
namespace {

// The first `count` elements of `items` become a uniform random choice of them (partial Fisher-Yates).
template <class T>
void choose_front(std::vector<T>& items, std::size_t count, std::mt19937_64& rng) {
  count = std::min(count, items.size());
  for (std::size_t i = 0; i < count; ++i) std::swap(items[i], items[i + rng() % (items.size() - i)]);
  items.resize(count);
  std::sort(items.begin(), items.end());
}

}  // namespace

AuditSample draw_sample(const std::vector<db::PathRow>& paths, const SampleSpec& spec) {
  std::mt19937_64 rng(spec.seed);
  AuditSample sample;
  for (const db::PathRow& p : paths)
    if (p.status == db::PathStatus::done && p.record_count >= 2) sample.paths.push_back(p.id);
  std::sort(sample.paths.begin(), sample.paths.end());
  choose_front(sample.paths, spec.paths, rng);

  std::vector<std::pair<std::int64_t, std::int64_t>> pool;
  for (const db::PathRow& p : paths)
    if (std::binary_search(sample.paths.begin(), sample.paths.end(), p.id))
      for (std::int64_t r = 1; r < p.record_count; ++r) pool.emplace_back(p.id, r);
  std::sort(pool.begin(), pool.end());
  choose_front(pool, spec.records, rng);
  for (const auto& [path, record] : pool) sample.records.push_back({path, record});
  return sample;
}

}  // namespace grainbank::audit
