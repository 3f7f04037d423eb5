#include "database/store/audit_log.hpp"

namespace grainbank::db {

std::int64_t record_audit(Catalogue& catalogue, const nlohmann::json& details) {
  SqliteConnection& db = catalogue.connection();
  db.prepare("INSERT INTO audits (created_at, details) VALUES (?, ?)").bind(1, utc_now()).bind(2, details.dump()).run();
  return db.last_insert_id();
}

std::vector<AuditRow> audits(Catalogue& catalogue) {
  SqliteStatement s = catalogue.connection().prepare("SELECT id, created_at, details FROM audits ORDER BY id");
  std::vector<AuditRow> rows;
  while (s.step()) rows.push_back({s.integer(0), s.text(1), s.text(2)});
  return rows;
}

}  // namespace grainbank::db
