// RAII wrappers for a SQLite connection and prepared statements. Every failure throws StoreError
// naming the database file and quoting SQLite's message.
#pragma once
#include <sqlite3.h>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

#include "database/store/error.hpp"

namespace grainbank::db {

class SqliteStatement;

class SqliteConnection {
 public:
  // Opens an existing database (create = false) or creates it. WAL journal and a busy timeout so
  // several writer processes and readers share one catalogue without "database is locked" errors.
  SqliteConnection(const std::filesystem::path& file, bool create, int busy_timeout_ms = 60'000);
  ~SqliteConnection();
  SqliteConnection(SqliteConnection&& other) noexcept;
  SqliteConnection(const SqliteConnection&) = delete;
  SqliteConnection& operator=(const SqliteConnection&) = delete;
  SqliteConnection& operator=(SqliteConnection&&) = delete;

  void execute(const std::string& sql);
  SqliteStatement prepare(const std::string& sql);
  std::int64_t last_insert_id() const;
  const std::filesystem::path& file() const { return file_; }
  sqlite3* raw() const { return db_; }
  [[noreturn]] void fail(const std::string& context) const;

 private:
  std::filesystem::path file_;
  sqlite3* db_ = nullptr;
};

class SqliteStatement {
 public:
  SqliteStatement(SqliteConnection& db, const std::string& sql);
  ~SqliteStatement();
  SqliteStatement(SqliteStatement&& other) noexcept;
  SqliteStatement(const SqliteStatement&) = delete;
  SqliteStatement& operator=(const SqliteStatement&) = delete;
  SqliteStatement& operator=(SqliteStatement&&) = delete;

  // Parameters are 1-based, as in SQLite.
  SqliteStatement& bind(int index, std::int64_t value);
  SqliteStatement& bind(int index, double value);
  SqliteStatement& bind(int index, const std::string& value);
  SqliteStatement& bind_null(int index);
  SqliteStatement& bind(int index, const std::optional<std::int64_t>& value);

  // Advances to the next row; false when done. Resets automatically when the rows run out.
  bool step();
  // Runs a statement that returns no rows.
  void run();

  std::int64_t integer(int column) const;
  double real(int column) const;
  std::string text(int column) const;
  bool is_null(int column) const;

 private:
  SqliteConnection* db_;
  sqlite3_stmt* stmt_ = nullptr;
};

// BEGIN IMMEDIATE ... COMMIT; rolls back if not committed (exception on the way).
class SqliteTransaction {
 public:
  explicit SqliteTransaction(SqliteConnection& db);
  ~SqliteTransaction();
  SqliteTransaction(const SqliteTransaction&) = delete;
  SqliteTransaction& operator=(const SqliteTransaction&) = delete;
  void commit();

 private:
  SqliteConnection& db_;
  bool done_ = false;
};

}  // namespace grainbank::db
