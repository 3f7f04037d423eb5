#include "database/store/merge.hpp"

#include <map>
#include <optional>
#include <set>
#include <tuple>

#include "database/store/material_parameters.hpp"

namespace grainbank::db {
namespace {

struct Source {
  std::filesystem::path directory;
  std::optional<std::string> only_shard_file;  // relative to the directory, when a shard was named
};

Source resolve(const std::filesystem::path& source) {
  if (std::filesystem::is_directory(source)) return {source, std::nullopt};
  if (!std::filesystem::is_regular_file(source)) throw StoreError(source, "merge source does not exist");
  const std::filesystem::path shards = source.parent_path();
  const std::filesystem::path directory = shards.parent_path();
  if (shards.filename() != "shards" || !std::filesystem::exists(directory / "catalogue.sqlite"))
    throw StoreError(source, "a shard without its library's catalogue (expected LIB/shards/<name>.h5 next to "
                             "LIB/catalogue.sqlite): which of its data is committed is unknown");
  return {directory, (std::filesystem::path("shards") / source.filename()).string()};
}

// Identity of the original template, carried along in its preparation JSON through every merge.
nlohmann::json template_origin(Library& source, const TemplateRow& row) {
  const nlohmann::json preparation = nlohmann::json::parse(row.preparation);
  if (preparation.contains("merged_from")) return preparation["merged_from"];
  const auto meta = source.catalogue().all_meta();
  return {{"library", text_hash(meta.at("created_at") + " " + meta.at("created_by"))}, {"template", row.id}};
}

class ShardMerge {
 public:
  ShardMerge(Library& target, Library& source, const std::string& target_name, MergeReport& report)
      : target_(target), source_(source), writer_(target, target_name), report_(report) {
    for (const TemplateRow& row : target_.catalogue().templates()) {
      const nlohmann::json preparation = nlohmann::json::parse(row.preparation);
      if (preparation.contains("merged_from")) templates_[preparation["merged_from"].dump()] = row.id;
    }
    for (PathRow& path : target_.catalogue().paths()) {
      if (path.shard_id != writer_.shard_id()) continue;
      if (path.status == PathStatus::running)
        writer_.finish_path(path.id, PathStatus::failed, path.wall_time, "merge interrupted; merged again");
      else if (path.status == PathStatus::done)
        merged_.insert({path.template_id, path.spec, path.record_count});
    }
  }

  std::int64_t map_template(std::int64_t source_id) {
    const TemplateRow row = source_.catalogue().template_row(source_id);
    const nlohmann::json origin = template_origin(source_, row);
    if (const auto found = templates_.find(origin.dump()); found != templates_.end()) return found->second;
    nlohmann::json preparation = nlohmann::json::parse(row.preparation);
    preparation["merged_from"] = origin;
    const std::int64_t id = writer_.add_template(target_.material(), preparation, source_.template_cell(source_id));
    templates_[origin.dump()] = id;
    ++report_.templates;
    return id;
  }

  void merge_path(const PathRow& path) {
    const std::int64_t template_id = map_template(path.template_id);
    const nlohmann::json spec = nlohmann::json::parse(path.spec);
    if (const auto found = merged_.find({template_id, spec.dump(), path.record_count}); found != merged_.end()) {
      merged_.erase(found);
      ++report_.already_merged;
      return;
    }
    const std::int64_t id = target_.add_path(template_id, spec, target_.material());
    writer_.start_path(id);
    writer_.append_records(id, source_.records(path.id));
    for (const SnapshotRow& snapshot : source_.catalogue().snapshots_of(path.id)) {
      writer_.add_snapshot(id, snapshot.record_index, source_.snapshot_cell(path.id, snapshot.record_index));
      ++report_.snapshots;
    }
    writer_.finish_path(id, PathStatus::done, path.wall_time);
    ++report_.paths;
    report_.records += path.record_count;
  }

 private:
  Library& target_;
  Library& source_;
  ShardWriter writer_;
  MergeReport& report_;
  std::map<std::string, std::int64_t> templates_;  // origin JSON -> target template id
  std::multiset<std::tuple<std::int64_t, std::string, std::int64_t>> merged_;  // (template, spec, records)
};

}  // namespace

MergeReport merge_into(Library& target, const std::filesystem::path& source_path) {
  const Source where = resolve(source_path);
  if (std::filesystem::equivalent(where.directory, target.directory()))
    throw StoreError(source_path, "cannot merge a library into itself");
  Library source = Library::open(where.directory);
  target.require_material(source.material(), "merge source " + where.directory.string());

  const auto meta = source.catalogue().all_meta();
  const std::string source_id = text_hash(meta.at("created_at") + " " + meta.at("created_by"));
  const std::vector<PathRow> paths = source.catalogue().paths();
  const std::vector<TemplateRow> templates = source.catalogue().templates();
  MergeReport report;
  bool found = !where.only_shard_file;
  for (const ShardRow& shard : source.catalogue().shards()) {
    if (where.only_shard_file && shard.file != *where.only_shard_file) continue;
    found = true;
    ++report.shards;
    if (Shard::open(source.shard_path(shard), false).parameter_hash() != target.parameter_hash())
      throw MaterialMismatch(source.shard_path(shard), "shard parameter hash differs from the library's " +
                                                           target.parameter_hash());
    std::vector<const PathRow*> done;
    for (const PathRow& path : paths) {
      if (path.shard_id != shard.id) continue;
      if (path.status == PathStatus::done)
        done.push_back(&path);
      else
        ++report.skipped;
    }
    std::vector<std::int64_t> own_templates;
    for (const TemplateRow& row : templates)
      if (row.shard_id == shard.id) own_templates.push_back(row.id);
    if (done.empty() && own_templates.empty()) continue;
    ShardMerge merge(target, source, "merge-" + source_id + "-" + shard.name, report);
    for (std::int64_t id : own_templates) merge.map_template(id);
    for (const PathRow* path : done) merge.merge_path(*path);
  }
  if (!found) throw StoreError(source_path, "shard is not in its library's catalogue");
  if (!where.only_shard_file)
    for (const PathRow& path : paths) report.skipped += !path.shard_id;  // pending: in no shard yet
  return report;
}

}  // namespace grainbank::db
