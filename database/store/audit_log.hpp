// The catalogue's `audits` table (SCHEMA.md): one row per `celldb audit` run, its JSON summary in
// `details`, so a library carries the history of its audits next to its data.
#pragma once
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "database/store/catalogue.hpp"

namespace grainbank::db {

struct AuditRow {
  std::int64_t id = 0;
  std::string created_at;  // UTC
  std::string details;     // JSON
};

// Commits a row stamped now; returns its id.
std::int64_t record_audit(Catalogue& catalogue, const nlohmann::json& details);
// Every row, oldest first.
std::vector<AuditRow> audits(Catalogue& catalogue);

}  // namespace grainbank::db
