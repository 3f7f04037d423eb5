// `mpm_solver audit RUN`: the audit of a finished (or interrupted) run against live DEM cells
// (audit/run_audit.hpp). Reads RUN/audit_trail.h5 (written when the scene has "audit": {"points": N})
// and the scene it names; the live reference is that scene with every DEM-backed material turned
// `live` (RUN/audit/scene_live.json). Writes RUN/audit/run_audit.json (the summary) and
// RUN/audit/run_audit_steps.csv (every compared point-step), and a row of the catalogue's audits
// table of every library the scene's materials use (its summary, "kind": "mpm_run"). With a floor
// cell, the summary and the steps also hold the audit's noise floor (audit/run_audit.hpp).
#pragma once
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <ostream>

namespace grainbank::mpm::app {

struct AuditCommandOptions {
  std::filesystem::path run;  // the --out folder of the run
  bool json = false;          // print the summary as JSON instead of the text report
  // A cell.json of the reference's recipe with another packing seed: the histories are re-run by it
  // too and its errors against the reference are the audit's noise floor ("noise_floor" in the
  // summary, RUN/audit/scene_floor.json). Refused unless its material and sphere count are the
  // reference cell's.
  std::optional<std::filesystem::path> floor_cell;
};

// Throws common::InputError (missing trail, a run resumed from a restart), db::StoreError (unreadable
// trail or library) or std::runtime_error (a reference cell failed), each naming the file or point.
nlohmann::json run_audit_command(const AuditCommandOptions& options, std::ostream& out);

}  // namespace grainbank::mpm::app
