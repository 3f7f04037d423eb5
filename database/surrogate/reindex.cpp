#include "database/surrogate/reindex.hpp"

#include <algorithm>
#include <iterator>
#include <numeric>
#include <optional>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "database/store/error.hpp"
#include "database/store/library.hpp"

namespace grainbank::surrogate {

PointState point_state(const db::Record& record) {
  return {db::from_stress6(record.stress), record.solid_fraction, record.coordination, record.damage};
}

std::vector<HeldSegment> held_segments(const std::string& spec) {
  std::vector<HeldSegment> held;
  const nlohmann::json document = nlohmann::json::parse(spec, nullptr, false);
  if (document.is_discarded() || !document.contains("segments")) return held;
  double begin = 0;
  for (const nlohmann::json& segment : document["segments"]) {
    const double end = begin + segment.value("duration", 0.0);
    if (segment.value("pressure", 0.0) > 0) held.push_back({begin, end});
    begin = end;
  }
  return held;
}

namespace {

// The held segment that interval k → k+1 of `records` lies in, or none. Record times are sums of
// time steps, so a segment's last record may lie past its end by rounding.
std::optional<std::size_t> held_segment_of(const std::vector<db::Record>& records, std::size_t k,
                                           const std::vector<HeldSegment>& held) {
  constexpr double kRounding = 1e-9;  // [s]
  for (std::size_t s = 0; s < held.size(); ++s)
    if (records[k].time >= held[s].begin - kRounding && records[k + 1].time <= held[s].end + kRounding) return s;
  return std::nullopt;
}

struct SpannedSample {
  Sample sample;
  std::size_t intervals = 0;  // how many recorded intervals its answer spans
};

// The samples of one stored path (its records in order), each spanning up to `span` ≥ 1 intervals.
std::vector<SpannedSample> spanned_samples(std::int64_t path_id, const std::vector<db::Record>& records,
                                           const FeatureConstants& constants, std::size_t span,
                                           const std::vector<HeldSegment>& held) {
  if (span < 1) throw std::invalid_argument("sample span: expected at least one interval");
  std::vector<SpannedSample> samples;
  for (std::size_t k = 0; k + 1 < records.size(); ++k) {
    const db::Record& before = records[k];
    // Record k+1 holds the L of interval k; the sample reaches on while the next intervals share it,
    // or share its pressure-controlled segment.
    const std::optional<std::size_t> segment = held_segment_of(records, k, held);
    std::size_t last = k + 1;
    bool one_L = true;
    while (last - k < span && last + 1 < records.size() && records[last + 1].time > records[last].time) {
      const bool same_L = records[last + 1].L == records[k + 1].L;
      if (!same_L && !(segment && held_segment_of(records, last, held) == segment)) break;
      one_L = one_L && same_L;
      ++last;
    }
    const db::Record& after = records[last];
    const double dt = after.time - before.time;
    dem::Mat3 L = after.L;
    if (!one_L) {
      L.setZero();
      for (std::size_t j = k + 1; j <= last; ++j) L += records[j].L * (records[j].time - records[j - 1].time);
      L /= dt;
    }
    if (!(dt > 0) || (L + L.transpose()).norm() == 0) continue;
    samples.push_back({make_sample(point_state(before), point_state(after), L, dt, constants,
                                   {path_id, static_cast<std::int64_t>(k)}),
                       last - k});
  }
  return samples;
}

// Of the samples whose keys are equal to the bit, the one whose answer spans the most intervals (the
// first of those), in library order.
std::vector<Sample> without_repeats(std::vector<SpannedSample> all) {
  // By key, the longest span first; stable, so library order among equals.
  std::vector<std::size_t> order(all.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    if (all[a].sample.features != all[b].sample.features) return all[a].sample.features < all[b].sample.features;
    return all[a].intervals > all[b].intervals;
  });
  std::vector<bool> kept(all.size(), false);
  for (std::size_t i = 0; i < order.size(); ++i)
    kept[order[i]] = i == 0 || all[order[i]].sample.features != all[order[i - 1]].sample.features;
  std::vector<Sample> samples;
  for (std::size_t i = 0; i < all.size(); ++i)
    if (kept[i]) samples.push_back(std::move(all[i].sample));
  return samples;
}

}  // namespace

FeatureConstants library_constants(db::Library& library, double pressure_floor) {
  if (!(pressure_floor > 0 && pressure_floor <= 1))
    throw std::invalid_argument("pressure_floor: expected a share of the preparation pressure in (0, 1]");
  const std::vector<db::TemplateRow> templates = library.catalogue().templates();
  if (templates.empty()) throw db::StoreError(library.directory(), "no template: the surrogate needs its pressure and grain size");
  double pressure = 0, diameter = 0;
  for (const db::TemplateRow& row : templates) {
    const dem::CellState cell = library.template_cell(row.id).state;
    pressure += -cell.last_stress.trace() / 3;
    double sum = 0;
    for (double r : cell.radius) sum += 2 * r;
    diameter += sum / static_cast<double>(cell.radius.size());
  }
  const double n = static_cast<double>(templates.size());
  // Divided by its reciprocal (1 / 0.1 is 10 exactly): the default floor is p_ref / 10 to the bit, as
  // before the floor was a setting, so runs on it are the same runs.
  FeatureConstants c{pressure / n, pressure / n / (1 / pressure_floor), diameter / n, library.material().density};
  check(c);
  return c;
}

Dataset reindex(db::Library& library, std::size_t span, double pressure_floor) {
  Dataset dataset{library_constants(library, pressure_floor), {}};
  std::vector<SpannedSample> all;
  for (const db::PathRow& path : library.catalogue().paths()) {
    if (path.status != db::PathStatus::done || path.record_count < 2) continue;
    std::vector<SpannedSample> samples =
        spanned_samples(path.id, library.records(path.id), dataset.constants, span, held_segments(path.spec));
    all.insert(all.end(), std::make_move_iterator(samples.begin()), std::make_move_iterator(samples.end()));
  }
  dataset.samples = without_repeats(std::move(all));
  return dataset;
}

}  // namespace grainbank::surrogate
