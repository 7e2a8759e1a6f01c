#include "map_server/store/sqlite_db.h"

#include <sqlite3.h>

namespace fleetmap {

SqliteStatement::SqliteStatement(sqlite3* db, const std::string& sql) : db_(db) {
  if (sqlite3_prepare_v2(db, sql.c_str(), static_cast<int>(sql.size()), &statement_, nullptr) !=
      SQLITE_OK) {
    sqlite3_finalize(statement_);
    statement_ = nullptr;
  }
}

SqliteStatement::~SqliteStatement() { sqlite3_finalize(statement_); }

std::string SqliteStatement::error() const { return sqlite3_errmsg(db_); }

SqliteStatement& SqliteStatement::Bind(int index, int64_t value) {
  if (statement_) sqlite3_bind_int64(statement_, index, value);
  return *this;
}

SqliteStatement& SqliteStatement::Bind(int index, double value) {
  if (statement_) sqlite3_bind_double(statement_, index, value);
  return *this;
}

SqliteStatement& SqliteStatement::Bind(int index, const std::string& text) {
  if (statement_) {
    sqlite3_bind_text(statement_, index, text.data(), static_cast<int>(text.size()),
                      SQLITE_TRANSIENT);
  }
  return *this;
}

SqliteStatement& SqliteStatement::BindBlob(int index, const std::string& bytes) {
  if (statement_) {
    sqlite3_bind_blob64(statement_, index, bytes.data(), bytes.size(), SQLITE_TRANSIENT);
  }
  return *this;
}

bool SqliteStatement::Step() {
  if (!statement_) return false;
  last_result_ = sqlite3_step(statement_);
  return last_result_ == SQLITE_ROW;
}

bool SqliteStatement::Run() {
  Step();
  return last_result_ == SQLITE_DONE;
}

int64_t SqliteStatement::Int(int column) const { return sqlite3_column_int64(statement_, column); }

double SqliteStatement::Double(int column) const {
  return sqlite3_column_double(statement_, column);
}

std::string SqliteStatement::Text(int column) const {
  const unsigned char* text = sqlite3_column_text(statement_, column);
  if (!text) return std::string();
  return std::string(reinterpret_cast<const char*>(text),
                     static_cast<size_t>(sqlite3_column_bytes(statement_, column)));
}

std::string SqliteStatement::Blob(int column) const {
  const void* data = sqlite3_column_blob(statement_, column);
  if (!data) return std::string();
  return std::string(static_cast<const char*>(data),
                     static_cast<size_t>(sqlite3_column_bytes(statement_, column)));
}

bool SqliteStatement::IsNull(int column) const {
  return sqlite3_column_type(statement_, column) == SQLITE_NULL;
}

bool SqliteExec(sqlite3* db, const std::string& sql, std::string* error) {
  char* message = nullptr;
  if (sqlite3_exec(db, sql.c_str(), nullptr, nullptr, &message) != SQLITE_OK) {
    *error = message ? message : sqlite3_errmsg(db);
    sqlite3_free(message);
    return false;
  }
  return true;
}

SqliteTransaction::SqliteTransaction(sqlite3* db) : db_(db) {
  began_ = SqliteExec(db_, "BEGIN IMMEDIATE", &error_);
}

SqliteTransaction::~SqliteTransaction() {
  if (began_ && !done_) {
    std::string ignored;
    SqliteExec(db_, "ROLLBACK", &ignored);
  }
}

bool SqliteTransaction::Commit(std::string* error) {
  if (!began_) {
    *error = error_;
    return false;
  }
  // A read statement left on a row keeps its read open and blocks COMMIT; our single-row reads
  // stop early, so end them all here.
  for (sqlite3_stmt* s = sqlite3_next_stmt(db_, nullptr); s; s = sqlite3_next_stmt(db_, s)) {
    sqlite3_reset(s);
  }
  if (!SqliteExec(db_, "COMMIT", error)) return false;
  done_ = true;
  return true;
}

}  // namespace fleetmap
