// `celldb audit LIB`: how far a library can be trusted (audit/audit.hpp): determinism replays of
// sampled records, leave-one-path-out lookup errors, error against nearest distance and a suggested
// tolerance. Writes OUT/audit.json (the summary) and OUT/audit_records.csv (every compared record),
// commits the summary as a row of the catalogue's audits table, and with --plots runs
// workflows/audit/plot_audit.py OUT (audit_histogram.png, audit_error_vs_distance.png).
// Exit code 0 when every replayed record reproduced its stored stress, 1 when some did not.
#pragma once
#include <filesystem>
#include <ostream>

#include "database/audit/audit.hpp"

namespace grainbank::celldb {

struct AuditCommandOptions {
  std::filesystem::path library;
  audit::AuditOptions audit;
  std::filesystem::path out;  // default LIB/audits/<UTC time>
  bool json = false;          // print the summary JSON instead of the text report
  bool plots = false;
};

int run_audit(const AuditCommandOptions& options, std::ostream& out);

// The command that draws the figures of an audit directory (python3 with matplotlib).
std::string plot_command(const std::filesystem::path& out_directory);

}  // namespace grainbank::celldb
