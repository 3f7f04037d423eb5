#include "database/celldb/verify_command.hpp"

#include <nlohmann/json.hpp>

#include "database/store/verify.hpp"

namespace grainbank::celldb {
namespace {

const char* kind_name(db::Finding::Kind kind) {
  return kind == db::Finding::Kind::orphan ? "orphan" : "inconsistency";
}

}  // namespace

int run_verify(const VerifyOptions& options, std::ostream& out) {
  db::Library library = db::Library::open(options.library);
  const db::VerifyReport report = db::verify_library(library, options.repair);
  if (options.json) {
    nlohmann::json findings = nlohmann::json::array();
    for (const db::Finding& f : report.findings)
      findings.push_back({{"kind", kind_name(f.kind)}, {"file", f.file}, {"object", f.object},
                          {"message", f.message}, {"repaired", f.repaired}});
    out << nlohmann::json{{"checked", {{"shards", report.shards}, {"templates", report.templates},
                                       {"paths", report.paths}, {"records", report.records},
                                       {"snapshots", report.snapshots}}},
                          {"findings", findings},
                          {"clean", report.clean()}}
               .dump(2)
        << "\n";
    return report.clean() ? 0 : 1;
  }
  out << "checked " << report.shards << " shards, " << report.templates << " templates, " << report.paths
      << " paths, " << report.records << " records, " << report.snapshots << " snapshots\n";
  for (const db::Finding& f : report.findings) {
    out << kind_name(f.kind) << (f.repaired ? " (removed)" : "") << ": " << f.file;
    if (!f.object.empty()) out << ": " << f.object;
    out << ": " << f.message << "\n";
  }
  out << report.orphans() << " orphans" << (options.repair ? " (removed)" : "") << ", " << report.inconsistencies()
      << " inconsistencies\n";
  if (!options.repair && report.orphans() > 0 && report.inconsistencies() == 0)
    out << "orphans are uncommitted data left by interrupted writers; remove them with --repair\n";
  if (report.inconsistencies() > 0)
    out << "inconsistencies mean committed data is missing or damaged; --repair does not change them\n";
  return report.clean() ? 0 : 1;
}

}  // namespace grainbank::celldb
