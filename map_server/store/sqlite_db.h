#ifndef FLEETMAP_MAP_SERVER_STORE_SQLITE_DB_H_
#define FLEETMAP_MAP_SERVER_STORE_SQLITE_DB_H_

#include <cstdint>
#include <string>

struct sqlite3;
struct sqlite3_stmt;

namespace fleetmap {

// A thin RAII layer over the SQLite C API: one prepared statement. Errors are reported through
// ok()/error(), never thrown.
class SqliteStatement {
 public:
  SqliteStatement(sqlite3* db, const std::string& sql);
  ~SqliteStatement();
  SqliteStatement(const SqliteStatement&) = delete;
  SqliteStatement& operator=(const SqliteStatement&) = delete;

  bool ok() const { return statement_ != nullptr; }
  std::string error() const;

  // Parameters are 1-based, columns 0-based (SQLite's convention).
  SqliteStatement& Bind(int index, int64_t value);
  SqliteStatement& Bind(int index, double value);
  SqliteStatement& Bind(int index, const std::string& text);
  SqliteStatement& BindBlob(int index, const std::string& bytes);

  // True while a row is available; check Done() afterwards to tell the end from an error.
  bool Step();
  bool Done() const { return last_result_ == kDone; }
  // Runs a statement that returns no rows; true on success.
  bool Run();

  int64_t Int(int column) const;
  double Double(int column) const;
  std::string Text(int column) const;
  std::string Blob(int column) const;
  bool IsNull(int column) const;

 private:
  static constexpr int kDone = 101;  // SQLITE_DONE
  sqlite3* db_;
  sqlite3_stmt* statement_ = nullptr;
  int last_result_ = 0;
};

// Runs one or more statements without results; fills `error` on failure.
bool SqliteExec(sqlite3* db, const std::string& sql, std::string* error);

// BEGIN IMMEDIATE on construction, ROLLBACK on destruction unless Commit() succeeded.
class SqliteTransaction {
 public:
  explicit SqliteTransaction(sqlite3* db);
  ~SqliteTransaction();
  bool ok() const { return began_; }
  bool Commit(std::string* error);
  const std::string& error() const { return error_; }

 private:
  sqlite3* db_;
  bool began_ = false;
  bool done_ = false;
  std::string error_;
};

}  // namespace fleetmap

#endif  // FLEETMAP_MAP_SERVER_STORE_SQLITE_DB_H_
