#include "database/celldb/audit_command.hpp"

#include <spawn.h>
#include <sys/wait.h>

#include <algorithm>
#include <fstream>
#include <iomanip>
#include <vector>

#include "database/audit/audit_report.hpp"
#include "database/store/audit_log.hpp"

extern char** environ;

namespace grainbank::celldb {
namespace {

// Debian's python3-matplotlib is installed for the system interpreter, which a virtualenv's python3
// earlier on PATH would hide.
std::string python() { return std::filesystem::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3"; }

std::filesystem::path default_out(const db::Library& library) {
  std::string stamp = db::utc_now();
  std::erase_if(stamp, [](char c) { return c == '-' || c == ':'; });
  return library.directory() / "audits" / stamp;
}

void write_file(const std::filesystem::path& file, const auto& write) {
  std::ofstream stream(file);
  if (!stream) throw db::StoreError(file, "cannot write the audit output");
  write(stream);
  stream.close();
  if (!stream) throw db::StoreError(file, "write failed (disk full?)");
}

void run_plots(const std::filesystem::path& directory) {
  const std::vector<std::string> args{python(), GRAINBANK_PLOT_AUDIT_SCRIPT, directory.string()};
  std::vector<char*> argv;
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  pid_t pid = 0;
  if (posix_spawnp(&pid, argv[0], nullptr, nullptr, argv.data(), environ) != 0)
    throw std::runtime_error("--plots: cannot start " + args[0] +
                             "; draw the figures later with: " + plot_command(directory));
  int status = 0;
  waitpid(pid, &status, 0);
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
    throw std::runtime_error("--plots: " + plot_command(directory) +
                             " failed (its message is above); the audit itself is complete");
}

void print_summary(const std::string& label, const audit::ErrorSummary& s, std::ostream& out) {
  out << std::left << std::setw(15) << label << s.count << " answers: relative error median " << s.median << ", p95 "
      << s.p95 << ", max " << s.max << "\n";
}

void print_report(const audit::AuditReport& r, std::ostream& out) {
  out << "audited " << r.sample.paths.size() << " of " << r.done_paths << " done paths (" << r.indexed_records
      << " records indexed); relative errors use a floor of " << r.stress_floor << " Pa\n";
  out << std::left << std::setw(15) << "determinism" << r.replays.size() - r.not_replayable
      << " records replayed from their snapshots: max " << r.determinism.max << " (median " << r.determinism.median
      << "), " << r.flagged << " flagged\n";
  if (r.not_replayable > 0)
    out << "  " << r.not_replayable << " sampled records belong to live cells of MPM runs, which cannot be replayed\n";
  for (const audit::ReplayResult& f : r.replays) {
    if (!f.flagged) continue;
    out << "  FLAGGED path " << f.check.record.path_id << " record " << f.check.record.record_index
        << " (replayed from "
        << (f.check.from_record > 0 ? "snapshot " + std::to_string(f.check.from_record) : std::string("the template"))
        << "): " << (f.check.error.empty() ? "relative error " + std::to_string(f.relative_error) : f.check.error)
        << "\n";
  }
  print_summary("in-index", r.in_index, out);
  print_summary("leave-one-out", r.leave_one_out, out);
  out << "error vs nearest distance (leave-one-out; distance in key units):\n"
      << "  distance from .. to        answers   median     p95\n";
  for (const audit::DistanceBin& b : r.bins)
    out << "  " << std::setw(11) << b.distance_min << " .. " << std::setw(11) << b.distance_max << " " << std::setw(9)
        << b.error.count << " " << std::setw(10) << b.error.median << " " << b.error.p95 << "\n";
  const audit::HitErrors& t = r.at_tolerance;
  out << "at tolerance " << t.tolerance << ": " << 100 * t.hit_share << " % of these answers hit, p95 error of hits "
      << t.hits.p95 << "\n";
  if (const auto& s = r.suggestion)
    out << "suggested tolerance " << s->tolerance << ": p95 error of its hits " << s->hits.p95 << " <= target "
        << r.options.target << ", " << 100 * s->hit_share << " % of these answers hit\n";
  else
    out << "no tolerance keeps the p95 error of hits within the target " << r.options.target
        << ": sample the key space more densely (more paths) or accept a larger error\n";
}

}  // namespace

std::string plot_command(const std::filesystem::path& out_directory) {
  return python() + " " + GRAINBANK_PLOT_AUDIT_SCRIPT + " " + out_directory.string();
}

int run_audit(const AuditCommandOptions& options, std::ostream& out) {
  db::Library library = db::Library::open(options.library);
  const audit::AuditReport report = audit::run_audit(library, options.audit);
  const std::filesystem::path directory = options.out.empty() ? default_out(library) : options.out;
  std::filesystem::create_directories(directory);

  nlohmann::json summary = audit::summary_json(report);
  summary["outputs"] = {{"directory", std::filesystem::absolute(directory).string()}};
  summary["audit_id"] = db::record_audit(library.catalogue(), summary);
  summary["library_directory"] = std::filesystem::absolute(options.library).string();
  write_file(directory / "audit.json", [&](std::ostream& s) { s << summary.dump(2) << "\n"; });
  write_file(directory / "audit_records.csv", [&](std::ostream& s) { audit::write_records_csv(report, s); });

  if (options.json)
    out << summary.dump(2) << "\n";
  else
    print_report(report, out);
  if (!options.json) {
    out << "wrote " << (directory / "audit.json").string() << " and " << (directory / "audit_records.csv").string()
        << "; audit " << summary["audit_id"] << " recorded in the catalogue (table audits)\n";
    if (!options.plots) out << "figures: " << plot_command(directory) << "\n";
  }
  if (options.plots) {
    out.flush();  // our report first, then the script's messages
    run_plots(directory);
  }
  return report.flagged == 0 ? 0 : 1;
}

}  // namespace grainbank::celldb
