#include "database/audit/replay_check.hpp"

#include <algorithm>
#include <optional>

#include "dem_sampler/driver/path_driver.hpp"
#include "dem_sampler/sampler/path_plan.hpp"
#include "dem_sampler/sampler/stored_path.hpp"

namespace grainbank::audit {
namespace {

// Thrown from the record callback once the last record of a replay is reached: the rest of the path
// is not needed.
struct Reached {};

// The last snapshot strictly before `record` (its state is the cell right after that record), 0 if none.
std::int64_t start_of(const std::vector<std::int64_t>& snapshots, std::int64_t record) {
  const auto it = std::lower_bound(snapshots.begin(), snapshots.end(), record);
  return it == snapshots.begin() ? 0 : *std::prev(it);
}

// Replays checks[first, last) (one path, one start) in one drive.
// `records`: the path's stored records (a pressure servo resumes from the L of the start's).
void replay_group(db::Library& library, const db::PathRow& row, const sampler::PathPlan& plan,
                  const std::vector<db::Record>& records, std::vector<ReplayCheck>::iterator first,
                  std::vector<ReplayCheck>::iterator last) {
  const std::int64_t start = first->from_record;
  const std::int64_t end = std::prev(last)->record.record_index;
  auto next = first;  // the first check not replayed yet
  try {
    dem::DemCell cell =
        library.restore(start > 0 ? library.snapshot_cell(row.id, start) : library.template_cell(row.template_id));
    app::drive_along_path(
        cell, plan.path,
        [&](const app::PathRecord& r) {
          if (r.index == next->record.record_index) (next++)->replayed = db::to_stress6(r.stress);
          if (r.index >= end) throw Reached{};
        },
        static_cast<long>(start), records.at(static_cast<std::size_t>(start)).L);
    for (auto it = next; it != last; ++it) it->error = "the path's spec ends before this record";
  } catch (const Reached&) {
  } catch (const std::exception& e) {
    for (auto it = next; it != last; ++it)
      it->error = "replay from record " + std::to_string(start) + " failed: " + e.what();
  }
}

}  // namespace

std::vector<ReplayCheck> replay_records(db::Library& library, const std::vector<lookup::RecordRef>& records,
                                        const std::map<std::int64_t, std::vector<db::Record>>& stored) {
  std::vector<ReplayCheck> checks;
  for (const lookup::RecordRef& ref : records) {
    ReplayCheck check;
    check.record = ref;
    check.stored = stored.at(ref.path_id).at(static_cast<std::size_t>(ref.record_index)).stress;
    checks.push_back(check);
  }
  std::sort(checks.begin(), checks.end(), [](const ReplayCheck& a, const ReplayCheck& b) {
    return std::pair(a.record.path_id, a.record.record_index) < std::pair(b.record.path_id, b.record.record_index);
  });
  for (auto first = checks.begin(); first != checks.end();) {
    const std::int64_t path_id = first->record.path_id;
    const db::PathRow row = library.catalogue().path(path_id);
    const auto path_end =
        std::find_if(first, checks.end(), [&](const ReplayCheck& c) { return c.record.path_id != path_id; });
    const auto fail_all = [&](const std::string& error, bool replayable) {
      for (auto it = first; it != path_end; ++it) {
        it->error = error;
        it->replayable = replayable;
      }
      first = path_end;
    };
    std::optional<sampler::PathPlan> plan;
    try {
      plan = sampler::stored_plan(library, row);
    } catch (const std::exception& e) {
      fail_all(e.what(), true);
      continue;
    }
    if (!plan) {
      fail_all("not replayable: the path's spec is not a sampler path (a live cell of an MPM run)", false);
      continue;
    }
    std::vector<std::int64_t> snapshots;
    for (const db::SnapshotRow& s : library.catalogue().snapshots_of(path_id)) snapshots.push_back(s.record_index);
    std::sort(snapshots.begin(), snapshots.end());
    for (auto it = first; it != path_end; ++it) it->from_record = start_of(snapshots, it->record.record_index);
    while (first != path_end) {
      const auto group_end =
          std::find_if(first, path_end, [&](const ReplayCheck& c) { return c.from_record != first->from_record; });
      replay_group(library, row, *plan, stored.at(path_id), first, group_end);
      first = group_end;
    }
  }
  return checks;
}

}  // namespace grainbank::audit
