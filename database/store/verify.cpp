#include "database/store/verify.hpp"

#include <algorithm>
#include <map>
#include <set>

#include "database/store/hdf5_handle.hpp"

namespace grainbank::db {
namespace {

using Kind = Finding::Kind;

struct ShardChecker {
  Library& library;
  bool repair;
  VerifyReport& report;
  const ShardRow& row;
  Shard& shard;

  void add(Kind kind, const std::string& object, const std::string& message, bool repaired = false) {
    report.findings.push_back(Finding{kind, shard.file().string(), object, message, repaired});
  }

  // Runs `check`; a StoreError (missing or unreadable data) becomes an inconsistency.
  template <class Check>
  bool readable(const std::string& object, Check check) {
    try {
      check();
      return true;
    } catch (const std::exception& e) {
      add(Kind::inconsistency, object, e.what());
      return false;
    }
  }

  // Orphans HDF5 cannot remove in place are removed together, after the check, by rewriting the
  // shard without them (Shard::rewrite_without); their findings are marked repaired then.
  Shard::Omitted& rewrite;
  std::vector<std::size_t>& rewrite_findings;
  void orphan_group(const std::string& group, const std::string& message) {
    rewrite.groups.insert(group);
    rewrite_findings.push_back(report.findings.size());
    add(Kind::orphan, group, message);
  }

  // Uncommitted rows are cut in place; a table whose chunk index a killed writer left unreadable
  // cannot be resized, so it is cut in the rewrite.
  void uncommitted_rows(std::int64_t path_id, std::uint64_t rows, std::uint64_t committed) {
    const std::string table = Shard::path_group(path_id) + "/records";
    const std::string message = std::to_string(rows - committed) + " uncommitted rows after the " +
                                std::to_string(committed) + " committed records";
    if (!repair) return add(Kind::orphan, table, message);
    try {
      shard.truncate_records(path_id, committed);
      add(Kind::orphan, table, message, true);
    } catch (const StoreError&) {
      rewrite.rows_kept[path_id] = committed;
      rewrite_findings.push_back(report.findings.size());
      add(Kind::orphan, table, message);
    }
  }

  void check(const std::vector<TemplateRow>& templates, const std::vector<PathRow>& paths,
             const std::vector<SnapshotRow>& snapshots) {
    if (shard.parameter_hash() != library.parameter_hash())
      add(Kind::inconsistency, "/", "parameter hash " + shard.parameter_hash() + " differs from the library's " +
                                        library.parameter_hash());

    std::set<std::string> committed_groups;
    for (const TemplateRow& t : templates) {
      if (t.shard_id != row.id) continue;
      committed_groups.insert(t.hdf5_group);
      ++report.templates;
      readable(t.hdf5_group, [&] { shard.read_cell(t.hdf5_group); });
    }
    for (const std::string& token : shard.template_tokens())
      if (!committed_groups.count(Shard::template_group(token)))
        orphan_group(Shard::template_group(token), "template group with no committed template row");

    std::map<std::int64_t, const PathRow*> own_paths;
    for (const PathRow& p : paths)
      if (p.shard_id == row.id) own_paths[p.id] = &p;
    std::map<std::int64_t, std::set<std::int64_t>> own_snapshots;
    for (const SnapshotRow& s : snapshots) {
      if (s.shard_id != row.id) continue;
      own_snapshots[s.path_id].insert(s.record_index);
      ++report.snapshots;
      readable(s.hdf5_group, [&] { shard.read_cell(s.hdf5_group); });
    }

    for (const auto& [id, path] : own_paths) {
      ++report.paths;
      const std::string table = Shard::path_group(id) + "/records";
      std::uint64_t rows = 0;
      if (!readable(table, [&] { rows = shard.record_rows(id); })) continue;
      const auto committed = static_cast<std::uint64_t>(path->record_count);
      if (rows < committed) {
        add(Kind::inconsistency, table,
            std::to_string(rows) + " rows but " + std::to_string(committed) + " committed records (data lost)");
        continue;
      }
      if (readable(table, [&] { shard.read_records(id, 0, committed); })) report.records += path->record_count;
      if (rows > committed) uncommitted_rows(id, rows, committed);
    }

    for (const std::int64_t id : shard.path_ids()) {
      if (!own_paths.count(id)) {
        orphan_group(Shard::path_group(id), "path group with no path committed to this shard");
        continue;
      }
      for (const std::int64_t index : shard.snapshot_indices(id))
        if (!own_snapshots[id].count(index))
          orphan_group(Shard::snapshot_group(id, index), "snapshot group with no committed snapshot row");
    }
  }
};

void check_catalogue(Catalogue& catalogue, VerifyReport& report) {
  auto s = catalogue.connection().prepare("PRAGMA quick_check");
  while (s.step())
    if (s.text(0) != "ok")
      report.findings.push_back(Finding{Kind::inconsistency, catalogue.file().string(), "quick_check", s.text(0), false});
}

// *.h5 files under shards/ that no shard row names: created, then a crash before the row committed;
// or a repair's copy of a shard (Shard::rewrite_without), then a crash before the rename.
void check_stray_files(Library& library, const std::vector<ShardRow>& shards, bool repair, VerifyReport& report) {
  std::set<std::filesystem::path> known;
  for (const ShardRow& row : shards) known.insert(library.shard_path(row).lexically_normal());
  const std::filesystem::path dir = library.directory() / "shards";
  if (!std::filesystem::is_directory(dir)) {
    report.findings.push_back(Finding{Kind::inconsistency, dir.string(), "", "shards directory is missing", false});
    return;
  }
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    if (entry.path().extension() != ".h5" || known.count(entry.path().lexically_normal())) continue;
    if (repair) std::filesystem::remove(entry.path());
    report.findings.push_back(
        Finding{Kind::orphan, entry.path().string(), "", "shard file with no row in the shards table", repair});
  }
}

// A writer killed in its flush, or whose disk filled up, leaves its shard shorter than the space it
// allocated: what is missing was never committed, so it is an orphan, and repair extends the file.
Finding cut_short_finding(const std::filesystem::path& shard) {
  return Finding{Kind::orphan, shard.string(), "",
                 "file shorter than the space its writer allocated (killed in a flush, or a write failed: disk "
                 "full?); the missing tail held uncommitted data only",
                 false};
}

// Repair runs with every writer stopped, so the state a killed or disk-full writer left in a shard
// (its "open for write" flag, a file shorter than its allocated space) can be cleared first. A shard
// that stays unopenable is reported by Shard::open below with HDF5's own reason.
void make_openable(const std::filesystem::path& shard) {
  if (!std::filesystem::exists(shard)) return;
  try {
    h5::clear_stale_writer_state(shard);
  } catch (const StoreError&) {
  }
}

// Checks one shard; with `repair`, truncates uncommitted rows in place and rewrites the shard without
// the orphans that cannot be removed in place, unless it holds damaged committed data: such a shard
// is left as it is.
void check_shard(Library& library, bool repair, VerifyReport& report, const ShardRow& row,
                 const std::vector<TemplateRow>& templates, const std::vector<PathRow>& paths,
                 const std::vector<SnapshotRow>& snapshots) {
  const std::filesystem::path file = library.shard_path(row);
  if (repair) make_openable(file);
  const std::size_t first_finding = report.findings.size();
  Shard::Omitted rewrite;
  std::vector<std::size_t> rewrite_findings;
  {
    Shard shard = Shard::open(file, repair);
    ShardChecker{library, repair, report, row, shard, rewrite, rewrite_findings}.check(templates, paths, snapshots);
    if (repair) shard.flush();
  }
  if (!repair && h5::cut_short(file)) report.findings.push_back(cut_short_finding(file));
  if (!repair || rewrite_findings.empty()) return;
  const bool damaged = std::any_of(report.findings.begin() + static_cast<std::ptrdiff_t>(first_finding),
                                   report.findings.end(), [](const Finding& f) { return f.kind == Kind::inconsistency; });
  if (damaged) {
    for (const std::size_t k : rewrite_findings)
      report.findings[k].message += " (left: repair does not rewrite a shard with damaged committed data)";
    return;
  }
  Shard::rewrite_without(file, rewrite);
  for (const std::size_t k : rewrite_findings) report.findings[k].repaired = true;
}

}  // namespace

std::size_t VerifyReport::orphans() const {
  return std::count_if(findings.begin(), findings.end(), [](const Finding& f) { return f.kind == Kind::orphan; });
}

std::size_t VerifyReport::inconsistencies() const { return findings.size() - orphans(); }

bool VerifyReport::clean() const {
  return std::all_of(findings.begin(), findings.end(),
                     [](const Finding& f) { return f.kind == Kind::orphan && f.repaired; });
}

VerifyReport verify_library(Library& library, bool repair) {
  VerifyReport report;
  Catalogue& catalogue = library.catalogue();
  check_catalogue(catalogue, report);
  const std::vector<ShardRow> shards = catalogue.shards();
  const std::vector<TemplateRow> templates = catalogue.templates();
  const std::vector<PathRow> paths = catalogue.paths();
  const std::vector<SnapshotRow> snapshots = catalogue.snapshots();
  for (const ShardRow& row : shards) {
    ++report.shards;
    try {
      check_shard(library, repair, report, row, templates, paths, snapshots);
    } catch (const StoreError& e) {
      if (!repair && h5::cut_short(library.shard_path(row)))
        report.findings.push_back(cut_short_finding(library.shard_path(row)));
      else
        report.findings.push_back(Finding{Kind::inconsistency, library.shard_path(row).string(), "", e.what(), false});
    }
  }
  for (const PathRow& p : paths)
    if (p.status != PathStatus::pending && !p.shard_id)
      report.findings.push_back(Finding{Kind::inconsistency, catalogue.file().string(),
                                        "paths/" + std::to_string(p.id), "path is " + to_string(p.status) +
                                        " but has no shard", false});
  check_stray_files(library, shards, repair, report);
  return report;
}

}  // namespace grainbank::db
