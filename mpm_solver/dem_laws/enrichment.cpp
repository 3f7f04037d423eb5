#include "mpm_solver/dem_laws/enrichment.hpp"

#include <unistd.h>

#include "database/lookup/cell_record.hpp"
#include "database/store/path_queue.hpp"

namespace grainbank::mpm {

namespace {
std::string run_shard_name() {
  // UTC time alone could repeat for runs started in the same second; the pid separates them.
  std::string stamp = db::utc_now();
  for (char& c : stamp)
    if (c == ':') c = '-';
  return "run-" + stamp + "-" + std::to_string(getpid());
}
}  // namespace

Enrichment::Enrichment(LibraryLink& link, int snapshot_interval, long snapshot_budget, bool lead)
    : link_(link), snapshot_interval_(snapshot_interval), snapshot_budget_(snapshot_budget), shard_name_(run_shard_name()) {
  if (lead) lock_.emplace(link.locked([](db::Library& library) { return library.directory(); }));
  writer_ = link_.locked([&](db::Library& library) {
    // Holding the lock, this run knows every `running` path was left by a writer that died.
    if (lead) db::reset_running_paths(library.catalogue());
    return std::make_unique<db::ShardWriter>(library, shard_name_);
  });
}

RunPath Enrichment::start(const nlohmann::json& origin) {
  RunPath path;
  path.start = std::chrono::steady_clock::now();
  link_.locked([&](db::Library& library) {
    nlohmann::json spec = {{"origin", origin}, {"run", shard_name_}, {"sequence", started_++}};
    path.id = library.add_path(link_.template_id(), spec, library.material());
    writer_->start_path(path.id);
  });
  return path;
}

void Enrichment::add(RunPath& path, const dem::DemCell& cell, const dem::Mat3& L, const dem::Mat3& stress) {
  path.pending.push_back(lookup::cell_record(cell, L, stress, link_.scales()));
  const std::int64_t index = path.records++;
  if (snapshot_interval_ > 0 && (index + 1) % snapshot_interval_ == 0) {
    commit(path);
    link_.locked([&](db::Library&) {
      if (snapshot_budget_ != kUnlimited && snapshots_written_ >= snapshot_budget_) return;
      writer_->add_snapshot(path.id, index, db::StoredCell{cell.state(), cell.skin()});
      ++snapshots_written_;
    });
  } else if (path.pending.size() >= kCommitBatch) {
    commit(path);
  }
}

void Enrichment::commit(RunPath& path) {
  if (path.pending.empty()) return;
  link_.locked([&](db::Library&) { writer_->append_records(path.id, path.pending); });
  path.pending.clear();
}

void Enrichment::finish(RunPath& path) {
  commit(path);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - path.start).count();
  link_.locked([&](db::Library&) { writer_->finish_path(path.id, db::PathStatus::done, wall); });
  path.id = -1;
}

}  // namespace grainbank::mpm
